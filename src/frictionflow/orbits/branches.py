"""What continuation returns: branches of points, bifurcations, and their JSON form."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .. import quantities as Q
from .._display import Row, Summarized, num
from .._figures import draw
from .._json import jsonable
from .equilibria import Equilibrium
from .measures import OrbitMeasures, equilibrium_measures
from .shooting import PeriodicOrbit

#: the averages every branch point reports (besides value, kind, stability), in the paper's
#: order; not P_f, which equals P_dv on a periodic orbit
POINT_POWER = tuple(n for n in Q.PAPER_AVERAGES if n != "P_f")


@dataclass(frozen=True)
class BranchPoint:
    """One solution on a branch: an equilibrium or a periodic orbit at parameter ``value``.

    Attributes
    ----------
    value:
        The parameter's value.
    kind:
        ``equilibrium`` or ``periodic``.
    stability:
        ``stable``, ``unstable`` or ``neutral``.
    x:
        X* for an equilibrium; the orbit's X on the section X' = 0 for a
        periodic orbit.
    measures:
        Averages over one period (or at the equilibrium), TR_B and the
        extremes of X and X'.
    period:
        The orbit's period (None for an equilibrium).
    multiplier:
        The nontrivial Floquet multiplier of an orbit.
    eigenvalues:
        The eigenvalues of an equilibrium.
    stick_fraction:
        The fraction of the period spent sticking.
    modes:
        The orbit's phase sequence (slip, stick, band modes) over one period.
    orbit:
        The :class:`PeriodicOrbit` itself, for an orbit.
    """

    value: float
    kind: str
    stability: str
    x: float
    measures: OrbitMeasures
    period: float | None = None
    multiplier: complex | None = None
    eigenvalues: tuple[complex, ...] | None = None
    stick_fraction: float = 0.0
    modes: tuple[str, ...] = ()
    orbit: PeriodicOrbit | None = field(default=None, repr=False, compare=False)

    @property
    def amplitude(self) -> float:
        """(X_max - X_min) / 2; 0 at an equilibrium."""
        return self.measures.amplitude

    @property
    def stable(self) -> bool:
        return self.stability == "stable"

    @classmethod
    def from_orbit(cls, value: float, orbit: PeriodicOrbit) -> BranchPoint:
        return cls(
            value=value,
            kind="periodic",
            stability=orbit.stability,
            x=orbit.state[0],
            measures=orbit.measures,
            period=orbit.period,
            multiplier=orbit.multiplier,
            stick_fraction=orbit.stick_fraction,
            modes=orbit.segment.modes,
            orbit=orbit,
        )

    @classmethod
    def from_equilibrium(cls, eq: Equilibrium, vb: float, fd: float) -> BranchPoint:
        return cls(
            value=eq.value,
            kind="equilibrium",
            stability=eq.stability,
            x=eq.x,
            measures=equilibrium_measures(eq.x, vb, fd),
            eigenvalues=tuple(complex(e) for e in eq.eigenvalues),
        )

    def to_dict(self) -> dict[str, Any]:
        av = self.measures.averages()
        d: dict[str, Any] = {
            "value": self.value,
            "kind": self.kind,
            "stability": self.stability,
            "stable": self.stable,
            "period": self.period,
            "amplitude": self.amplitude,
            "X": self.x,
            "X_max": self.measures.extremes["X_max"],
            "X_min": self.measures.extremes["X_min"],
            **{k: av[k] for k in POINT_POWER},
            "TR_B": self.measures.TR_B,
            "energy_residual": self.measures.power.energy_residual,
            "stick_fraction": self.stick_fraction,
        }
        if self.kind == "periodic":
            d["multiplier"] = self.multiplier
            d["modes"] = list(self.modes)
        else:
            d["eigenvalues"] = list(self.eigenvalues or ())
        return d


@dataclass
class Branch:
    """A connected set of solutions, in the order continuation found them.

    Attributes
    ----------
    kind:
        ``equilibrium`` or ``periodic``.
    points:
        Its :class:`BranchPoint` s.
    seed:
        How it began (the sliding equilibrium, a Hopf point, an attractor a
        simulation reached at an end of the interval).
    end:
        How it ended (the interval's end, a grazing, a period blow-up, ...).
    """

    kind: str
    points: list[BranchPoint]
    seed: str
    end: str = ""

    def values(self) -> list[float]:
        return [p.value for p in self.points]


@dataclass(frozen=True)
class Bifurcation:
    """A special point: ``type`` is hopf, fold, grazing, switching, period_blowup or branch_end.

    Attributes
    ----------
    type:
        The kind of point (above).
    value:
        The parameter's value there.
    branch:
        The index of the branch it lies on in
        :attr:`ContinuationResult.branches`, if any.
    detail:
        What else is known about it (a Hopf point's criticality, the
        multiplier at a fold, ...); the JSON output carries these keys.
    """

    type: str
    value: float
    branch: int | None = None
    detail: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.type, "value": self.value, "branch": self.branch, **self.detail}


@dataclass(repr=False)
class ContinuationResult(Summarized):
    """Branches of equilibria and periodic orbits in one parameter, with the bifurcations found.

    Shows itself as a short summary; :meth:`plot` draws the bifurcation diagram.

    Attributes
    ----------
    param:
        The continued parameter.
    start, stop:
        The interval it was continued over.
    params:
        Every other parameter's value (the oscillator's and the law's).
    branches:
        The :class:`Branch` es found.
    bifurcations:
        The :class:`Bifurcation` s found on them.
    sweep:
        The brute-force simulations along the interval (``sweep`` of the
        settings; one dict per value), or None.
    """


    param: str
    start: float
    stop: float
    params: dict[str, Any]
    branches: list[Branch]
    bifurcations: list[Bifurcation]
    sweep: list[dict[str, Any]] | None = None

    def _summary(self) -> tuple[str, list[Row]]:
        fixed = ", ".join(f"{k}={num(v, 4)}" for k, v in self.params.items()
                          if k != self.param and isinstance(v, (int, float)) and not isinstance(v, bool))
        kinds = [f"{b.kind} ({b.seed}, {len(b.points)} points{', ' + b.end if b.end else ''})" for b in self.branches]
        bifs = [f"{b.type} at {num(b.value)}" for b in self.bifurcations]
        rows = [
            ("parameter", f"{self.param} from {num(self.start)} to {num(self.stop)}"),
            ("fixed", f"{self.params.get('friction', '?')}: {fixed}"),
            ("branches", _first(kinds, 3) or "none"),
            ("bifurcations", _first(bifs, 4) or "none"),
        ]
        if self.sweep is not None:
            rows.append(("simulations", f"{len(self.sweep)} overlaid"))
        return "ContinuationResult", rows

    def plot(self, path: Any = None, **options: Any):
        """Bifurcation diagram, power and TR_B along the branches (:func:`~frictionflow.orbits.plotting.plot_bifurcation`).

        ``options``: the figure function's keywords (``dpi``: dots per inch, ``name``).
        """
        return draw(self, path, **options)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``branches`` is a list of lists of points; ``branch_info`` says how each began and ended."""
        d: dict[str, Any] = {
            "param": self.param,
            "from": self.start,
            "to": self.stop,
            "params": self.params,
            "branches": [[p.to_dict() for p in b.points] for b in self.branches],
            "branch_info": [{"kind": b.kind, "seed": b.seed, "end": b.end, "points": len(b.points)} for b in self.branches],
            "bifurcations": [b.to_dict() for b in self.bifurcations],
        }
        if self.sweep is not None:
            d["sweep"] = self.sweep
        return jsonable(d)


def _first(items: list[str], n: int) -> str:
    """The first ``n`` items joined, and how many more (a summary stays a few lines long)."""
    more = f"; and {len(items) - n} more" if len(items) > n else ""
    return "; ".join(items[:n]) + more
