"""What a piece of work will cost, estimated from its declared parameters before it starts, and the limits it keeps.

An :class:`Estimate` is one record per run or study: the count of its
dominant unit of work (steps, switches, points), the CPU seconds that takes
on this machine, the bytes it holds in memory and the bytes of every file it
writes.  Each solver and study builds its own from what it declares (a
solver: its steps per unit time and its cost per step); the costs per step
are the constants of :data:`SECONDS_PER`, measured once on the project's
machine.

:func:`enforce` is the one place an estimate meets the limits: about an hour
of computing, the free space of each output's disk, and a memory bound if
one is set (:class:`Limits`; the runs' own ``max_memory`` checks stay where
they are).  The limits are those :func:`limited` put in force -- none unless
a caller does (the command line does for every command, and its
``--no-limit`` lifts them);
the first estimate accepted inside :func:`limited` is the one the progress
bars show (:func:`frictionflow._progress.progress_bar`) and the one that
counts: a study's estimate covers the runs it makes, which are not checked
again.  A stage whose cost is known only once earlier work is done (the
Newton shooting after the transient that finds its period) is left open by
that first estimate (``enforce(..., open_stage=...)``) and estimated when it
is known (``enforce_stage``), under the same limits.
"""

from __future__ import annotations

import math
import shutil
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, Iterator

from ._progress import ESTIMATE

#: CPU seconds per unit of work of each kernel on one core of the project's 2-core machine (numba compiled, caches
#: warm), measured with ``time.process_time`` around runs long enough that start-up is under a few per cent, then
#: rounded up (an estimate should not promise less than the run takes).  The runs, and what they gave:
#: ``simulate`` of Coulomb(0.02, 0.04), zeta 0.05, V_b 0.01: RK4 dt 1e-3 to tau 2000 (2.3e-8 s per step), exact to
#: tau 1e5 (1.2e-8 s per kept sample); Stribeck, adaptive, to 1e4 (5.0e-7 s per step); the Lyapunov default run
#: of BeltOscillator(0.01, 0.1, fex=0.5, omega=1), Coulomb(0.5, 1) (2.4e-7 s per tangent step, switches
#: included); a forced flow map of 2000 periods of 512 steps, BeltOscillator(0.05, 0.1, fex=0.3, omega=0.8),
#: Coulomb(0.3, 0.5) (5.6e-7 s per grid step, switches included); sweeps over V_b to tau 200-500 (exact: 512
#: points, 4.1e-7 s per point and time unit; adaptive Stribeck: 128 points, 6.1e-6; RK4 Karnopp: 128 points,
#: 1.0e-8 s per point and step); a compiled orbit flow of the grazing margin (Stribeck, 2e-4 s; at V_s = 1e-300
#: 2.7 s for the 1e6 steps of its cap).  A located switch is not timed apart: ~10 grid steps of its root's bisection.
#: The orbit engines' flows, per time unit flowed, over 10 and 1000 time units from (0.06, 0) at zeta 0 and 0.05:
#: closed forms (Coulomb, Karnopp) ~1.1e-5 s a phase, at most SWITCHES_PER_TIME phases a time unit (7e-6), a flow
#: of one phase 7e-6 s in all; compiled DOP853 with sensitivities (Stribeck, cubic, stick-slip and sliding) 0.9 to
#: 2.6e-5 s; scipy's solve_ivp (Stribeck) 8.9e-4 s.
SECONDS_PER = {
    "rk4_step": 3e-8,  # simulate, RK4, per step
    "rk4_point_step": 3e-8,  # a sweep's batched RK4, per point and step
    "exact_sample": 3e-8,  # simulate, exact, per kept sample (each switch or extreme is one)
    "adaptive_step": 6e-7,  # simulate, adaptive (Dormand-Prince), per step
    "exact_point_time": 1e-6,  # a sweep's batched exact solver, per point and time unit
    "adaptive_point_time": 1e-5,  # a sweep's batched adaptive solver, per point and time unit
    "tangent_step": 3e-7,  # Lyapunov: RK4 with two tangent vectors, per grid step
    "map_step": 6e-7,  # a forced orbit's flow map (RK4 grid, switches located), per grid step
    "switch": 3e-6,  # a located switch of the forced kernels (root bisection, saltation)
    "flow_step": 3e-6,  # the compiled orbit flow (Dormand-Prince with sensitivities), per step
    "flow_run": 1e-3,  # a compiled orbit flow over a cycle or two (a grazing margin, a fold corrector's run)
    "flow_start": 2e-5,  # any orbit flow, however short (setting up, the first phase)
    "exact_flow_time": 1e-5,  # the closed-form orbit flow, per time unit flowed
    "compiled_flow_time": 3e-5,  # the compiled orbit flow (with sensitivities), per time unit flowed
    "smooth_flow_time": 1e-3,  # scipy's orbit flow (user laws), per time unit flowed
    # a structure's steady sliding at one parameter value (model rebuilt and validated, assembled, linearised):
    # 2e-4 s on the 2-dof Hoffmann model, plus the eigenvalues of the 2n x 2n Jacobian (numpy's eig: 3.8e-8 s
    # times (2n)^3 at 2n = 200, all threads counted)
    "structure_point": 5e-4,
    # a located switch of the exact structure engine: its phase set-up, event walk and stick rule (about 0.25 ms
    # at n = 10 on this machine, rounded up), plus the eigen-decomposition of a new mode combination, which grows
    # as n^3 (35 ms a switch at n = 100 measured)
    "structure_switch": 1e-3,
    "structure_switch_cube": 4e-8,
    "eig_cube": 5e-8,
}
#: switches per unit time a forced kernel is assumed to locate: a stick-slip cycle has two per natural period,
#: chattering a few more; a bound for the estimate, not a count (the motion decides)
SWITCHES_PER_TIME = 4.0 / (2.0 * math.pi)
#: the time limit unless a caller sets one: about an hour of computing
DEFAULT_SECONDS = 3600.0

