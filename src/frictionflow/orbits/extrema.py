"""What monitors along branches report: the monitor names and a located :class:`Extremum`.

Below both :mod:`.monitors` (free branches) and :mod:`.forced_chart` (forced
ones), which hands the forced branches' extrema to the latter.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

#: the per-orbit quantities a branch can be monitored by
MONITORS = ("P_fin", "P_dv", "P_df", "R_c", "R_f", "P_belt", "P_heat", "TR_B", "amplitude", "stick_fraction", "period")
#: those of a forced branch (its period is fixed by the forcing; the input power P_ex joins)
FORCED_MONITORS = ("P_dv", "P_df", "P_fin", "R_c", "R_f", "P_belt", "P_heat", "P_f", "P_ex", "TR_B", "amplitude",
                   "stick_fraction")


@dataclass(frozen=True)
class Extremum:
    """A located extremum of ``monitor`` along a branch: at ``value`` of the parameter, orbit through (x, 0).

    Attributes
    ----------
    monitor:
        The monitored quantity (``P_fin``, ``R_c``, ``TR_B``, ``amplitude``, ...).
    kind:
        ``max`` or ``min``.
    param:
        The branch's parameter.
    value:
        Its value at the extremum.
    monitor_value:
        The monitor's value there.
    x:
        The orbit's X on its section there (forced: at tau = 0).
    branch:
        The index of the branch it lies on, if known.
    method:
        How it was refined: ``slope root`` (a root of the exact slope) or
        ``brent`` (the monitor itself).
    extra:
        What else is known there (a second parameter's value, ...).
    """


    monitor: str
    kind: str  # "max" or "min"
    param: str
    value: float
    monitor_value: float
    x: float
    branch: int | None = None
    method: str = ""  # "slope root" (exact slope) or "brent" (the monitor itself)
    extra: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {"monitor": self.monitor, "kind": self.kind, "param": self.param, "value": self.value,
                "monitor_value": self.monitor_value, "X": self.x, "branch": self.branch, "method": self.method, **self.extra}
