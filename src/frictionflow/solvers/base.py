"""The contract every solver satisfies.

A solver is a small immutable strategy object: it validates its settings in
``__init__`` and its :meth:`Solver.solve` turns (model, friction law, initial
state, end time) into a :class:`~frictionflow.trajectory.Trajectory` whose
``work`` columns it integrated itself.  What it is and supports it declares
(:class:`Solver`'s class attributes); sweeps, the classification and
``Trajectory.at`` read the declarations, never its name.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any, Callable, ClassVar, Mapping

import numpy as np

from .. import _validate as check
from ..core.layout import FEX, N_WORK, OMEGA, PHI, VB_AMP, VB_OMEGA, VB_PHI
from ..core.records import N_CONTACTS, N_STATE, Events, Samples, empty_events, empty_samples
from ..estimate import SECONDS_PER, Estimate
from ..friction.base import FrictionLaw
from ..parameters import Param, Sealed, resolve
from ..modes import SwitchMode
from ..params import BeltOscillator
from ..trajectory import Trajectory
from .events import switch_modes


#: what one kept sample costs: t, X, X', F_c, mode, the work integrals, one event slot
BYTES_PER_SAMPLE = 4 * 8 + 1 + N_WORK * 8 + 2 * 8
#: memory a run's samples may take unless the caller says otherwise (GiB)
DEFAULT_MAX_MEMORY = 4.0
#: RK4 steps per period (a forcing period, a renormalisation block) of the flow-map and tangent runs unless told
RK4_STEPS = 512
#: the longest default RK4 step: a period longer than RK4_STEPS of these takes twice the steps, or four times, ...
#: (512 steps a period up to Omega = 1/8, so nothing changes above it)
RK4_MAX_STEP = 2.0 * math.pi / 64.0


def rk4_steps(period: float, steps: int | None = None) -> int:
    """RK4 steps per ``period``: ``steps`` if given, else :data:`RK4_STEPS` doubled until a step is at most
    :data:`RK4_MAX_STEP`.  The slip phases' accuracy is set by the oscillator's own time scale 2 pi, not the
    forcing's: 512 steps per forcing period at Omega = 0.01 are steps of 1.2, and the Floquet multipliers came
    out four decades small.  Doubling (not a step count proportional to the period) keeps one grid over a wide
    range of Omega, so that a branch and the orbits found point by point on it share theirs."""
    if steps is not None:
        return steps
    n = RK4_STEPS
    while float(period) / n > RK4_MAX_STEP * (1.0 + 1e-12):
        n *= 2
    return n


def kernel_params(model: BeltOscillator, friction: FrictionLaw) -> np.ndarray:
    """The kernels' force record (:mod:`frictionflow.core.layout`): the law's slots and the external force's."""
    p = friction.kernel_params()
    if not (model.forced or model.belt_varies):
        return p
    p = p.copy()
    if model.forced:
        p[FEX], p[OMEGA], p[PHI] = model.fex, model.omega, model.phi
    if model.belt_varies:
        p[VB_AMP], p[VB_OMEGA], p[VB_PHI] = model.vb_amplitude, model.vb_omega, model.vb_phi
    return p


def flag(name: str, value: Any) -> bool:
    """``value`` as a bool; it must be True or False (a numpy bool too): a TypeError naming ``name`` otherwise.

    ``bool(value)`` would take "no", nan, [0.1] or -1 for True.
    """
    check.instance(name, value, (bool, np.bool_), "True or False")
    return bool(value)


def check_memory(samples: float, max_memory: float, what: str | Callable[[], str],
                 row: float = BYTES_PER_SAMPLE) -> None:
    """Refuse, with the numbers and the settings that would fix it, a run whose samples exceed ``max_memory`` GiB.

    ``what`` names the run by the settings its size follows (:meth:`Solver.sized`; a callable is
    called only to say so); ``row`` is the bytes of one sample (the single mass's by default).
    """
    need = samples * row / 2**30
    if need > max_memory:
        raise ValueError(
            f"{what() if callable(what) else what} needs about {samples:.3g} samples ({need:.3g} GiB) "
            f"but max_memory={max_memory:g} GiB: shorten the run, sample it less densely, or raise max_memory"
        )