GIB = 2.0**30


@dataclass(frozen=True)
class Estimate:
    """The cost of a run or a study, before it starts.

    Attributes
    ----------
    work:
        How much work, in ``unit`` (e.g. 5e10).
    unit:
        What the work counts (e.g. "RK4 steps", "points").
    seconds:
        CPU seconds on one core.
    memory:
        Bytes held at once.
    outputs:
        (name, path, bytes) of each file written, ``name`` the option or
        argument that gave its path.
    cores:
        Cores the work is shared over.
    """

    work: float
    unit: str
    seconds: float
    memory: float = 0.0
    outputs: tuple[tuple[str, str, float], ...] = ()
    cores: int = 1

    @property
    def wall(self) -> float:
        """Seconds of the run's wall clock, its CPU seconds over its cores."""
        return self.seconds / max(self.cores, 1)

    def then(self, other: "Estimate") -> "Estimate":
        """This work, then ``other`` (its unit kept; memory: the larger of the two)."""
        return replace(self, seconds=self.seconds + other.seconds, memory=max(self.memory, other.memory),
                       outputs=self.outputs + other.outputs)

    def times(self, n: float, unit: str | None = None) -> "Estimate":
        """``n`` of this work, one after another (per ``unit`` when given, e.g. "per point")."""
        return replace(self, work=self.work * n, seconds=self.seconds * n,
                       unit=self.unit if unit is None else f"{self.unit} {unit}")

    def writing(self, path: str | Path | None, size: float, name: str = "out") -> "Estimate":
        """This work, also writing ``size`` bytes to ``path`` (None: nothing), given as option ``name``."""
        return self if path is None else replace(self, outputs=self.outputs + ((name, str(path), float(size)),))

    def text(self) -> str:
        """One phrase: the work, the time, and what is large (memory, outputs)."""
        cores = f" on {self.cores} cores" if self.cores > 1 else ""
        parts = [f"{self.work:.3g} {self.unit}", f"about {duration(self.wall)}{cores}"]
        if self.memory >= 0.1 * GIB:
            parts.append(f"{size(self.memory)} in memory")
        parts += [f"{Path(path).name} {size(b)}" for _, path, b in self.outputs if b >= 2**20]
        return ", ".join(parts)


