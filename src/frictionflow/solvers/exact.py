"""The exact event-driven solver for piecewise-constant friction laws."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from .._progress import progress_bar
from ..core import batch, batch_forced
from ..core import exact as kernel
from ..core import exact_belt
from ..core import sections
from ..core.records import Events, Samples, run_record
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..trajectory import Trajectory
from ..parameters import MODEL_MAX, SUBNORMAL_BELOW, Param
from .base import flag, kernel_params, Solver, run_growing, trajectory_from
from .events import ADAPTIVE_EVENT_MODES, EXACT_EVENT_MODES

#: the dense grid's step: from 1e-9 up, as RK4's step (finer ones make the sample count of any run beyond memory,
#: and a subnormal one made it inf)
DENSE_DT = Param("dense_dt", "", "exact/adaptive: also sample every DENSE_DT", "solver", None, lower=1e-9, upper=MODEL_MAX,
                 default_text="only switches and sections; 2pi/200 with --out/--plot, with --model and --out at least 200 "
                              "per period of its fastest mode")


def resonance_problem(zeta: float, omega: float, fex: float) -> str | None:
    """Why the exact solver cannot run (zeta, omega, fex), or None: undamped resonance has no closed form it uses.

    Nor has a resonance so nearly undamped that |1 - Omega^2 + 2i zeta Omega|^2, whose reciprocal scales the
    particular solution, is below the normal floats (zeta Omega below ~1e-154 at Omega = 1): the closed form
    divides by 0 there, or builds on a denominator that has lost its digits.
    """
    if fex <= 0.0:
        return None
    if zeta == 0.0 and omega == 1.0:
        return (f"solver=exact: undamped resonance (zeta=0, omega=1, fex={fex:g}) has no periodic particular solution "
                "(the response grows like tau sin tau); use zeta > 0 or omega != 1")
    if (1.0 - omega * omega) ** 2 + (2.0 * zeta * omega) ** 2 < SUBNORMAL_BELOW:
        return (f"solver=exact: resonance too nearly undamped (zeta={zeta:g}, omega={omega:.17g}): "
                f"|1 - omega^2 + 2i zeta omega|^2 underflows, so the particular solution cannot be computed; "
                "use a larger zeta or move omega away from 1")
    return None


def _sliding_hint(model: BeltOscillator, friction: FrictionLaw, t: float, x: float, v: float) -> str:
    """Why a run stalls where the spring stick rule says slip but both slip directions return to the belt."""
    f = float(model.external_force(t))
    if friction.stick_force != "spring" or v != model.vb:
        return ""
    if abs(x - f) > friction.fs and abs(x + 2.0 * model.zeta * model.vb - f) < friction.fd:
        return (": the spring stick rule says slip (|X - f| > F_s) but both slip directions return to the belt "
                "(|X + 2 zeta V_b - f| < F_d), a sliding motion the switch model cannot represent; "
                "use stick_force='resultant'")
    return ""


class Exact(Solver):
    """Advance from switch to switch in closed form (Karnopp and ideal Coulomb).

    Between switches the oscillator is linear with a constant (or linear)
    friction force; switch times are found by bracketed root finding on the
    closed form to about machine precision, and the work integrals are
    integrated in closed form, so averages and the energy balance are exact
    to rounding.

    Parameters
    ----------
    dense_dt:
        Also sample the closed form every ``dense_dt`` (for plots and files).
        ``None``: only the samples the analysis needs (switches, zeros and
        extremes of X', the end).
    replicate:
        Copy a stretch of switches that repeats bit for bit (an unforced
        stick-slip cycle, from a release state equal to an earlier one)
        instead of integrating it again: the same samples, bit for bit
        (``frictionflow.core.exact.run``).  False: integrate every
        switch (for timing; the result is the same).
    """

    name = "exact"
    refusal_reason = " (its slip force is not constant)"
    parameters = (DENSE_DT,)
    interpolant = "closed_form"
    #: in a structure: the laws whose phases are linear (piecewise-constant slip force, stuck a constraint)
    structure_laws = staticmethod(lambda law: law.piecewise_constant and law.stick_rule == "switch")
    steady_rtol = 1e-10  # the closed forms resolve orbits to rounding
    default_chunk = 8192
    batched = staticmethod(batch.exact_points)
    batched_forced = staticmethod(batch_forced.forced_points)

    def __init__(self, dense_dt: float | None = None, *, replicate: bool = True) -> None:
        self.dense_dt = None if dense_dt is None else DENSE_DT.check(dense_dt)
        self.replicate = flag("replicate", replicate)
        self._seal()

    def describe(self) -> dict[str, Any]:
        # not ``replicate``: it changes the cost, never the result
        return {"name": self.name, "dense_dt": self.dense_dt}

    def __repr__(self) -> str:
        return super().__repr__()[:-1] + ("" if self.replicate else ", replicate=False") + ")"

    supports_belt_motion = True  # Coulomb's switch (core.exact_belt); Karnopp's band on a moving belt is refused
    # On a moving belt the stroboscopic section converges geometrically (no stick phase resets it), so a run of
    # a few hundred time units is often still above this solver's steady tolerance (1e-10, rounding) where the
    # adaptive solver's (1e-6) classifies it: auto keeps the adaptive solver there.
    auto_belt_motion = False

    def belt_motion_problem(self, friction: FrictionLaw) -> str | None:
        if friction.stick_rule != "switch":  # core.exact_belt locates Coulomb's switch; a band has no closed form
            return (f"solver=exact runs a belt whose speed varies (vb_amplitude > 0) with Coulomb's switch only, "
                    f"not friction={friction.name}'s band")
        return super().belt_motion_problem(friction)

    def supports(self, friction: FrictionLaw) -> bool:
        return friction.piecewise_constant

    def forcing_problem(self, zeta: float, omega: float, fex: float) -> str | None:
        return resonance_problem(zeta, omega, fex)

    @classmethod
    def section_noise(cls, settings: Mapping[str, Any]) -> float:
        return 1e-13  # rounding of the closed forms

    def run_points(self, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray,
                   t_end: float, rtol: float, min_periods: int, out: np.ndarray) -> None:
        self.batched(p, zeta, vb, x0, v0, t_end, rtol, min_periods, self.section_noise(self.describe()), out)

    def run_forced_points(self, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray,
                          t_end: float, rtol: float, friction: FrictionLaw, out: np.ndarray) -> np.ndarray:
        # a law without a tangent kernel cannot have its Lyapunov exponent: such points are not_settled, as in analyze
        return self.batched_forced(p, zeta, vb, x0, v0, t_end, rtol, 3, self.section_noise(self.describe()), out,
                                   dense_dt=self.dense_dt or 0.0, lyapunov=friction.has_tangent_kernel)

    step_cost = "exact_sample"  # a step of the exact solver is a kept sample: a switch, an extreme, a dense point
    point_cost_per = "exact_point_time"

    def sample_estimate(self, t_end: float, model: BeltOscillator | None = None) -> int:
        """Room for the samples of a run to ``t_end``: ~8 per natural period, the dense grid included.

        A forced ``model`` adds the stroboscopic samples, and extremes at the forcing's frequency.
        """
        dense = int(t_end / self.dense_dt) + 2 if self.dense_dt else 0
        forced = 0
        if model is not None and model.forced:
            forced = int(t_end / model.forcing_period) + int(8 * model.omega * t_end / math.pi)
        if model is not None and model.belt_varies:  # the belt's stroboscopic samples, extremes at its frequency
            forced += int(t_end * model.vb_omega / math.pi) + int(8 * model.vb_omega * t_end / math.pi)
        return int(16 * t_end / (2 * math.pi)) + 64 + dense + forced

    @staticmethod
    def _full(result: tuple, bufs: tuple[Samples, Events]) -> bool:
        return result[2] == kernel.FULL or result[1] > len(bufs[1].t)

    def _solve(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, t_end: float,
               progress: bool, max_memory: float) -> Trajectory:
        problem = self.forcing_problem(model.zeta, model.omega, model.fex)
        if problem:
            raise ValueError(problem)
        problem = self.belt_motion_problem(friction) if model.belt_varies else None
        if problem:
            raise ValueError(problem)
        p = kernel_params(model, friction)
        dense = self.dense_dt or 0.0
        t_tail = sections.tail_start(0.0, t_end)
        t_mode = np.zeros(1, dtype=np.int64)

        # every argument positional, typed as the adaptive façade's: one compiled builder for both
        rec = run_record((float(x0), float(v0)), float(t_end), model.zeta, model.vb, t_tail, dense, (0.0, 0.0, 0),
                         (False, False, 0.0, 3), (0.0, 0.0))

        def run(bufs: tuple[Samples, Events]) -> tuple:
            if model.belt_varies:
                return exact_belt.run_moving(rec, p, *bufs)
            if model.forced:
                return kernel.run_forced(rec, p, *bufs, t_mode)
            return kernel.run(rec, p, *bufs, t_mode, self.replicate, False)  # False: no periodic stop

        estimate = self.sample_estimate(t_end, model)
        if progress and t_end > 1e5:
            with progress_bar("exact", 1) as advance:
                (n, ne, status, t_term, _), bufs = run_growing(run, estimate, self._full, max_memory, lambda: self.sized(t_end))
                advance(1)
        else:  # (no context manager: ~1 us, a few per cent of a short run)
            (n, ne, status, t_term, _), bufs = run_growing(run, estimate, self._full, max_memory, lambda: self.sized(t_end))
        if status == kernel.STUCK:
            t, (x, v) = bufs[0].t, bufs[0].y
            raise RuntimeError(f"exact: repeated zero-length phases at tau={t[n - 1]:.17g}, X={x[n - 1]:.17g}, "
                               f"X'={v[n - 1]:.17g}" + _sliding_hint(model, friction, t[n - 1], x[n - 1], v[n - 1]))
        extra = {"t_terminal": None if t_term < 0 else float(t_term), "terminal_mode": int(t_mode[0])}
        return trajectory_from(bufs, n, ne, model, friction, self.describe(), extra,
                               # on a moving belt the switches are coded as the adaptive kernel's (its stick rule)
                               event_modes=ADAPTIVE_EVENT_MODES if model.belt_varies else EXACT_EVENT_MODES)