def run_growing(kernel: Callable[[tuple[Samples, Events]], tuple], cap: int,
                full: Callable[[tuple, tuple[Samples, Events]], bool],
                max_memory: float, what: str | Callable[[], str]) -> tuple[tuple, tuple[Samples, Events]]:
    """Run ``kernel(buffers)`` with room for ``cap`` samples, four times more each time it reports them ``full``.

    An event-driven run cannot know its number of samples in advance; a retry
    costs at most a third of the run again.  ``buffers`` are the records of
    :func:`output_buffers`.  Returns the kernel's result and the buffers.
    """
    while True:
        check_memory(cap, max_memory, what)
        buffers = output_buffers(cap)
        result = kernel(buffers)
        if not full(result, buffers):
            return result, buffers
        cap *= 4


class CoarseStepWarning(UserWarning):
    """The fixed step is too coarse for the stick band or for RK4's stability."""


class Solver(Sealed, ABC):
    """Base class of solvers.

    What a solver is and supports it declares here: nothing outside
    ``frictionflow.solvers`` compares solver names.

    Class attributes a solver sets
    ------------------------------
    name:
        Registry name (``--solver NAME``).
    refusal_reason:
        Why it refuses the laws it does not support, appended to :meth:`solve`'s one line ("" for none).
    interpolant:
        How :meth:`Trajectory.at <frictionflow.Trajectory.at>` evaluates its runs between
        samples: a key of ``frictionflow._continuous.FORMS`` (the closed form, quintic or cubic Hermite).
    steady_rtol:
        The steady-state classification's default ``rtol`` for its runs (what it resolves orbits to).
    fixed_step:
        It steps at a fixed dt through a stick band: it does not locate switches, its sample
        count follows t_end / dt, and its section values jitter from cycle to cycle.
    refine_between_samples:
        Its samples need not hold the turns of X', of the transmitted force or a threshold stick's boundaries
        (its laws are smooth): the analysis finds V's extremes, TR_B and the stick share between them on the
        cubic Hermite interpolant (``frictionflow.analysis.between_samples``).
    default_chunk:
        Points per sweep chunk (about 0.2 s of work on a core); see :meth:`chunk_points`.
    batched:
        The batched kernel of ``frictionflow.core.batch`` sweeps run unforced points through
        (:meth:`run_points`), or None: a sweep then takes only laws with internal states, each point
        one ``simulate`` and ``analyze`` on numba's threads.
    batched_forced:
        The batched kernel forced sweep points run through (:meth:`run_forced_points`), or None:
        they then run one ``simulate`` and ``analyze`` each.
    supports_forcing:
        It integrates an external force f(tau) (:meth:`forcing_problem` names the exceptions).
    supports_belt_motion:
        It integrates a belt whose speed varies in time, V_b(tau) (``BeltOscillator.belt_varies``);
        :meth:`belt_motion_problem` names the laws it still refuses there.
    auto_belt_motion:
        ``solver=auto`` may pick it for such a belt.
    structure_laws:
        For linear structures with friction contacts (:func:`frictionflow.solvers.structure.simulate_system`):
        a test of a law class, true for the laws this solver runs at a structure's contacts; None: it
        does not run structures.
    structure_free_motion:
        It runs a structure with an undamped free motion: a direction no spring, damper or normal load holds
        (a mass on a belt without a spring), whose motion is polynomial in time, not exponential.
    step_cost, point_cost_per:
        Its cost model: the keys of ``frictionflow.estimate.SECONDS_PER`` of a step of a
        single run, and of a sweep point's work per unit of time (:meth:`cost`, :meth:`point_cost`).
    """

    name: str = "abstract"
    refusal_reason: ClassVar[str] = ""
    #: its settings, declared once (CLI options, config keys); ``keywords`` maps them to ``__init__``
    parameters: ClassVar[tuple[Param, ...]] = ()
    keywords: ClassVar[dict[str, str]] = {}
    interpolant: ClassVar[str] = "cubic_hermite"
    steady_rtol: ClassVar[float] = 1e-6
    fixed_step: ClassVar[bool] = False
    refine_between_samples: ClassVar[bool] = False
    default_chunk: ClassVar[int] = 256
    batched: ClassVar[Callable[..., None] | None] = None
    batched_forced: ClassVar[Callable[..., np.ndarray] | None] = None
    supports_forcing: ClassVar[bool] = True
    supports_belt_motion: ClassVar[bool] = False
    auto_belt_motion: ClassVar[bool] = True
    step_cost: ClassVar[str] = "adaptive_step"
    point_cost_per: ClassVar[str] = "adaptive_point_time"
    structure_laws: ClassVar[Callable[[type[FrictionLaw]], bool] | None] = None
    structure_free_motion: ClassVar[bool] = False

    def belt_motion_problem(self, friction: FrictionLaw) -> str | None:
        """Why it cannot run a belt whose speed varies under ``friction``, or None (the one line of every refusal)."""
        if not self.supports_belt_motion:
            return f"solver={self.name} does not run a belt whose speed varies (vb_amplitude > 0)"
        return None

    def runs_belt_motion(self, friction: FrictionLaw) -> bool:
        """Whether it runs a belt whose speed varies under ``friction`` (:meth:`belt_motion_problem` has none)."""
        return self.belt_motion_problem(friction) is None

    @classmethod
    def from_values(cls, values: Mapping[str, Any]) -> "Solver":
        """Build from a mapping of parameter values (missing or None: the declared defaults)."""
        resolved = resolve(cls.parameters, values)
        return cls(**{cls.keywords.get(k, k): v for k, v in resolved.items()})

    def solve(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, t_end: float,
              progress: bool = False, max_memory: float = DEFAULT_MAX_MEMORY) -> Trajectory:
        """Integrate from (x0, v0) at tau = 0 to ``t_end``, keeping at most ``max_memory`` GiB of samples.

        Every solver's: the law is refused here, in one line, when the solver does not declare it
        (:meth:`supports`); ``_solve`` integrates.
        """
        if not self.supports(friction):
            raise ValueError(f"solver={self.name} does not support friction={friction.name}{self.refusal_reason}")
        return self._solve(model, friction, x0, v0, t_end, flag("progress", progress), max_memory)

    @abstractmethod
    def _solve(self, model: BeltOscillator, friction: FrictionLaw, x0: float, v0: float, t_end: float,
               progress: bool, max_memory: float) -> Trajectory:
        """:meth:`solve` for a law the solver supports."""

    def supports(self, friction: FrictionLaw) -> bool:
        """Whether this solver can integrate ``friction`` (from the law's declared capabilities)."""
        return True

    def forcing_problem(self, zeta: float, omega: float, fex: float) -> str | None:
        """Why this solver cannot run the forced model (zeta, omega, fex), or None."""
        return None if self.supports_forcing or fex == 0.0 else f"solver={self.name} does not run an external force"

    @classmethod
    def section_noise(cls, settings: Mapping[str, Any]) -> float:
        """Relative error of a section value of a run with ``settings`` (its ``describe()``): below it
        repetition cannot be judged (0: not known)."""
        return 0.0

    def chunk_points(self, t_end: float) -> int:
        """Points per sweep chunk for runs to ``t_end``."""
        return self.default_chunk

    def run_points(self, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray,
                   t_end: float, rtol: float, min_periods: int, out: np.ndarray) -> None:
        """Fill ``out`` (a row per point) through ``batched`` with this solver's settings."""
        raise NotImplementedError(f"solver={self.name} has no batched kernel for sweeps")

    def run_forced_points(self, p: np.ndarray, zeta: np.ndarray, vb: np.ndarray, x0: np.ndarray, v0: np.ndarray,
                          t_end: float, rtol: float, friction: FrictionLaw, out: np.ndarray) -> np.ndarray:
        """Fill ``out`` for forced points through ``batched_forced``; returns which points it left to
        the façade (all of them without a batched kernel)."""
        return np.ones(len(zeta), dtype=bool)

    def sample_estimate(self, t_end: float, model: BeltOscillator | None = None) -> int:
        """Room for the samples of a run to ``t_end`` (a first guess: event-driven runs grow it)."""
        raise NotImplementedError

    def step_estimate(self, t_end: float, model: BeltOscillator, friction: FrictionLaw) -> float:
        """Steps of a run to ``t_end``: one per kept sample unless the solver says otherwise."""
        return float(self.sample_estimate(t_end, model))

    def cost(self, model: BeltOscillator, friction: FrictionLaw, t_end: float) -> Estimate:
        """The estimate of one run to ``t_end``: its steps, their time, its samples' memory."""
        steps = self.step_estimate(t_end, model, friction)
        return Estimate(steps, f"{self.name} steps", steps * SECONDS_PER[self.step_cost],
                        float(self.sample_estimate(t_end, model)) * BYTES_PER_SAMPLE)

    def point_cost(self, model: BeltOscillator, friction: FrictionLaw, t_end: float) -> Estimate:
        """The estimate of one unforced sweep point to ``t_end`` in the batched kernel (no samples kept).

        A bound: a point stops once its steady state is settled.
        """
        return Estimate(t_end, "time units", t_end * SECONDS_PER[self.point_cost_per])

    def describe(self) -> dict[str, Any]:
        """Name and settings, for reports and JSON."""
        return {"name": self.name}

    def sized(self, t_end: float) -> str:
        """The run's length and the settings its number of samples follows (for messages)."""
        sampling = {k: v for k, v in self.describe().items() if k in ("dt", "dense_dt", "record_every") and v is not None}
        return f"t_end={t_end:g} with solver={self.name}" + "".join(f", {k}={v:g}" for k, v in sampling.items())

    def __repr__(self) -> str:
        d = self.describe()
        args = ", ".join(f"{k}={v!r}" for k, v in d.items() if k != "name")
        return f"{type(self).__name__}({args})"


