"""Fixed-step classical RK4, the paper's method."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from .. import _validate as check
from .._progress import progress_bar
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from ..trajectory import Trajectory
from ..parameters import Param, positive_real
from .base import CoarseStepWarning, Solver

DT = positive_real("dt", "", "RK4 step", "solver", 1e-3)
RECORD_EVERY = Param("record_every", "", "keep every k-th RK4 step", "solver", None, default_text="every step, up to 5e6 samples",
                     kind="int", lower=1)
from ..core import rk4 as kernel

#: RK4's stability limit h*|lambda| on the negative real axis
RK4_REAL_LIMIT = 2.785
#: without ``record_every`` the run keeps at most this many samples
MAX_AUTO_SAMPLES = 5_000_000
CHUNK = 2_000_000


class RK4(Solver):
    """Classical fourth-order Runge-Kutta with a fixed step.

    The friction law is evaluated at each of the four stages, with the
    discontinuities handled by its stick band (Karnopp's |V_r| <= V_d), as in
    the paper.  The power-flow work integrals are integrated by the same
    stages.

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

    def __init__(self, dt: float = 1e-3, record_every: int | None = None) -> None:
        self.dt = check.positive("dt", dt)
        self.record_every = None if record_every is None else check.positive_int("record_every", record_every)

    def describe(self) -> dict[str, Any]:
        return {"name": self.name, "dt": self.dt, "record_every": self.record_every}

    def supports(self, friction: FrictionLaw) -> bool:
        return friction.band is not None

    def step_limits(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float) -> dict[str, float]:
        """Largest steps that resolve the stick band and keep RK4 stable."""
        z = model.zeta
        # Bound on |X''| over the run: the motion stays within the energy radius
        # about the slip centre, grown by at most the static-kinetic gap and V_b.
        radius = math.hypot(x0 - friction.fd, v0) + (friction.fs - friction.fd) + abs(model.vb)
        accel = radius * (1.0 + 2.0 * z) + friction.fs
        band_dt = friction.band / accel if accel > 0 else math.inf
        # Slip about (F_d, 0) never gets faster than its start: the band is out of reach.
        if abs(model.vb) - friction.band > math.hypot(x0 - friction.fd, v0):
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

    def solve(
        self,
        model: BeltOscillator,
        friction: FrictionLaw,
        x0: float,
        v0: float,
        t_end: float,
        progress: bool = False,
    ) -> Trajectory:
        if not self.supports(friction):
            raise ValueError(f"solver=rk4 does not support friction={friction.name}")
        for msg in self.check_step(model, friction, x0, v0):
            warnings.warn(msg, CoarseStepWarning, stacklevel=3)
        n = max(1, math.ceil(t_end / self.dt - 1e-9))
        every = self.record_every or max(1, math.ceil(n / MAX_AUTO_SAMPLES))
        n_samples = -(-n // every) + 1
        t, x, v, fc = (np.empty(n_samples) for _ in range(4))
        mode = np.empty(n_samples, dtype=np.int8)
        work = np.empty((n_samples, 4))
        state = np.array([x0, v0, 0.0, 0.0, 0.0, 0.0])
        p = friction.kernel_params()
        k = 0
        with progress_bar("rk4", n, enabled=progress and n > 5 * CHUNK) as advance:
            for i0 in range(0, n, CHUNK):
                i1 = min(n, i0 + CHUNK)
                k = kernel.run(state, i0, i1, n, every, 0.0, self.dt, model.zeta, model.vb, p, t, x, v, fc, mode, work, k)
                advance(i1 - i0)
        assert k == n_samples
        return Trajectory(
            t=t,
            x=x,
            v=v,
            fc=fc,
            mode=mode,
            dwork=work,
            model=model,
            friction=friction,
            solver=self.describe() | {"record_every": every, "steps": n},
        )
