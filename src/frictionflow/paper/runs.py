"""One parameter point of the paper, run with the paper's method and with the exact solver.

The paper's method is fixed-step RK4 through Karnopp's band with F_e = X,
F_s = F_d, V_d = 1e-3 from X(0) = F_d, X'(0) = V_b.  The exact solver
integrates the same law switch to switch in closed form; the two differ only
by RK4's error and by where RK4's steps land in the band.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..friction import Coulomb, Karnopp
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers import RK4, Exact
from ..trajectory import Trajectory
from .settings import Settings

#: the two ways every study is run, by solver name: the paper's RK4, and the exact solver on a dense grid
_MAKERS: dict[str, Callable[["Settings", "int | None"], "RK4 | Exact"]] = {
    RK4.name: lambda settings, record_every: RK4(dt=settings.dt, record_every=record_every),
    Exact.name: lambda settings, record_every: Exact(dense_dt=settings.exact_dense_dt),
}
SOLVERS = tuple(_MAKERS)


@dataclass(frozen=True)
class Point:
    """A parameter point (zeta, V_b, F_d) of the paper."""

    zeta: float
    vb: float
    fd: float

    @property
    def label(self) -> str:
        return f"zeta={self.zeta:g}, V_b={self.vb:g}, F_d={self.fd:g}"


def paper_law(fd: float, settings: Settings) -> Karnopp:
    """Karnopp's law as the paper uses it: F_s = F_d, F_e = X."""
    return Karnopp(fd, vd=settings.vd, stick_force="spring")


def solver(name: str, settings: Settings, record_every: int | None = None) -> RK4 | Exact:
    """The paper's RK4 (``"rk4"``) or the exact solver sampled on a dense grid (``"exact"``)."""
    make = _MAKERS.get(name)
    if make is None:
        raise ValueError(f"solver must be one of {', '.join(SOLVERS)}, got {name!r}")
    return make(settings, record_every)


def run(point: Point, name: str, settings: Settings, t_end: float | None = None,
        record_every: int | None = None) -> Trajectory:
    """Run ``point`` from the paper's initial state with solver ``name``."""
    return simulate(
        BeltOscillator(zeta=point.zeta, vb=point.vb),
        paper_law(point.fd, settings),
        solver(name, settings, record_every),
        t_end=settings.t_end if t_end is None else t_end,
    )


def run_coulomb(point: Point, settings: Settings, t_end: float) -> Trajectory:
    """Ideal Coulomb friction (no band), exact: what Karnopp's band approximates as V_d -> 0."""
    return simulate(
        BeltOscillator(zeta=point.zeta, vb=point.vb),
        Coulomb(point.fd, stick_force="spring"),
        Exact(dense_dt=settings.exact_dense_dt),
        t_end=t_end,
    )