def output_buffers(cap: int) -> tuple[Samples, Events]:
    """The records an event-driven kernel writes into (:mod:`frictionflow.core.records`), room for ``cap`` of each."""
    return (empty_samples(cap, N_STATE, N_CONTACTS),
            empty_events(cap))


def trajectory_from(
    buffers: tuple[Samples, Events],
    n: int,
    n_events: int,
    model: BeltOscillator,
    friction: FrictionLaw,
    solver: dict[str, Any],
    extra: dict[str, Any] | None = None,
    *,
    event_modes: Mapping[int, SwitchMode],
) -> Trajectory:
    """A :class:`Trajectory` of the first ``n`` samples and ``n_events`` events in ``buffers`` (:func:`output_buffers`).

    ``event_modes`` is the solver's table from its kernel's mode codes to
    :class:`SwitchMode` (see :mod:`.events`): the events leave the solver in
    public values only.
    """
    (t, y, fc, mode, work), (ev_t, ev_mode, _) = buffers  # the single mass: every event is contact 0's
    return Trajectory(
        t=t[:n].copy(), state=y[:, :n].copy(), force=fc[:, :n].copy(), modes=mode[:, :n].copy(), dwork=work[:n].copy(),
        model=model, friction=friction, solver=solver,
        events={"t": ev_t[:n_events].copy(), "mode": switch_modes(ev_mode[:n_events], event_modes)},
        extra=extra or {},
    )
