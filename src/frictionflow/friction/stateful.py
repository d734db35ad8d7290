"""Laws with internal state: F depends on V_r and states z whose rates the law gives.

A stateful law (LuGre, ...) declares its states (``internal_names``), evaluates
its force, the states' rates and its stored energy on arrays
(:meth:`StatefulLaw.force`, :meth:`StatefulLaw.rate`,
:meth:`StatefulLaw.stored_energy`), and hands the stiff engine
(:mod:`frictionflow.core.stiff`) its record: the kernels' force record
followed by its own parameters, with its code there.  The engine evaluates the
same formulas compiled, with their exact derivatives.

Its capabilities: ``stick_rule = "state"`` (no rule at V_r = 0: the states
hold the mass), no slip curve the static kernels evaluate, no tangent kernel.
The solvers that integrate internal states say so (``Solver.supports``).
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np

from ..core import layout, stiff_points
from .base import FrictionLaw

#: below this fraction of the law's velocity scale (``speed_scale``) the mass counts as sticking (the mode
#: samples record): the states then take up the relative motion, a slip of that size is creep
STICK_SPEED_FRACTION = 1e-2
#: internal states rest when their rates are below this fraction of the sliding speed (Newton's rounding)
REST_RATE = 1e-12


class StatefulLaw(FrictionLaw):
    """Base class of laws with internal state (see the module's docstring).

    Class attributes a stateful law sets
    ------------------------------------
    internal_names:
        Its states' names (the rows of ``Trajectory.internal``).
    record_names:
        Its parameters in the order of its record's slots after the kernels' force record.
    stiff_at_rest:
        Whether its force can move by more than its tolerance across the rounding of V_r at V_r = 0
        (rate-and-state): ``frictionflow.solvers.stiff.check_resolved`` then checks each run.
    """

    stick_rule = "state"
    piecewise_constant = False
    compiled_slip = False
    internal_names: ClassVar[tuple[str, ...]] = ()
    record_names: ClassVar[tuple[str, ...]] = ()
    #: its force moves by more than its tolerance across the rounding of V_r = V_b - X' near V_r = 0 (a
    #: stiffness at rest beyond the belt frame's reach): the stiff solver then checks that a run stays resolved
    stiff_at_rest: ClassVar[bool] = False

    @property
    def n_internal(self) -> int:
        """Number of internal states."""
        return len(self.internal_names)

    def kernel_params(self) -> np.ndarray:
        """The stiff engine's record: the kernels' force record (law code, F_d, F_s) and the law's parameters."""
        p = np.zeros(layout.N_PARAMS + len(self.record_names))
        p[layout.LAW], p[layout.FD], p[layout.FS] = self.code, self.fd, self.fs
        p[layout.N_PARAMS:] = [getattr(self, name) for name in self.record_names]
        return p

    def kernel_force(self) -> None:
        return None  # no static slip force: only the stiff engine runs it

    def initial_state(self, vb: float | None = None) -> np.ndarray:
        """The internal states a run starts from (relaxed), given the belt speed ``vb`` (a law whose rest
        state depends on it reads it)."""
        return np.zeros(self.n_internal)

    def internal_scale(self) -> np.ndarray:
        """Each state's size when it carries a force of order F_s: the absolute scale of its error control."""
        raise NotImplementedError

    def steady_internal(self, vr: float) -> np.ndarray:
        """The internal states sliding steadily at ``vr`` (every rate zero), from the law's compiled rates
        and their exact derivatives: Newton from the states that carry F_s in the direction of ``vr``, else
        from the relaxed ones (laws whose states stay positive); NaN where neither rests."""
        q = self.kernel_params()
        for start in (np.sign(float(vr)) * np.asarray(self.internal_scale(), dtype=float), self.initial_state()):
            z = stiff_points.steady_internal(q, float(vr), np.array(start, dtype=float))
            rates = np.asarray(self.rate(float(vr), z), dtype=float)
            if np.all(np.abs(rates) <= REST_RATE * max(abs(float(vr)), 1e-300)):
                return z
        return np.full(self.n_internal, np.nan)

    def speed_scale(self) -> float:
        """The velocity on which the law's force changes (its Stribeck velocity)."""
        raise NotImplementedError

    def rate(self, vr: Any, z: np.ndarray) -> np.ndarray:
        """dz/dtau (m, ...) at relative velocity ``vr`` and states ``z`` (m, ...)."""
        raise NotImplementedError

    def force(self, vr: Any, z: np.ndarray) -> np.ndarray:
        """Friction force on the mass at relative velocity ``vr`` and states ``z`` (m, ...)."""
        raise NotImplementedError

    def stored_energy(self, z: np.ndarray) -> np.ndarray:
        """Energy held in the contact at states ``z`` (m, ...)."""
        raise NotImplementedError

    def stick_speed(self) -> float:
        """|V_r| below which the contact counts as stuck: ``STICK_SPEED_FRACTION`` of the speed scale."""
        return STICK_SPEED_FRACTION * self.speed_scale()

    def mode_of(self, vr: Any) -> np.ndarray:
        """Friction mode per sample: stick (0) while |V_r| is below :meth:`stick_speed`."""
        vr = np.asarray(vr, dtype=float)
        slip = np.abs(vr) > self.stick_speed()
        return np.where(slip, np.sign(vr), 0.0).astype(np.int8)

    def stick_force_value(self, x: Any, v: Any, zeta: float) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return x + 2.0 * zeta * np.asarray(v, dtype=float)

    def sliding_equilibrium(self, vb: float) -> float:
        return float(self.slip_force(vb))