def duration(seconds: float) -> str:
    """``seconds`` in the unit that reads best (s, min, h, days, years)."""
    for unit, length in (("years", 365.25 * 86400), ("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= length:
            return f"{seconds / length:.3g} {unit}"
    return f"{seconds:.2g} s"


def size(n: float) -> str:
    """``n`` bytes in the binary unit that reads best."""
    for unit, length in (("TiB", 2.0**40), ("GiB", GIB), ("MiB", 2.0**20), ("KiB", 2.0**10)):
        if n >= length:
            return f"{n / length:.3g} {unit}"
    return f"{n:.0f} B"


@dataclass(frozen=True)
class Limits:
    """What a run may cost.

    Attributes
    ----------
    seconds:
        Wall seconds (the CPU seconds over the work's cores).
    memory:
        GiB held at once.
    disk:
        Whether every output must fit the free space of its disk.
    lift:
        What lifts the limits (said when refusing, e.g. ``--no-limit``).
    """

    seconds: float = DEFAULT_SECONDS
    memory: float = math.inf
    disk: bool = True
    lift: str = "limits=None"


@dataclass
class _State:
    limits: Limits | None
    accepted: Estimate | None = None
    #: the stage the accepted estimate leaves out, to be estimated once it is known (``enforce_stage``)
    open_stage: str | None = None


_STATE: ContextVar[_State | None] = ContextVar("frictionflow_limits", default=None)


@contextmanager
def limited(limits: Limits | None) -> Iterator[None]:
    """Put ``limits`` in force for the work done inside.

    Parameters
    ----------
    limits:
        The limits; None: no limit, but the estimate is still shown.
    """
    token, shown = _STATE.set(_State(limits)), ESTIMATE.set(None)
    try:
        yield
    finally:
        ESTIMATE.reset(shown)
        _STATE.reset(token)


def free_space(path: str | Path) -> float:
    """Bytes free on the disk ``path`` would be written to (its nearest existing ancestor's)."""
    p = Path(path).absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    return float(shutil.disk_usage(p).free)


def refusal(est: Estimate, limits: Limits) -> str | None:
    """Why ``est`` is above ``limits`` (one line with the estimate and what lifts it), or None.

    Parameters
    ----------
    est:
        The estimated cost.
    limits:
        The limits it is held to.
    """
    if est.memory > limits.memory * GIB:
        return (f"estimated {est.text()}: needs {size(est.memory)} in memory but max_memory={limits.memory:g} GiB; "
                "raise max_memory or make the run shorter")
    for name, path, need in est.outputs if limits.disk else ():
        free = free_space(path)
        if need > free:
            return (f"{name}: {path!r} would need about {size(need)} but its disk has {size(free)} free: no space left "
                    f"on device (estimated {est.text()}); write it elsewhere, make the work smaller, or pass {limits.lift}")
    if not est.wall <= limits.seconds:
        return (f"estimated {est.text()}, above the limit of {duration(limits.seconds)}: make the work smaller, "
                f"or pass {limits.lift} to run it anyway")
    return None


def enforce(estimate: Estimate | Callable[[], Estimate] | None, open_stage: str | None = None) -> None:
    """Compare ``estimate`` (None: not known) with the limits in force; ValueError (one line) if above them.

    The first estimate accepted inside :func:`limited` is the work's: the
    runs it is made of are not checked again, and the progress bars show it.
    Outside :func:`limited`, nothing is compared (a callable ``estimate`` is
    not even called: for the runs of a study, which need none).

    Parameters
    ----------
    estimate:
        The cost, a callable that computes it, or None (not known).
    open_stage:
        The name of a later stage of the same work that ``estimate`` leaves
        out because its cost is not known yet; ``enforce_stage`` checks
        it when it is (only if this estimate is the one accepted).
    """
    state = _STATE.get()
    if state is None or estimate is None or state.accepted is not None:
        return
    if callable(estimate):
        estimate = estimate()
    _check(state, estimate)
    state.accepted, state.open_stage = estimate, open_stage
    ESTIMATE.set(estimate.text())


def enforce_stage(stage: str, estimate: Estimate | Callable[[], Estimate]) -> None:
    """Compare the later ``stage`` of the work with the limits in force, now that its cost is known.

    Only a stage the accepted estimate left open (:func:`enforce`'s
    ``open_stage``) is compared: inside a study, whose estimate covers its
    runs and all their stages, nothing is.  The stage is held to the limits
    alone (the work before it is done); the progress bars then show both.

    Parameters
    ----------
    stage:
        The name given as ``open_stage`` when the work was first estimated.
    estimate:
        The stage's cost, or a callable that computes it.
    """
    state = _STATE.get()
    if state is None or state.accepted is None or state.open_stage != stage:
        return
    if callable(estimate):
        estimate = estimate()
    _check(state, estimate)
    state.open_stage = None
    ESTIMATE.set(f"{state.accepted.text()}, then {estimate.text()}")


def _check(state: _State, estimate: Estimate) -> None:
    """ValueError (one line) if ``estimate`` is above the limits of ``state`` (none: never)."""
    if state.limits is not None:
        why = refusal(estimate, state.limits)
        if why:
            raise ValueError(why)


def located_run(steps: float, span: float, per_step: str, omega: float = 1.0) -> Estimate:
    """A run over ``span`` time units on a grid of ``steps`` RK4 steps (cost per step: key ``per_step`` of
    :data:`SECONDS_PER`) whose switches are located between the grid points.

    The switches are a bound, not a count: :data:`SWITCHES_PER_TIME`, times
    the forcing frequency ``omega`` when it is above the natural one.
    """
    switches = span * SWITCHES_PER_TIME * max(1.0, omega)
    return Estimate(steps, f"RK4 steps and up to {switches:.3g} switches",
                    steps * SECONDS_PER[per_step] + switches * SECONDS_PER["switch"])
