"""Fixed-step classical RK4, the paper's method."""

from __future__ import annotations

import math
import warnings
from typing import Any, Mapping

import numpy as np

from .._progress import progress_bar
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..trajectory import Trajectory
from ..parameters import MODEL_MAX, Param
from ..core import batch, sections
from ..core.layout import FEX, LAW, VB_AMP
from ..core.records import N_CONTACTS, N_STATE, Samples, empty_samples
from ..estimate import SECONDS_PER, Estimate
from .base import kernel_params, CoarseStepWarning, Solver, check_memory

# (a step below 1e-9 or more steps than MAX_STEPS would run for days: refused up front)
DT = Param("dt", "", "RK4 step", "solver", 1e-3, lower=1e-9, upper=MODEL_MAX)
RECORD_EVERY = Param("record_every", "", "keep every k-th RK4 step", "solver", None, default_text="every step, up to 5e6 samples",
                     kind="int", lower=1, upper=1e12)
from ..core import rk4 as kernel
from ..core.rk4 import step_count

#: RK4's stability limit h*|lambda| on the negative real axis
RK4_REAL_LIMIT = 2.785
#: without ``record_every`` the run keeps at most this many samples
MAX_AUTO_SAMPLES = 5_000_000
CHUNK = 2_000_000
#: more steps than this would run for hours (at ~30 ns each): refused up front
MAX_STEPS = 10**11


def _forced_amplitude(model: BeltOscillator) -> float:
    """Amplitude of the linear oscillator's steady response to the external force (inf at undamped resonance)."""
    w = model.omega
    den = math.hypot(1.0 - w * w, 2.0 * model.zeta * w)
    return model.fex / den if den > 0 else (math.inf if model.fex > 0 else 0.0)


def _driven(p: np.ndarray) -> bool:
    """Whether the force record ``p`` drives the mass in time (an external force or a moving belt): the forced loops."""
    return bool(p[FEX] != 0.0 or p[VB_AMP] != 0.0)


def _divisor_at_least(n: int, k: int) -> int:
    """The smallest divisor of ``n`` that is >= ``k`` (``k`` itself when ``n`` is 0): thinning that keeps every n-th step."""
    if n == 0 or k <= 1:
        return max(k, 1)
    return next((d for d in range(k, n + 1) if n % d == 0), n * math.ceil(k / n))


class ThinnedOutputWarning(UserWarning):
    """RK4 keeps only part of its steps (the analysis is unaffected: events are kept)."""


def _arrays(n: int) -> Samples:
    """The kernels' output record (:data:`~frictionflow.core.records.Samples`) with room for ``n`` samples."""
    return empty_samples(n, N_STATE, N_CONTACTS)


def _grown(bufs: Samples) -> Samples:
    """``bufs`` with twice the room, the samples kept (each block grows along its sample axis)."""
    t, y, fc, mode, work = bufs
    more = _arrays(len(t))
    return Samples(np.concatenate([t, more.t]), np.concatenate([y, more.y], axis=1),
                   np.concatenate([fc, more.fc], axis=1), np.concatenate([mode, more.mode], axis=1),
                   np.concatenate([work, more.work]))


def _first(bufs: Samples, k: int) -> Samples:
    """The first ``k`` samples of ``bufs`` (views)."""
    t, y, fc, mode, work = bufs
    return Samples(t[:k], y[:, :k], fc[:, :k], mode[:, :k], work[:k])


