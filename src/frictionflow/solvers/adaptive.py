"""Adaptive Dormand-Prince 5(4) with located switches, for nonlinear slip laws."""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache
from typing import Any, Callable, Mapping

import numpy as np

from .. import _validate as check
from .._progress import progress_bar
from ..core import batch, dopri, sections
from ..core._rebind import rebind
from ..core.layout import FEX, VB_AMP
from ..core.records import Events, Samples, run_record
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..trajectory import Trajectory
from ..parameters import Param
from .base import kernel_params, Solver, run_growing, trajectory_from
from .events import ADAPTIVE_EVENT_MODES
from .exact import DENSE_DT

# below 1e-14 the error estimate is rounding; above 1e-2 the switches are not located
ODE_RTOL = Param("ode_rtol", "", "adaptive solver's relative tolerance", "solver", 1e-10, lower=1e-14, upper=1e-2)
MAX_STEPS = Param("max_steps", "", "adaptive solver's step cap", "solver", 10_000_000, default_text="1e7",
                  kind="int", lower=1, upper=1e12)


class StepLimitError(RuntimeError):
    """The adaptive solver hit its step cap (or a vanishing step) before the end."""


def kernel_for(friction: FrictionLaw) -> tuple[Callable, bool]:
    """The ``run`` kernel for a law: the built-in one, or one rebuilt around a user's slip function.

    Returns (kernel, compiled).  A user function numba cannot compile runs in
    the Python version of the same kernel.
    """
    if friction.compiled_slip:
        return _builtin_run, True
    force = friction.kernel_force()
    if force is not None:  # one kernel for every compiled user function: it calls the one whose address p holds
        return _compiled_user_kernel(force), True
    return _python_user_kernel(friction.func), False


def _builtin_run(run, p, samples, events):
    """:func:`frictionflow.core.dopri.run`, choosing its variant here: a first unforced run compiles only the unforced one."""
    return _variant(p, dopri.run_unforced, dopri.run_forced, dopri.run_moving)(run, p, samples, events)


def _variant(p: np.ndarray, unforced: Callable, forced: Callable, moving: Callable) -> Callable:
    """The kernel's variant for the force record ``p``: on a moving belt, forced, or neither."""
    if p[VB_AMP] != 0.0:
        return moving
    return forced if p[FEX] != 0.0 else unforced


@lru_cache(maxsize=None)
def _compiled_user_kernel(force: Callable) -> Callable:
    return _rebuild(force, compiled=True)


@lru_cache(maxsize=32)
def _python_user_kernel(func: Callable[[float], float]) -> Callable:
    def py_force(p, speed):
        return float(func(speed))

    return _rebuild(py_force, compiled=False)


def _rebuild(force: Callable, compiled: bool) -> Callable:
    kernels = rebind(dopri, dopri.KERNEL_FUNCS, compiled, slip_force=force)
    unforced, forced, moving = kernels["run_unforced"], kernels["run_forced"], kernels["run_moving"]

    def run(run, p, samples, events):
        """:func:`frictionflow.core.dopri.run` for the user's law: each variant compiled when first used."""
        return _variant(p, unforced, forced, moving)(run, p, samples, events)

    return run


