"""Find the steady state of a run instead of assuming it.

Three outcomes:

``periodic``
    The maxima and minima of X on the section X' = 0 have repeated, with the
    same period, to within ``rtol`` for at least ``min_periods`` periods.  The
    window is the whole number of trailing periods that repeat, cut at the
    section (at the first sample after each crossing).  Fixed-step runs
    through a stick band jitter from cycle to cycle -- where the step lands
    relative to the band edge changes every cycle -- so for them a sequence
    with no significant trend over at least 8 periods is accepted, and its
    relative spread reported as ``jitter``.
``equilibrium``
    X and X' have stopped moving (spread below ``rtol``) over the tail, the
    last 10 % of the run (at least 4 pi).
``not_settled``
    Neither.  The amplitude's measured exponential rate (``decay_rate`` > 0:
    decaying, < 0: growing) and where the sequence is heading (Aitken
    extrapolation of the last amplitudes and centres) are reported; the
    window is the last whole period, or the tail.

The decision itself is :func:`frictionflow.core.sections.classify`, shared
with the batched kernels.

A forced run (F_ex > 0) is judged on the stroboscopic section instead, with
the kinds ``periodic`` (period m 2 pi / Omega), ``quasi_periodic``,
``chaotic`` and ``not_settled``: :mod:`.forced`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import Any, Mapping

import numpy as np

from .. import quantities as Q
from .._display import Row, Summarized, num, pairs
from ..core import certificate
from ..core import sections as sec
from ..solvers.registry import solver_classes, solver_named
from .. import _validate as check
from ..trajectory import Trajectory
from .between_samples import refines, stick_share
from .equilibrium import sliding_equilibrium
from .forced import classify_forced, internal_scaled, largest_exponent

KINDS = Q.KINDS
HEADINGS = {sec.HEAD_NONE: None, sec.HEAD_EQUILIBRIUM: "equilibrium", sec.HEAD_PERIODIC: "periodic", sec.HEAD_GROWING: "growing"}


@dataclass(frozen=True, repr=False)
class SteadyState(Summarized):
    """What the run settled on, and the window to average over.

    Its ``repr`` (and ``_repr_html_`` in a notebook) shows the fields that are
    set, in significant digits; :meth:`to_dict` has every field exactly.

    Attributes
    ----------
    kind:
        ``periodic``, ``equilibrium``, ``not_settled`` or ``diverged``;
        forced runs also ``quasi_periodic`` or ``chaotic``.
    window:
        (t0, t1), the window the averages are taken over.
    period:
        The period of a periodic steady state (else None).
    n_periods:
        How many periods (forced: repetitions of the section) repeat at the
        end of the run.
    decay_rate:
        Not settled: the rate at which the amplitude decays (negative: grows).
    heading:
        Not settled: where the motion is heading (``equilibrium``,
        ``periodic``, ``growing``), or None: also for a decay too slow for
        its last amplitudes to tell (a limit cycle would lie beyond ten
        times their own change; near a Hopf point, say).
    limit:
        Where it is heading or resting: ``{"x": X*}`` for an equilibrium,
        ``{"amplitude", "x_center"}`` of the limit cycle by Aitken
        extrapolation; None otherwise.
    manual_window:
        True when the window was given (``window=``), not detected.
    stability:
        ``stable``, ``unstable`` or ``neutral`` where the solver knows it
        (the equilibrium's linear stability), else None.
    stick_fraction:
        The fraction of the window the mass spends sticking.
    jitter:
        Fixed-step RK4 through a stick band: the spread of the section
        values accepted as periodic.
    forcing_multiple:
        Forced and periodic: the period in forcing periods, m.
    lyapunov:
        Forced: the largest Lyapunov exponent, where the classification
        needed it.
    forced:
        Whether the run was forced (the keys its report carries).
    """

    kind: str
    window: tuple[float, float]
    period: float | None = None
    n_periods: int = 0
    decay_rate: float | None = None
    heading: str | None = None
    limit: dict[str, float] | None = None
    manual_window: bool = False
    stability: str | None = None
    stick_fraction: float | None = None
    jitter: float | None = None
    # forced runs: the period in forcing periods, and the largest Lyapunov exponent where it was needed
    forcing_multiple: int | None = None
    lyapunov: float | None = None
    forced: bool = False

    def _summary(self) -> tuple[str, list[Row]]:
        kind = ", ".join(x for x in (self.kind, self.stability) if x)
        rows = [("kind", kind + (" (window set by hand)" if self.manual_window else "")),
                ("window", f"tau {num(self.window[0])} .. {num(self.window[1])}")]
        if self.period is not None:
            rows.append(("period", f"{num(self.period, 8)} ({self.n_periods} in the window)"))
        if self.forcing_multiple:
            rows.append(("forcing periods", str(self.forcing_multiple)))
        optional = (("decay rate", self.decay_rate, 4), ("stick fraction", self.stick_fraction, 4),
                    ("jitter", self.jitter, 2), ("Lyapunov exponent", self.lyapunov, 3))
        rows += [(label, num(value, digits)) for label, value, digits in optional if value is not None]
        if self.heading:
            rows.append(("heading", self.heading))
        if self.limit:
            rows.append(("limit", pairs(self.limit)))
        return "SteadyState", rows

    def to_dict(self) -> dict[str, Any]:
        """Every field exactly, JSON-ready (the window a list)."""
        d = asdict(self)
        d["window"] = [float(self.window[0]), float(self.window[1])]
        del d["forced"]
        if not self.forced:  # the autonomous system's report keeps its keys
            del d["forcing_multiple"], d["lyapunov"]
        return d


def _opt(x: float) -> float | None:
    return None if np.isnan(x) else float(x)


def from_classification(cls: np.ndarray, summary: np.ndarray) -> SteadyState:
    """A :class:`SteadyState` from the arrays of :func:`~frictionflow.core.sections.classify`."""
    kind = KINDS[int(cls[sec.C_KIND])]
    head = HEADINGS[int(cls[sec.C_HEAD])]
    limit = None
    if kind == "equilibrium" or head == "equilibrium":
        limit = {"x": float(cls[sec.C_LIMX])}
    elif head == "periodic":
        limit = {"amplitude": float(cls[sec.C_LIMA]), "x_center": float(cls[sec.C_LIMX])}
    return SteadyState(
        kind=kind,
        window=(float(summary[sec.S_T0]), float(summary[sec.S_T1])),
        period=_opt(cls[sec.C_PERIOD]) if kind == "periodic" else None,
        n_periods=int(cls[sec.C_NPER]),
        decay_rate=_opt(cls[sec.C_DECAY]) if kind == "not_settled" else None,
        heading=head if kind == "not_settled" else None,
        limit=limit,
        stick_fraction=_opt(summary[sec.S_STICK]),
        jitter=_opt(cls[sec.C_JITTER]),
    )


#: convergence tolerance of the steady-state test, by solver: each solver's declared
#: ``steady_rtol`` (fixed-step RK4 resolves orbits to about 1e-6, the adaptive solver
#: to its rtol, the exact solver to rounding); kept as a table for existing callers
DEFAULT_RTOL = {cls.name: cls.steady_rtol for cls in solver_classes()}


def default_rtol(solver: Mapping[str, Any]) -> float:
    """The classification's rtol for a run whose ``solver`` record this is (1e-6 for an unknown solver)."""
    cls = solver_named(solver.get("name"))
    return 1e-6 if cls is None else cls.steady_rtol


def section_noise(solver: Mapping[str, Any]) -> float:
    """The solver's relative error in a section value: below it repetition cannot be judged.

    What the solver the record names declares (``Solver.section_noise``); 0 for an unknown solver.
    """
    cls = solver_named(solver.get("name"))
    return 0.0 if cls is None else cls.section_noise(solver)


def _fixed_step(solver: Mapping[str, Any]) -> bool:
    """Does the solver of this record step at a fixed dt (its sections jitter)?  An unknown one: if it has a dt."""
    cls = solver_named(solver.get("name"))
    return "dt" in solver if cls is None else cls.fixed_step


def classify_trajectory(traj: Trajectory, rtol: float = 1e-6, min_periods: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Section records of ``traj`` classified; returns (classification, window summary).

    Only the last :data:`~frictionflow.core.sections.MAX_RECORDS` records
    count, as in the batched kernels, so both paths give the same answer.
    A law's internal states are part of the state the section compares
    (:func:`internal_sections`).
    """
    t_tail = sec.tail_start(float(traj.t[0]), float(traj.t[-1]))
    rec, tail, fin = sec.records_from_samples(traj.t, traj.x, traj.v, traj.mode, traj.dwork, traj.zeta, t_tail)
    rec = np.ascontiguousarray(rec[-sec.MAX_RECORDS :])
    scale = sec.scale_of(rec, tail, traj.vb, traj.friction.fd)
    h = float(np.max(np.diff(traj.t))) if len(traj) > 1 else 0.0
    judge = (scale, rtol, min_periods, h, _fixed_step(traj.solver), section_noise(traj.solver) * scale)
    if traj.internal is None:
        cls = sec.classify(rec, tail, *judge)
    else:
        zs, spread = internal_sections(traj, t_tail)
        cls = sec.classify_state(rec, np.ascontiguousarray(zs[-sec.MAX_RECORDS :]), spread, tail, *judge)
    return cls, sec.window_summary(rec, tail, fin, cls, traj.friction.fd, traj.vb)


def internal_sections(traj: Trajectory, t_tail: float) -> tuple[np.ndarray, float]:
    """(the scaled internal states at each downward X' = 0 crossing, one row per section record; their
    largest range over the samples from ``t_tail`` on) -- interpolated between samples as the records'
    crossing time is (:func:`frictionflow.core.sections.records_from_samples`)."""
    z = internal_scaled(traj)
    v = traj.v
    i = np.flatnonzero((v[:-1] > 0.0) & (v[1:] <= 0.0)) + 1
    s = v[i - 1] / (v[i - 1] - v[i])
    zs = (z[:, i - 1] + s * (z[:, i] - z[:, i - 1])).T
    tail = z[:, traj.t >= t_tail]
    spread = float(np.max(np.ptp(tail, axis=1))) if tail.size else 0.0
    return zs, spread


def _diverged(traj: Trajectory) -> SteadyState | None:
    """``diverged`` from the first sample whose state is not finite (the window runs from it to the end)."""
    if math.isfinite(traj.x[-1]) and math.isfinite(traj.v[-1]):  # a state that overflowed stays non-finite
        return None
    bad = ~(np.isfinite(traj.x) & np.isfinite(traj.v))
    i = int(np.argmax(bad))
    return SteadyState(kind="diverged", window=(float(traj.t[i]), float(traj.t[-1])))


def steady_state(
    traj: Trajectory,
    *,
    rtol: float = 1e-6,
    min_periods: int = 3,
    window: tuple[float, float] | None = None,
) -> SteadyState:
    """Classify the end of ``traj`` as periodic, equilibrium or not settled.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    rtol:

        Convergence tolerance relative to the motion's scale
        max(range of X, range of X', |V_b|, F_d).
    min_periods:
        Number of consecutive repeated periods a periodic orbit needs.
    window:
        ``(t0, t1)`` to average over instead of the detected window; the kind
        is still the detected one.
    """
    return classified_steady_state(traj, rtol=rtol, min_periods=min_periods, window=window)[0]


def classified_steady_state(traj: Trajectory, *, rtol: float = 1e-6, min_periods: int = 3,
                            window: tuple[float, float] | None = None) -> tuple[SteadyState, np.ndarray | None]:
    """:func:`steady_state`, and the window summary of the section records where they decided it (unforced, the
    window not given: :func:`~frictionflow.core.sections.window_summary`, the table layout), else None.

    The summary's extremes of X are the records' (cubic Hermite at the turns of X, between samples): what the
    batched sweeps report, whose lanes keep no samples.
    """
    check.instance("traj", traj, Trajectory, "a Trajectory (from simulate)")
    if isinstance(rtol, bool) or not isinstance(rtol, (int, float)) or not 0.0 < rtol < 1.0:
        raise ValueError(f"rtol must be a number in (0, 1), got {rtol!r}")
    min_periods = check.positive_int("min_periods", min_periods)  # an int: the kernels compile for one type
    if window is not None:
        window = traj.checked_window(window)
    found, summary = _diverged(traj), None
    if found is not None:
        return found, None
    if traj.model.driven:
        found = _forced(traj, rtol, min_periods)
    else:
        found = _terminal(traj) or _certified(traj)
    if found is None:
        cls, summary = classify_trajectory(traj, rtol, min_periods)
        found = from_classification(cls, summary)
        if _threshold_stick(traj) and found.stick_fraction is not None:
            found = replace(found, stick_fraction=stick_fraction(traj, found.window))
        found = _with_internal(traj, found)
        found = replace(found, stability=_stability(traj, found))
    if window is None:
        return found, summary
    t0, t1 = window
    return replace(found, window=(t0, t1), manual_window=True, stick_fraction=stick_fraction(traj, (t0, t1))), None


def _with_internal(traj: Trajectory, found: SteadyState) -> SteadyState:
    """An equilibrium of a law with internal states: where they rest too (the run's last values) in
    ``limit``; resting sliding, the decay rate of the whole state's linearisation (as a certified one's)."""
    if traj.internal is None or found.kind != "equilibrium":
        return found
    limit = {**(found.limit or {}), **dict(zip(traj.internal_names, map(float, traj.internal[:, -1])))}
    rate = None if found.stick_fraction else sliding_equilibrium(traj.model, traj.friction).decay_rate
    return replace(found, limit=limit, decay_rate=rate)


def _forced(traj: Trajectory, rtol: float, min_periods: int) -> SteadyState:
    """The forced run's steady state on the stroboscopic section (:func:`.forced.classify_forced`); a moving belt's
    on its own period's, refused (ValueError) when it and an external force have none in common."""
    problem = traj.model.section_problem()
    if problem is not None:
        raise ValueError(problem)
    c = classify_forced(traj, rtol, min_periods, section_noise(traj.solver), lyapunov=largest_exponent)
    found = SteadyState(kind=c["kind"], window=c["window"], period=c["period"], n_periods=c["n_periods"],
                        stick_fraction=stick_fraction(traj, c["window"]), forcing_multiple=c["multiple"],
                        lyapunov=c["lyapunov"], jitter=c["jitter"], forced=True)
    return replace(found, stability=_stability(traj, found))


def _terminal(traj: Trajectory) -> SteadyState | None:
    """The analytic verdict of a solver that knows the run has entered its final slip phase.

    From a slip phase that can never again reach the stick boundary, a
    damped oscillator with a constant slip force decays onto the sliding
    equilibrium however short the run.  (Undamped, it circles for ever: that
    case is left to the section records, which find it periodic.)
    """
    t_term = traj.extra.get("t_terminal")
    if t_term is None or traj.extra.get("terminal_mode", 0) == 0:
        return None
    eq = sliding_equilibrium(traj.model, traj.friction)
    if eq.stability != "stable":
        return None
    return SteadyState(
        "equilibrium",
        (float(t_term), float(traj.t[-1])),
        decay_rate=eq.decay_rate,
        limit={"x": eq.x},
        stability="stable",
        stick_fraction=0.0,
    )


def _certified(traj: Trajectory) -> SteadyState | None:
    """``equilibrium`` by the energy certificate: the run ends inside the certified disc about X*.

    From inside the disc (:mod:`frictionflow.core.certificate`) the motion
    provably converges onto X* without sticking again; the window starts where
    the run entered it for good.
    """
    if traj.mode[-1] != np.sign(traj.vb):  # not slipping with the belt at the end
        return None
    x_eq = float(traj.friction.sliding_equilibrium(traj.vb))
    if not (traj.x[-1] - x_eq) ** 2 + traj.v[-1] ** 2 < traj.vb**2:  # no disc is larger than V_b
        return None
    r = certificate.radius(traj.friction, traj.zeta, traj.vb)
    if r <= 0.0:
        return None
    eq = sliding_equilibrium(traj.model, traj.friction)
    inside = ((traj.x - eq.x) ** 2 + traj.v**2 <= r * r) & (traj.mode == np.sign(traj.vb))
    if not inside[-1]:
        return None
    first = len(inside) - int(np.argmin(inside[::-1])) if not inside.all() else 0
    return SteadyState("equilibrium", (float(traj.t[first]), float(traj.t[-1])), decay_rate=eq.decay_rate,
                       limit={"x": eq.x}, stability="stable", stick_fraction=0.0)


def _stability(traj: Trajectory, ss: SteadyState) -> str | None:
    """Stability of what the run settled on, where it is known without Floquet analysis."""
    if ss.kind == "equilibrium":
        if ss.stick_fraction:
            return None  # resting in a stick band: not the sliding equilibrium
        return sliding_equilibrium(traj.model, traj.friction).stability
    if ss.kind == "periodic":
        if ss.stick_fraction and ss.stick_fraction > 0:
            return "stable"  # a stick phase collapses every perturbation (a zero multiplier)
        if traj.zeta == 0.0 and traj.friction.piecewise_constant and not traj.model.driven:
            return "neutral"  # one of the family of undamped slip circles
    return None


def _threshold_stick(traj: Trajectory) -> bool:
    """Is the run's stick a threshold on |V_r| whose crossings its samples need not hold?"""
    return traj.friction.stick_speed() > 0.0 and refines(traj)


def stick_fraction(traj: Trajectory, window: tuple[float, float]) -> float:
    """Share of the window spent in the stick mode (time-weighted over samples); a threshold stick's (a law with
    internal states: |V_r| below its stick speed) with its crossings between samples where the solver leaves
    them there (:func:`.between_samples.refines`)."""
    i0, i1 = traj.index(window[0]), traj.index(window[1])
    if _threshold_stick(traj):
        return stick_share(traj, slice(i0, i1 + 1))
    if i1 <= i0:
        return float(traj.mode[i0] == 0)
    dt = np.diff(traj.t[i0 : i1 + 1])
    return float(np.sum(dt * (traj.mode[i0:i1] == 0)) / np.sum(dt))