class RK4(Solver):
    """Classical fourth-order Runge-Kutta with a fixed step.

    The friction law is evaluated at each of the four stages, with the
    discontinuities handled by its stick band (Karnopp's |V_r| <= V_d), as in
    the paper.  The power-flow work integrals are integrated by the same
    stages.  A moving belt enters each stage at its time (V_b(tau), and the
    load f - V_b' that the band holds); the step divides 2 pi / Omega_b as
    it does a forcing period.

    Parameters
    ----------
    dt:
        Step in non-dimensional time, > 0.
    record_every:
        Keep every k-th step (the work integrals stay exact at the kept
        samples).  ``None`` keeps every step unless that exceeds
        5,000,000 samples, then thins evenly.
    """

    name = "rk4"
    parameters = (DT, RECORD_EVERY)
    steady_rtol = 1e-6  # fixed-step RK4 resolves orbits to about 1e-6 at dt = 1e-3
    fixed_step = True
    supports_belt_motion = True
    batched = staticmethod(batch.rk4_points)
    step_cost = "rk4_step"

    def __init__(self, dt: float = 1e-3, record_every: int | None = None) -> None:
        self.dt = DT.check(dt)
        self.record_every = None if record_every is None else RECORD_EVERY.check(record_every)
        self._seal()

    def describe(self) -> dict[str, Any]:
        return {"name": self.name, "dt": self.dt, "record_every": self.record_every}

    def supports(self, friction: FrictionLaw) -> bool:
        return friction.band is not None  # it steps through a stick band: the law must say how wide

    @classmethod
    def section_noise(cls, settings: Mapping[str, Any]) -> float:
        return cls.steady_rtol  # about the tolerance its classification uses (1e-6 of the motion at dt = 1e-3)

    def chunk_points(self, t_end: float) -> int:
        steps = math.ceil(t_end / self.dt)
        return max(64, int(0.2 / (steps * 10e-9)))  # ~10 ns per step per point, one core

    def run_points(self, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray,
                   t_end: float, rtol: float, min_periods: int, out: np.ndarray) -> None:
        # one law per sweep: the batched loop is compiled for its code; it counts the steps as simulate does
        self.batched(int(p[0, LAW]), p, zeta, vb, x0, v0, t_end, self.dt, rtol, min_periods,
                     self.section_noise(self.describe()), out)

    def step_estimate(self, t_end: float, model: BeltOscillator, friction: FrictionLaw) -> float:
        """Steps to ``t_end`` with the step used (:meth:`aligned_step`): exact, not an estimate."""
        return float(math.ceil(t_end / self.aligned_step(model)[0] - 1e-9))

    def sample_estimate(self, t_end: float, model: BeltOscillator | None = None) -> int:
        """Samples kept: every ``record_every``-th step (unless told: every step, up to 5e6) and those around events."""
        n = math.ceil(t_end / (self.dt if model is None else self.aligned_step(model)[0]) - 1e-9)
        if self.record_every is None and n < MAX_AUTO_SAMPLES:
            return n + 1
        return min(n + 1, n // (self.record_every or max(1, n // MAX_AUTO_SAMPLES)) + int(4 * t_end) + 64)

    def point_cost(self, model: BeltOscillator, friction: FrictionLaw, t_end: float) -> Estimate:
        """A sweep point's steps to ``t_end`` in the batched kernel (a bound: it stops once settled)."""
        steps = self.step_estimate(t_end, model, friction)
        return Estimate(steps, "RK4 steps", steps * SECONDS_PER["rk4_point_step"])

    def step_limits(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float) -> dict[str, float]:
        """Largest steps that resolve the stick band and keep RK4 stable."""
        z = model.zeta
        # Bound on |X''| over the run: the motion stays within the energy radius
        # about the slip centre, grown by at most the static-kinetic gap and V_b.
        # An external force adds its linear steady response F_ex / sqrt((1 - W^2)^2 + (2 zeta W)^2).
        belt = model.vb_amplitude if model.belt_varies else 0.0
        radius = math.hypot(x0 - friction.fd, v0) + (friction.fs - friction.fd) + abs(model.vb) + belt + _forced_amplitude(model)
        accel = radius * (1.0 + 2.0 * z) + friction.fs + model.fex + belt * model.vb_omega
        band_dt = friction.band / accel if accel > 0 else math.inf
        # Unforced slip about (F_d, 0) never gets faster than its start: the band is out of reach.
        if not model.driven and abs(model.vb) - friction.band > math.hypot(x0 - friction.fd, v0):
            band_dt = math.inf
        lam = z + math.sqrt(z * z - 1.0) if z > 1.0 else 1.0
        return {"band": band_dt, "stability": RK4_REAL_LIMIT / lam}

    def check_step(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float) -> list[str]:
        """Warnings (as text) for a step too coarse for the band or for stability."""
        lim = self.step_limits(model, friction, x0, v0)
        out = []
        if self.dt > lim["band"]:
            out.append(
                f"dt={self.dt:g} lets X' jump across the stick band |V_r| <= {friction.band:g} "
                f"in one step; use dt <= {lim['band']:.3g}"
            )
        if self.dt > lim["stability"]:
            out.append(f"dt={self.dt:g} is beyond RK4's stability limit for zeta={model.zeta:g}; use dt <= {lim['stability']:.3g}")
        return out

    def _solve(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, t_end: float,
               progress: bool, max_memory: float) -> Trajectory:
        dt, per_period = self.aligned_step(model)
        n = self.steps(t_end, dt)
        for msg in self.check_step(model, friction, x0, v0):
            warnings.warn(msg, CoarseStepWarning, stacklevel=3)
        every = self.record_every or _divisor_at_least(per_period, math.ceil(n / MAX_AUTO_SAMPLES))
        if every > 1 and self.record_every is None:
            warnings.warn(f"rk4: {n} steps; keeping one step in {every} and the steps around every section crossing, "
                          "extreme and mode change, so that classification and averages are those of every step "
                          "(record_every sets the thinning)", ThinnedOutputWarning, stacklevel=3)
        p = kernel_params(model, friction)
        args = (dt, model.zeta, model.vb, p)
        with progress_bar("rk4", n, enabled=progress and n > 5 * CHUNK) as advance:
            if every == 1:
                out = self._every_step(n, x0, v0, args, max_memory, t_end, advance)
            else:
                out = self._thinned(n, every, x0, v0, args, max_memory, t_end, advance)
        return Trajectory(
            t=out.t, state=out.y, force=out.fc, modes=out.mode, dwork=out.work, model=model, friction=friction,
            solver=self.describe() | {"record_every": every, "steps": n} | ({"dt": dt} if dt != self.dt else {}),
        )

    def aligned_step(self, model: BeltOscillator) -> tuple[float, int]:
        """The step used and the steps per forcing period (0 unforced).

        With an external force (or a moving belt) the step shrinks to the
        nearest whole fraction of the period 2 pi / Omega (2 pi / Omega_b), so
        that the stroboscopic section falls on steps.
        """
        if not model.driven:
            return self.dt, 0
        period = model.drive_period
        per = max(1, math.ceil(period / self.dt - 1e-9))
        return period / per, per

    def steps(self, t_end: float, dt: float | None = None) -> int:
        """Steps to reach ``t_end``; ValueError when that is none or more than ``MAX_STEPS``."""
        dt = self.dt if dt is None else dt
        if dt > t_end:
            raise ValueError(f"dt must be <= t_end = {t_end:g}, got {dt:g}")
        n = step_count(t_end, dt)
        if n > MAX_STEPS:
            raise ValueError(f"t_end={t_end:g} with dt={dt:g} makes {n:.3g} RK4 steps, more than {MAX_STEPS:.0e} "
                             "(hours of computing): raise dt or shorten t_end")
        return n

    def _every_step(self, n: int, x0: float, v0: float, args: tuple, max_memory: float, t_end: float, advance) -> tuple:
        check_memory(n + 1, max_memory, lambda: self.sized(t_end))
        out = _arrays(n + 1)
        state = np.zeros(kernel.N_STATE)
        state[:2] = x0, v0
        run = kernel.run_forced if _driven(args[-1]) else kernel.run  # an unforced run compiles no forced loop
        k = 0
        for i0 in range(0, n, CHUNK):
            i1 = min(n, i0 + CHUNK)
            k = run(state, (i0, i1, n, 1), 0.0, *args, out, k)
            advance(i1 - i0)
        return out

    def _thinned(self, n: int, every: int, x0: float, v0: float, args: tuple, max_memory: float, t_end: float, advance) -> tuple:
        # room for the regular samples and ~25 event samples per natural period; grown on demand
        cap = n // every + int(4 * t_end) + 64
        bufs = _arrays(cap)
        state = np.zeros(kernel.N_STATE + 2)
        state[:2] = x0, v0
        state[kernel.N_STATE] = np.nan
        t_tail = sections.tail_start(0.0, n * args[0])
        thinned = kernel.run_thinned_forced if _driven(args[-1]) else kernel.run_thinned
        k = i = 0
        while i < n:
            check_memory(len(bufs[0]), max_memory, lambda: self.sized(t_end))
            i1 = min(n, i + CHUNK)
            k, i_done = thinned(state, (i, i1, n, every), 0.0, args[0], t_tail, *args[1:], bufs, k)
            advance(i_done - i)
            i = i_done
            if i < i1:  # full: more room, and on from where it stopped
                bufs = _grown(bufs)
        return _first(bufs, k)