class Adaptive(Solver):
    """Embedded Runge-Kutta 5(4) (Dormand-Prince) with every switch located.

    Slip phases are integrated adaptively with the slip direction fixed (no
    sign() inside the integrator, so nothing chatters at V_r = 0); each
    switch is located on the dense output and the run restarts there in the
    mode Coulomb's stick rule selects; stick phases are closed forms.

    With an external force (``model.forced``) every stage sees f at its own
    time, a stick phase ends where |F_e - f(tau)| first reaches F_s (every
    excursion found), W_ex is integrated with the others, and the run also
    samples every tau_k = k 2 pi / Omega.  Steps are at most 0.25 and at most
    0.25 / Omega.  A moving belt (``model.belt_varies``) runs the same way: V_b(tau) at each stage's
    time, a stick phase follows the belt exactly and holds F_e + V_b' - f; the run samples every
    2 pi / Omega_b when there is no external force.

    Parameters
    ----------
    rtol, atol:
        Error tolerances on X and X' per step.  In a structure (``simulate --model``) ``atol`` is in the
        structure's own sizes of positions, velocities and works
        (``frictionflow.system.assemble.state_scales``), so that a run means the same in any units.
    max_steps:
        Step cap; when hit the run stops with :class:`StepLimitError` saying where.
    dense_dt:
        Also sample the dense output every ``dense_dt``.
    """

    name = "adaptive"
    parameters = (ODE_RTOL, MAX_STEPS, DENSE_DT)
    keywords = {"ode_rtol": "rtol"}
    interpolant = "quintic_hermite"  # it samples every step: X'' at both ends is known
    #: in a structure: every switch-rule law with a compiled slip curve (a user's function is not reached there)
    structure_laws = staticmethod(lambda law: law.stick_rule == "switch" and law.compiled_slip)
    structure_free_motion = True  # its steps need no modes
    steady_rtol = 1e-8  # resolves orbits to about its rtol
    default_chunk = 256
    batched = staticmethod(batch.adaptive_points)
    supports_belt_motion = True

    def __init__(self, rtol: float = 1e-10, atol: float = 1e-13, max_steps: int = 10_000_000, dense_dt: float | None = None) -> None:
        self.rtol = replace(ODE_RTOL, name="rtol").check(rtol)  # the API calls it rtol, configs ode_rtol
        self.atol = check.positive("atol", check.number("atol", atol, "finite and > 0"))
        self.max_steps = MAX_STEPS.check(max_steps)
        self.dense_dt = None if dense_dt is None else DENSE_DT.check(dense_dt)
        self._seal()

    def describe(self) -> dict[str, Any]:
        return {"name": self.name, "rtol": self.rtol, "atol": self.atol, "max_steps": self.max_steps, "dense_dt": self.dense_dt}

    def supports(self, friction: FrictionLaw) -> bool:
        return friction.stick_rule == "switch"  # smooth, piecewise-constant and user slip curves alike

    @classmethod
    def section_noise(cls, settings: Mapping[str, Any]) -> float:
        # ten times its rtol: local errors of the steps of a period partly cancel
        return 10.0 * float(settings.get("rtol", 1e-10))

    def run_points(self, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray,
                   t_end: float, rtol: float, min_periods: int, out: np.ndarray) -> None:
        self.batched(p, zeta, vb, x0, v0, t_end, batch.Ode(self.rtol, self.atol, self.max_steps), rtol, min_periods,
                     self.section_noise(self.describe()), out)

    def sample_estimate(self, t_end: float, model: BeltOscillator | None = None) -> int:
        """Room for the samples of a run to ``t_end`` (measured: up to ~26 per time unit), the dense grid included.

        A forced ``model`` adds a sample per forcing period and, for Omega > 1,
        the steps its cap 0.25 / Omega adds.
        """
        dense = int(t_end / self.dense_dt) + 2 if self.dense_dt else 0
        forced = 0
        if model is not None and model.forced:
            forced = int(t_end / model.forcing_period) + 2 + int(40 * t_end * max(model.omega - 1.0, 0.0))
        if model is not None and model.belt_varies:
            forced += int(t_end * model.vb_omega / (2 * np.pi)) + 2 + int(40 * t_end * max(model.vb_omega - 1.0, 0.0))
        return int(40 * t_end) + 256 + dense + forced

    def step_estimate(self, t_end: float, model: BeltOscillator, friction: FrictionLaw) -> float:
        """Steps to ``t_end``, at most ``max_steps``: its samples, and the steps its stability limit adds.

        A bound, not a count: Dormand-Prince is stable for h |lambda| below
        about 3.3, and a damping 2 zeta >> 1 makes |lambda| ~ 2 zeta; a slip
        curve it cannot resolve (:meth:`FrictionLaw.resolvable`) is assumed
        to take it to its step cap.
        """
        if not friction.resolvable():
            return float(self.max_steps)
        stiff = t_end * 2.0 * model.zeta / 3.3
        return float(min(self.max_steps, self.sample_estimate(t_end, model) + stiff))

    @staticmethod
    def _full(result: tuple, bufs: tuple[Samples, Events]) -> bool:
        return result[2] == dopri.FULL or result[1] > len(bufs[1].t)

    def _solve(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, t_end: float,
               progress: bool, max_memory: float) -> Trajectory:
        run, _ = kernel_for(friction)
        p = kernel_params(model, friction)
        dense_dt = self.dense_dt or 0.0
        t_tail = sections.tail_start(0.0, t_end)

        # a single run goes to its end (no early stop: sweeps stop where the end is known, core.batch); every
        # argument positional, typed as the exact façade's: one compiled builder for both
        rec = run_record((float(x0), float(v0)), float(t_end), model.zeta, model.vb, t_tail, dense_dt,
                         (self.rtol, self.atol, self.max_steps), (False, False, 0.0, 3), (0.0, 0.0))

        def kernel(bufs: tuple[Samples, Events]) -> tuple:
            return run(rec, p, *bufs)

        with progress_bar("adaptive", 1, enabled=progress and t_end > 1e5) as advance:
            (n, ne, status, t_stop, h), bufs = run_growing(
                kernel, self.sample_estimate(t_end, model), self._full, max_memory, lambda: self.sized(t_end))
            advance(1)
        if status in (dopri.STEP_CAP, dopri.TINY_STEP):
            why = f"max_steps={self.max_steps} reached" if status == dopri.STEP_CAP else "the step size vanished"
            x, v, mode = bufs[0].y[0], bufs[0].y[1], bufs[0].mode[0]
            raise StepLimitError(
                f"adaptive: {why} at tau={t_stop:.10g} (X={x[n - 1]:.6g}, X'={v[n - 1]:.6g}, "
                f"mode {int(mode[n - 1]):+d}, step {h:.3g}) after {ne} switches; "
                "raise max_steps or loosen rtol/atol, or check the slip law near V_r = 0"
            )
        return trajectory_from(bufs, n, ne, model, friction, self.describe(), event_modes=ADAPTIVE_EVENT_MODES)
