"""The stiff solver: Rodas4 on the whole state (X, X', internal states), for laws with internal state."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from .. import _validate as check
from .._progress import progress_bar
from ..core import stiff as kernel
from ..core import stiff_points
from ..friction.base import FrictionLaw
from ..parameters import MODEL_MAX, Param
from ..params import BeltOscillator
from ..trajectory import Trajectory
from .adaptive import MAX_STEPS, StepLimitError
from .base import DEFAULT_MAX_MEMORY, Solver, check_memory, flag, kernel_params

# below 1e-13 the error estimate is rounding; above 1e-2 breakaway is not resolved
STIFF_RTOL = Param("stiff_rtol", "", "stiff solver's relative tolerance (whole state)", "solver", 1e-8,
                   lower=1e-13, upper=1e-2)
MAX_STEP = Param("max_step", "", "stiff solver's largest step", "solver", 0.5, lower=1e-9, upper=MODEL_MAX, report=False)


class Stiff(Solver):
    """Rodas4 (L-stable Rosenbrock, order 4(3)) with the law's exact Jacobian, for laws with internal state.

    The error is controlled on X, X' and every internal state (each state's
    absolute tolerance is ``atol`` times its scale, the size at which it
    carries a force of F_s), the work integrals (and the belt's work) are
    integrated with the state, and ``traj(t)`` interpolates the steps
    (quintic Hermite in X, cubic in the internal states).  No switch is
    located: the law's states carry stick and slip (see
    ``frictionflow.core.stiff``).  A step ends on every zero of X' (X'
    exactly 0 there: the downward ones are the section the other solvers
    sample, so an unforced steady-state window is whole periods) and of the
    friction power X' F (the kink of its split into input and output).  The
    extremes of X' and of the transmitted force (TR_B) and the stick share
    are found between the steps by the analysis (``refine_between_samples``:
    on the cubic Hermite interpolant of the samples and their rates).  A belt
    whose speed varies, V_b(tau), enters every stage; a forced run, or one
    on a varying belt, has a sample on every k 2 pi / Omega (with both,
    Omega_b must equal Omega).

    Parameters
    ----------
    rtol, atol:
        Relative tolerance and absolute tolerance (on X and X'; scaled for the internal states).
    max_steps:
        Step cap (attempted steps); when hit the run stops with :class:`StepLimitError`.
    max_step:
        Largest step.
    """

    name = "stiff"
    parameters = (STIFF_RTOL, MAX_STEPS, MAX_STEP)
    keywords = {"stiff_rtol": "rtol"}
    interpolant = "state_hermite"
    refine_between_samples = True  # its steps end on the zeros of X' and P_f, not of X'' or F_T'
    supports_belt_motion = True
    steady_rtol = 1e-6
    default_chunk = 64
    step_cost = "adaptive_step"

    def __init__(self, rtol: float = 1e-8, atol: float = 1e-10, max_steps: int = 10_000_000, max_step: float = 0.5) -> None:
        self.rtol = STIFF_RTOL.check(rtol)
        self.atol = check.positive("atol", check.number("atol", atol, "finite and > 0"))
        self.max_steps = MAX_STEPS.check(max_steps)
        self.max_step = MAX_STEP.check(max_step)
        self._seal()

    def describe(self) -> dict[str, Any]:
        return {"name": self.name, "rtol": self.rtol, "atol": self.atol, "max_steps": self.max_steps,
                "max_step": self.max_step}

    def supports(self, friction: FrictionLaw) -> bool:
        return len(friction.internal_names) > 0  # the static laws have their own, exact or switch-locating, solvers

    @classmethod
    def section_noise(cls, settings: Mapping[str, Any]) -> float:
        return 10.0 * float(settings.get("rtol", 1e-8))

    def sample_estimate(self, t_end: float, model: BeltOscillator | None = None) -> int:
        """Room for the samples of a run to ``t_end`` (a first guess; the run grows it)."""
        return int(100 * t_end) + 256

    def _solve(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, t_end: float,
               progress: bool, max_memory: float) -> Trajectory:
        y0 = np.concatenate([[float(x0), float(v0)], friction.initial_state(model.vb)])
        return self.solve_state(model, friction, y0, t_end, progress, max_memory)

    def solve_state(self, model: BeltOscillator, friction: FrictionLaw, y0: np.ndarray, t_end: float,
                    progress: bool = False, max_memory: float = DEFAULT_MAX_MEMORY) -> Trajectory:
        """As :meth:`~frictionflow.Solver.solve`, from the whole state ``y0`` = (X, X', internal states) (an orbit's point, say)."""
        y0 = np.asarray(y0, dtype=float)
        if y0.shape != (2 + len(friction.internal_names),) or not np.all(np.isfinite(y0)):
            raise ValueError(f"y0 must be {2 + len(friction.internal_names)} finite numbers (X, X', the internal states), got {y0!r}")
        period = sample_period(model)
        q = kernel_params(model, friction)
        tol = np.concatenate([[self.atol, self.atol], self.atol * friction.internal_scale(), [self.rtol]])
        steps = np.array([min(1e-5, self.max_step), self.max_step, float(self.max_steps), period])
        with progress_bar("stiff", 1, enabled=flag("progress", progress) and t_end > 1e5) as advance:
            (n, status, t_stop, h), (t, y, w) = self._run(q, model, y0, t_end, tol, steps, max_memory)
            advance(1)
        if status in (kernel.STEP_CAP, kernel.TINY_STEP):
            why = f"max_steps={self.max_steps} reached" if status == kernel.STEP_CAP else "the step size vanished"
            raise StepLimitError(f"stiff: {why} at tau={t_stop:.10g} (X={y[0, n - 1]:.6g}, X'={y[1, n - 1]:.6g}, "
                                 f"step {h:.3g}); raise max_steps or loosen rtol/atol")
        check_resolved(model, friction, t[:n], y[:, :n])
        return self._trajectory(model, friction, t[:n].copy(), y[:, :n], w[:n])

    def _run(self, q, model, y0, t_end, tol, steps, max_memory):
        """The kernel with room for the samples: when they do not fit, four times more room and the run
        goes on where it stopped."""
        cap = self.sample_estimate(t_end, model)
        at = np.zeros(kernel.N_AT)
        t, y, w = np.empty(0), np.empty((len(y0), 0)), np.empty((0, kernel.N_CHANNELS))
        while True:
            check_memory(cap, max_memory, lambda: self.sized(t_end))  # a sample: about the size of the others'
            t, y, w = _grown(t, y, w, cap, int(at[kernel.AT_COUNT]))
            # the kernel with the GIL released: a sweep runs its points on threads through here
            result = stiff_points.run_released(q, model.zeta, model.vb, y0, float(t_end), tol, steps, t, y, w, at)
            if result[1] != kernel.FULL:
                return result, (t, y, w)
            cap *= 4

    def _trajectory(self, model, friction, t, y, w) -> Trajectory:
        """The run's Trajectory: the force and the mode from the law at each sample.  ``y``, ``w``: views
        of the run's buffers (each block is copied once, out of them)."""
        vr = (model.belt_speed(t) if model.belt_varies else model.vb) - y[1]
        internal = y[2:].copy()
        return Trajectory(
            t=t, state=y[:2].copy(), force=np.asarray(friction.force(vr, internal), dtype=float)[None, :],
            modes=friction.mode_of(vr)[None, :], dwork=np.ascontiguousarray(w[:, :kernel.W_BELT]),
            model=model, friction=friction, solver=self.describe(), events=None,
            internal=internal, internal_names=friction.internal_names, dbelt=w[:, kernel.W_BELT].copy(),
        )


class ResolutionError(StepLimitError):
    """The run reached states its variables cannot resolve (V_r = V_b - X' within rounding of V_b where
    the law's force moves by more than its tolerance): its steps there are not the law's motion."""


#: a law whose force moves by more than this fraction of F_s across the rounding of V_r is unresolved there
RESOLVED_FORCE = 1e-6


def check_resolved(model: BeltOscillator, friction: FrictionLaw, t: np.ndarray, y: np.ndarray) -> None:
    """Refuse a run whose V_r = V_b(tau) - X' fell within rounding of V_b where the law's force moves by more
    than :data:`RESOLVED_FORCE` F_s across that rounding (rate-and-state at rest: N a e^(mu0/a) / (2 V_0)
    per unit of V_r).  The belt frame holds X', so V_r is known to rounding of V_b only; a Rosenbrock step
    there extrapolates the force linearly from a V_r it cannot move off, and every check passes.  Only laws
    that declare it (``stiff_at_rest``) can get there."""
    if not friction.stiff_at_rest:
        return
    vbt = model.belt_speed(t) if model.belt_varies else np.full(len(t), model.vb)
    res = 4.0 * np.finfo(float).eps * np.maximum(np.abs(vbt), np.abs(y[1]))
    near = np.flatnonzero(np.abs(vbt - y[1]) <= res)
    if not len(near):
        return
    z = y[2:, near]
    jump = np.abs(np.asarray(friction.force(res[near], z)) - np.asarray(friction.force(np.zeros(len(near)), z)))
    bad = np.flatnonzero(jump > RESOLVED_FORCE * max(abs(float(friction.fs)), np.finfo(float).tiny))
    if len(bad):  # the first such sample: where the run stopped being the law's motion
        first, last = t[near[bad[0]]], t[near[bad[-1]]]
        held = f" (and at {len(bad)} samples up to tau={last:.6g})" if len(bad) > 1 else ""
        raise ResolutionError(
            f"stiff: V_r = V_b - X' reached the rounding of V_b at tau={first:.6g}{held}, where friction="
            f"{friction.name}'s force moves by {jump[bad[0]]:.3g} across it: the run is not resolved there; "
            f"start it off V_r = 0 (the law's stiffness at rest is beyond the belt frame's reach)")


def _grown(t, y, w, cap, count):
    """Sample buffers with room for ``cap``, holding the first ``count`` samples of (t, y, w)."""
    t2, y2, w2 = np.empty(cap), np.empty((y.shape[0], cap)), np.empty((cap, w.shape[1]))
    t2[:count], y2[:, :count], w2[:count] = t[:count], y[:, :count], w[:count]
    return t2, y2, w2


def sample_period(model: BeltOscillator) -> float:
    """The stroboscopic period a run samples exactly: the forcing's 2 pi / Omega, the belt's 2 pi / Omega_b,
    their common one when both vary (Omega_b must equal Omega), 0.0 for neither (the section X' = 0)."""
    if model.forced and model.belt_varies:
        if model.vb_omega != model.omega:
            raise ValueError(f"vb_omega must equal omega when the belt's speed and the external force both vary "
                             f"(one stroboscopic period), got vb_omega={model.vb_omega:g}, omega={model.omega:g}")
        return model.forcing_period
    if model.belt_varies:
        return 2.0 * math.pi / model.vb_omega
    return model.forcing_period if model.forced else 0.0
