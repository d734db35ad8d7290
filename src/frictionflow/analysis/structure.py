"""The steady state and the power flow of a structure with several masses and contacts.

A :class:`~frictionflow.motion.Motion` is judged as the single mass is, on a
section, but in the whole state: the section is the downward crossing of
q_i' = 0 for the coordinate i that moves most over the tail (a bounded
motion's velocities average to zero, so each moving coordinate crosses it),
located to rounding on the exact solution (:meth:`Motion.at`).

``periodic``
    The state at the section has repeated with some period p (in section
    crossings) for ``min_periods`` periods, to ``rtol`` of the state's size.
    The window is those whole periods.  As for the single mass's forced runs
    (:mod:`.forced`), a p whose last period repeats after a divisor d of p to
    a hundred times ``rtol`` is a d-cycle still converging, not a p-cycle: a
    multiplier near a root of unity makes the state repeat after p crossings
    before it does after d (a cycle of 3.32 time units with multipliers
    0.92 e^(+-2.4i) was reported with the period 9.96): ``not_settled``.
    With harmonic forces of one frequency Omega, a period within ten times
    ``rtol`` of m 2 pi / Omega is that (as the single mass's forced runs
    report it): a forced cycle lasts a whole number of forcing periods, and
    the crossings' mean still carries the transient's last drift.
``equilibrium``
    Every state component has stopped moving over the tail (the last tenth of
    the run, at least 4 pi of the slowest natural period's scale) and every
    velocity is zero, to ``rtol`` of the motion's scale (the ranges of its
    states); or the run's end is certified to slide into
    the steady-sliding equilibrium (:func:`certified_sliding`).
``chaotic``, ``quasi_periodic``
    The section does not repeat, and the largest Lyapunov exponent (two
    nearby exact runs) and the section's revisits tell these apart as the
    single mass's forced runs are told (:mod:`.structure_lyapunov`); the
    window is the tail.  Only for a run longer than the structure's slowest
    time scale (:func:`slowest_period`): within it a slow mode's drift is
    neither told from a growth (a heavy mass's linear drift gave a positive
    exponent) nor from a torus (a stiff damper's creep revisited the section).
``not_settled``
    None of these; the window is the tail.
``contact_lost``
    A normal load reached zero: the run ended there.  Nothing is averaged (the
    run is a transient), but the energy residual is given over the whole run up
    to the loss (0 when the load is lost at the start).

The averages are each element's powers over the window
(:meth:`Motion.element_power`), the amplitudes each coordinate's extremes
there, and the stick fraction is given per contact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..motion import Motion
from .. import _validate as check
from .. import quantities as Q
from .._json import jsonable
from .._display import Row, Summarized, num
from ..core.assembly import natural_frequencies
from ..system.assemble import fastest_rate, free_directions
from ..core.layout import LAW
from ..core.strobe import SUBCYCLE_SPREAD
from ..friction.registry import law_classes
from .forced import state_subcycle
from .stability import steady_sliding
from .structure_lyapunov import beyond_periodic


#: the kinds a structure's run is given: the shared ones (:data:`frictionflow.quantities.KINDS`) but
#: ``diverged`` (an exact linear run stays finite), and ``contact_lost``; the first four keep their codes
STRUCTURE_KINDS = (*Q.KINDS[:3], "contact_lost", *(k for k in Q.KINDS[3:] if k != "diverged"))
#: largest number of section crossings in one period that is looked for (the orbit command's --returns range: a
#: chain's cycle of several stick episodes crosses it 17 times and more)
MAX_CROSSINGS = 64
#: grid points per shortest natural period when looking for section crossings
GRID_PER_PERIOD = 64
#: the rounding the removal of a free drift leaves in the positions, in EPS of their size
DRIFT_ROUNDING = 64.0
#: natural frequencies below this share of the fastest are a rigid mode's (computed at rounding, not 0)
RIGID = 1e-6
#: evaluations a crossing's refinement takes at most, for estimates (measured: about 24 steps at t_end 1e5)
REFINE_STEPS = 32
#: Wilkinson's first-order eigenvalue bound, EPS ||A|| kappa_i, times this for the eigen-solver's own rounding
EIGEN_ROUNDING = 64.0
EPS = float(np.finfo(float).eps)


@dataclass(frozen=True, repr=False)
class StructureSteadyState(Summarized):
    """What a structure's run settled on, and the window to average over.

    Attributes
    ----------
    kind:
        One of ``STRUCTURE_KINDS``.
    period:
        The period (periodic only, else NaN).
    window:
        (t0, t1): the whole periods that repeat, or the tail.
    stick_fraction:
        Per contact, the share of the window it spends stuck.
    periods:
        How many periods the window holds (periodic only, else 0).
    lyapunov:
        The largest Lyapunov exponent where the section did not repeat and it was measured, else NaN.
    manual_window:
        True when the window was given (``window=``), not detected (as the single mass's steady state says).
    """

    kind: str
    period: float
    window: tuple[float, float]
    stick_fraction: tuple[float, ...]
    periods: int = 0
    lyapunov: float = math.nan
    manual_window: bool = False

    def _summary(self) -> tuple[str, list[Row]]:
        rows = [("kind", self.kind + (" (window set by hand)" if self.manual_window else "")),
                ("period", num(self.period)),
                ("window", f"{num(self.window[0])} .. {num(self.window[1])}"),
                ("stick fraction", ", ".join(num(s, 4) for s in self.stick_fraction))]
        if math.isfinite(self.lyapunov):
            rows.append(("Lyapunov exponent", num(self.lyapunov, 3)))
        return "StructureSteadyState", rows

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: an undefined value (a period or stick fraction where none settled) is None."""
        return jsonable({"kind": self.kind, "period": self.period, "window": list(self.window),
                         "stick_fraction": list(self.stick_fraction), "periods": self.periods,
                         "lyapunov": self.lyapunov, "manual_window": self.manual_window})


@dataclass(frozen=True, repr=False)
class StructureAnalysis(Summarized):
    """A structure's steady state, each element's average powers and each coordinate's extremes over its window.

    Attributes
    ----------
    motion:
        The run analysed.
    steady_state:
        :class:`StructureSteadyState`.
    elements:
        Element name -> its average powers over the window (``P`` for springs,
        dampers and forces: the power it puts into the structure; ``P_belt``
        and ``P_heat`` for contacts).
    amplitude:
        ``{"X_max": {dof: value}, "X_min": {dof: value}}`` over the window.
    energy_residual:
        The relative residual of the energy balance over the window.
    """

    motion: Any
    steady_state: StructureSteadyState
    elements: dict[str, dict[str, float]] = field(default_factory=dict)
    amplitude: dict[str, dict[str, float]] = field(default_factory=dict)
    energy_residual: float = math.nan

    def _summary(self) -> tuple[str, list[Row]]:
        rows = [("steady state", self.steady_state.kind), ("period", num(self.steady_state.period)),
                ("energy residual", num(self.energy_residual, 3))]
        if self.motion.lost is not None:  # where the run stopped: the contact whose normal load reached 0, and when
            rows.insert(1, ("contact lost", f"{self.motion.lost[0]} at t = {num(self.motion.lost[1])}"))
        rows += [(name, ", ".join(f"{k} {num(v, 4)}" for k, v in powers.items()))
                 for name, powers in self.elements.items()]
        return "StructureAnalysis", rows

    def to_dict(self) -> dict[str, Any]:
        """The ``simulate --model --json`` report, JSON-ready (undefined values None); ``lost``: the contact whose
        normal load reached 0 and when ({"contact", "t"}), or None."""
        lost = self.motion.lost
        return jsonable({"steady_state": self.steady_state.to_dict(), "amplitude": self.amplitude,
                         "elements": self.elements, "energy_residual": self.energy_residual,
                         "status": self.motion.status, "switches": len(self.motion.switches),
                         "lost": None if lost is None else {"contact": lost[0], "t": lost[1]}})


def analyze_structure(motion: Any, rtol: float = 1e-6, min_periods: int = 3,
                      window: tuple[float, float] | None = None) -> StructureAnalysis:
    """Steady state, element powers, amplitudes and energy residual of ``motion``.

    Parameters
    ----------
    motion:
        A :class:`~frictionflow.motion.Motion`.
    rtol:
        The section states must repeat to ``rtol`` of the state's size.
    min_periods:
        How many periods must repeat (>= 1).
    window:
        (t0, t1) to average over instead of the steady state's own window.
    """
    check.instance("motion", motion, Motion, "a Motion (from simulate_system)")
    if not 0.0 < rtol < 1.0:
        raise ValueError(f"rtol must be in (0, 1), got {rtol!r}")
    if int(min_periods) != min_periods or min_periods < 1:
        raise ValueError(f"min_periods must be an integer >= 1, got {min_periods!r}")
    ss = structure_steady_state(motion, rtol, int(min_periods))
    if window is not None:
        t0, t1 = float(window[0]), float(window[1])
        if not motion.t[0] <= t0 < t1 <= motion.t[-1]:
            raise ValueError(f"window must lie in [{motion.t[0]:g}, {motion.t[-1]:g}] with t0 < t1, got {window!r}")
        ss = replace(ss, window=(t0, t1), stick_fraction=stick_fractions(motion, (t0, t1)), manual_window=True)
    if ss.kind == "contact_lost":  # a transient: nothing averaged, but the run up to the loss is still checked
        t0, t1 = ss.window
        return StructureAnalysis(motion, ss, energy_residual=window_residual(motion, ss.window) if t1 > t0 else 0.0)
    if ss.kind == "equilibrium" and window is None and certified_sliding(motion):
        return _at_sliding_equilibrium(motion, ss)
    t0, t1 = ss.window
    return StructureAnalysis(motion, ss, motion.element_power(t0, t1), amplitudes(motion, ss.window),
                             window_residual(motion, ss.window))


def structure_steady_state(motion: Any, rtol: float = 1e-6, min_periods: int = 3) -> StructureSteadyState:
    """Classify ``motion`` (see the module's description)."""
    t_start, t_end = float(motion.t[0]), float(motion.t[-1])
    if motion.status != "ok":
        return StructureSteadyState("contact_lost", math.nan, (t_start, t_end), (math.nan,) * _contacts(motion))
    tail = _tail(motion)
    grid = np.linspace(tail[0], t_end, _grid_size(motion, tail))
    states = states_at(motion, (grid))
    if _at_rest(motion, tail, states, rtol) or certified_sliding(motion):
        return StructureSteadyState("equilibrium", math.nan, tail, stick_fractions(motion, tail))
    states = without_drift(motion.assembly, states)
    found = _periodic(motion, rtol, min_periods, np.max(np.abs(states), axis=1))
    if found is not None:
        period, window, p = found
        return StructureSteadyState("periodic", _whole_forcing(motion.assembly, period, rtol), window,
                                    stick_fractions(motion, window), min_periods)
    kind, lam = _not_periodic(motion, np.ptp(states, axis=1))
    return StructureSteadyState(kind, math.nan, tail, stick_fractions(motion, tail), lyapunov=lam)


def _whole_forcing(assembly: Any, period: float, rtol: float) -> float:
    """``period`` as m 2 pi / Omega where the structure's forces share one frequency Omega and it lies within
    10 ``rtol`` of such a multiple (the tolerance of the periods' spread in :func:`_periodic`); else as measured."""
    omega = np.unique(np.asarray(assembly.force_omega)[np.asarray(assembly.force_amp) != 0.0])
    if len(omega) != 1:
        return period
    forcing = 2.0 * math.pi / float(omega[0])
    m = int(round(period / forcing))
    return m * forcing if m >= 1 and abs(period - m * forcing) <= 10.0 * rtol * period else period


def _tail(motion: Any) -> tuple[float, float]:
    """The span a kind is judged on: the run's last tenth, at least two of the structure's slowest natural
    periods (:func:`_slowest_swing`; all of a shorter run)."""
    t_start, t_end = float(motion.t[0]), float(motion.t[-1])
    return max(t_start, t_end - _tail_length(motion, t_end - t_start)), t_end


def _tail_length(motion: Any, span: float) -> float:
    """The tail's length for a run of ``span``, before it is cut to the run (:func:`_tail`)."""
    return max(0.1 * span, 2.0 * _slowest_swing(motion))


def repeating(motion: Any, rtol: float = 1e-6, min_periods: int = 3) -> tuple[float, tuple[float, float], int] | None:
    """(period, window, section crossings per period) if the run's section states repeat (the periodic kind's
    test alone, as :func:`structure_steady_state` makes it: no rest test, no exponent), else None."""
    tail = _tail(motion)
    states = without_drift(motion.assembly, states_at(motion, np.linspace(*tail, _grid_size(motion, tail))))
    return _periodic(motion, rtol, min_periods, np.max(np.abs(states), axis=1))


def _at_rest(motion: Any, span: tuple[float, float], tail: np.ndarray, rtol: float) -> bool:
    """Nothing moves over the tail (``span``; ``tail``: its states on a grid) and every velocity is zero, to ``rtol``
    of the motion's scale -- but for a steady drift along the free translations (:func:`without_drift`: a
    structure no spring holds, carried along by the belt at a constant speed is at rest relative to it): the
    ranges of the run's states, positions' and velocities' each (:func:`_grouped`); with a free translation at
    least the velocities' size (a structure riding its belt from the start has no range) and the positions'
    rounding (``DRIFT_ROUNDING`` EPS of the drifting q: what the drift's removal leaves).
    Not the belt speeds: a fast belt made a lasting oscillation of a stuck-free mass "at rest" (amplitude 5e-4
    at belt 1000).  A tail shorter than the fastest natural period has its changes stretched to that period: an
    unbalanced force moves a short run's velocities a little, but not nothing."""
    omega = _fastest(motion)
    stretch = max(1.0, 2.0 * math.pi / omega / max(span[1] - span[0], 1e-300)) if omega > 0.0 else 1.0
    n, a = _n(motion), motion.assembly
    held = without_drift(a, tail)
    free = free_directions(a)
    moving = held[n:] - free @ (free.T @ held[n:])  # velocities off the free translations: none at rest
    ranges = np.maximum(np.ptp(held, axis=1), np.ptp(without_drift(a, np.asarray(motion.state)), axis=1))
    tol = rtol * _grouped(ranges)
    if free.shape[1]:  # riding on a belt from the start: no range, but a speed; and q's rounding left in held
        tol = np.maximum(tol, np.concatenate((np.full(n, DRIFT_ROUNDING * EPS * float(np.max(np.abs(tail[:n])))),
                                              rtol * np.full(n, float(np.max(np.abs(tail[n:])))))))
    return bool(np.all(stretch * np.ptp(held, axis=1) <= tol) and np.all(np.abs(moving) <= tol[n:, None]))


def _grouped(size: np.ndarray) -> np.ndarray:
    """Per state row, the largest of ``size`` (per row) over the row's group, the positions or the velocities
    (at least 1e-300): a tolerance in each group's own units.  One scale over both made a test depend on the
    unit of time (velocities scale by 1 / s, positions do not): a forced slider was periodic in seconds and
    not settled in milliseconds."""
    n = len(size) // 2
    return np.repeat([max(float(np.max(size[:n])), 1e-300), max(float(np.max(size[n:])), 1e-300)], n)


def _not_periodic(motion: Any, ranges: np.ndarray) -> tuple[str, float]:
    """(kind, largest exponent or NaN) of a run whose section does not repeat (:mod:`.structure_lyapunov`).

    The exponent's block: the first force's period when forced, else the
    section's mean return time; fewer than two crossings: ``not_settled``.
    The section goes to the revisit test in units of the motion's size: its positions' and its velocities'
    largest ``ranges`` (per state row, over the tail) each (:func:`_grouped`).
    """
    a = motion.assembly
    forced = np.flatnonzero(np.asarray(a.force_amp) != 0.0)
    times = section_times(motion)
    if len(times) < 2 or float(motion.t[-1] - motion.t[0]) < slowest_period(a):
        return "not_settled", math.nan
    block = 2.0 * math.pi / float(a.force_omega[forced[0]]) if len(forced) else float(np.mean(np.diff(times)))
    section = without_drift(a, states_at(motion, times))
    size = _grouped(np.maximum(ranges, np.ptp(section, axis=1)))
    kind, lam = beyond_periodic(motion, section, size, block, not len(forced))
    return kind, math.nan if lam is None else lam


def slowest_period(assembly: Any) -> float:
    """2 pi / the least |lambda| of the structure's own motion (masses, springs, dampers; no contacts), its zero
    eigenvalues left out (a free position and a free drift, as many as the null spaces of K and of [K; C] hold);
    0 for none.  A stiff damper's creep (|lambda| ~ k / c) and a heavy mass's swing set it."""
    m, k, c = (np.asarray(x, dtype=float) for x in (assembly.mass, assembly.stiffness, assembly.damping))
    n = len(m)
    zeros = (n - np.linalg.matrix_rank(k)) + (n - np.linalg.matrix_rank(np.vstack((k, c))))
    first = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])
    rates = np.sort(np.abs(np.linalg.eigvals(first)))[zeros:]
    return 2.0 * math.pi / float(rates[0]) if len(rates) and rates[0] > 0.0 else 0.0


def certified_sliding(motion: Any) -> bool:
    """Is the run's end proven to slide into the steady-sliding equilibrium without another switch?

    With every contact slipping the way its belt drives it and no force, the
    motion is the linearisation's: x(t) = x* + sum_i c_i v_i e^{lambda_i t}.
    If every Re lambda_i < 0 (beyond rounding: :func:`decay_floor`), each contact's relative velocity stays within
    sum_i |(e_j . v_i) c_i| of b_j (and each normal load within the same bound
    of its equilibrium value) for all later times; below |b_j| (and N_j*) no
    switch can come.  The single mass's certificate
    (:mod:`frictionflow.core.certificate`) is the same argument on a disc.
    The motion is the linearisation's only where every contact's slip force
    is piecewise constant: a smooth slip curve is not certified.
    """
    a = motion.assembly
    linear = {cls.code for cls in law_classes() if cls.configurable and cls.piecewise_constant}
    if not all(int(code) in linear for code in np.asarray(a.law)[:, LAW]):
        return False
    modes = np.asarray(motion.modes)[:, -1]
    if np.any(np.asarray(a.force_amp) != 0.0) or np.any(modes != np.sign(a.belt)) or np.any(a.belt == 0.0):
        return False
    try:
        eq = steady_sliding(a)
    except ValueError:
        return False
    lam, vec = eq.eigenvalues, eq.eigenvectors
    try:
        inv = np.linalg.inv(vec)
    except np.linalg.LinAlgError:  # a defective spectrum: no modal amplitudes to bound
        return False
    n = len(eq.q)
    # conditions measured with velocities over the fastest rate, as lengths: the same in any unit of time
    # (in microseconds the velocity rows' size made cond(V) 2.4e6 instead of 4.45 and the floor above the decay)
    unit = np.concatenate((np.ones(n), np.full(n, max(_fastest(motion), 1e-300))))
    vb, ib = vec / unit[:, None], inv * unit[None, :]
    if not np.all(lam.real < -decay_floor(unit[:, None] ** -1 * eq.jacobian * unit[None, :], vb, ib)):
        return False  # an undamped mode circles for ever
    c = inv @ (np.asarray(motion.state)[:, -1] - np.concatenate((eq.q, np.zeros(n))))
    speed = np.abs(np.asarray(a.contact_dir) @ vec[n:]) @ np.abs(c)
    load = np.abs(np.asarray(a.normal)[:, 1:] @ vec[:n]) @ np.abs(c)
    # rounding of the bound itself, and of the amplitudes through the eigenvectors' condition number
    margin = 1.0 - max(1e-9, EIGEN_ROUNDING * EPS * np.linalg.norm(vb, 1) * np.linalg.norm(ib, 1))
    return bool(np.all(speed < margin * np.abs(a.belt)) and np.all(load < margin * eq.normal))


def decay_floor(jacobian: np.ndarray, vec: np.ndarray, inv: np.ndarray) -> np.ndarray:
    """Per eigenvalue, how far below 0 its real part must lie to be negative beyond rounding: ``EIGEN_ROUNDING``
    EPS ||A|| kappa_i, with kappa_i = ||left_i|| ||right_i|| / |left_i . right_i| its condition number (the
    rows of V^-1 are the left eigenvectors): Wilkinson's first-order bound on the eigen-solver's error.

    Not a share of the spectrum's size: a stiff damper's slow mode (rate k / c, 1e-4 beside the damper's 2e4)
    is known to far better than 1e-8 of the largest |lambda|, and a floor that size called it undamped."""
    kappa = np.linalg.norm(inv, axis=1) * np.linalg.norm(vec, axis=0)
    return EIGEN_ROUNDING * EPS * np.linalg.norm(jacobian, 1) * kappa


def _at_sliding_equilibrium(motion: Any, ss: StructureSteadyState) -> StructureAnalysis:
    """The analysis of a run certified to end in steady sliding: the equilibrium's own values.

    The springs and dampers then do no work, each contact's belt input and
    heat are F_j b_j (V_r = b_j), and every coordinate rests at q*.
    """
    a = motion.assembly
    eq = steady_sliding(a)
    elements = {name: {"P": 0.0} for name in motion.channels if not name.startswith("contact.")}
    for j, contact in enumerate(motion.contacts):
        power = float(eq.normal[j] * eq.mu[j] * a.belt[j])
        elements[contact] = {"P_belt": power, "P_heat": power}
    rest = {dof: float(x) for dof, x in zip(motion.dof, eq.q)}
    fractions = tuple(0.0 for _ in motion.contacts)
    ss = StructureSteadyState("equilibrium", math.nan, ss.window, fractions)
    return StructureAnalysis(motion, ss, elements, {"X_max": rest, "X_min": dict(rest)},
                             window_residual(motion, ss.window))


def states_at(motion: Any, times: Any) -> np.ndarray:
    """The exact state (2n,) at ``times`` (a scalar) or (2n, len(times)) at each of ``times``."""
    if np.ndim(times) == 0:
        return motion.states([float(times)])[:, 0]
    return motion.states(times)


def _contacts(motion: Any) -> int:
    return int(np.asarray(motion.modes).shape[0])


def _n(motion: Any) -> int:
    return int(np.asarray(motion.state).shape[0]) // 2


def _fastest(motion: Any) -> float:
    """:func:`fastest_rate` of ``motion``'s structure."""
    return fastest_rate(motion.assembly)


def _slowest_swing(motion: Any) -> float:
    """:func:`swing_period` of ``motion``'s structure."""
    return swing_period(motion.assembly)


def swing_period(assembly: Any) -> float:
    """The structure's slowest natural period (its zero frequencies left out), else the fastest rate's period
    (0 without any): the least tail a kind is judged on (two of them; 4 pi for the nondimensional single mass),
    and a sweep's probe's unit of time."""
    omega = natural_frequencies(assembly)
    omega = omega[omega > RIGID * float(omega.max(initial=0.0))]  # a rigid mode's comes out ~1e-8, not 0
    if len(omega):
        return 2.0 * math.pi / float(omega.min())
    fastest = fastest_rate(assembly)
    return 2.0 * math.pi / fastest if fastest > 0.0 else 0.0


def evaluations(motion: Any, t_end: float) -> tuple[int, int]:
    """(on grids, scattered): how many states the classification of a run of ``motion``'s structure from t = 0
    to ``t_end`` evaluates -- on its grids (the tail's, the section's over the second half, the amplitudes'
    window about the tail) and, at most, in refining crossings (one a fastest period on the section, two per
    coordinate in the window, each up to REFINE_STEPS evaluations): the part of the analysis that grows with
    the run (a sweep's estimate times both on a short probe; scattered times cost a phase's setup each)."""
    tail = min(_tail_length(motion, t_end), t_end)
    window, section = _grid_size(motion, (0.0, tail)), _grid_size(motion, (0.0, 0.5 * t_end))
    crossings = (section + 2 * _n(motion) * window) / GRID_PER_PERIOD
    return 2 * window + section, int(math.ceil(REFINE_STEPS * crossings))


def _grid_size(motion: Any, span: tuple[float, float]) -> int:
    """Grid points over ``span`` resolving the fastest natural period (GRID_PER_PERIOD each)."""
    omega = _fastest(motion)
    return max(64, int(math.ceil((span[1] - span[0]) * omega / (2.0 * math.pi) * GRID_PER_PERIOD)) + 1)


def _periodic(motion: Any, rtol: float, min_periods: int,
              size: np.ndarray) -> tuple[float, tuple[float, float], int] | None:
    """(period, window, crossings per period) if the section states repeat to ``rtol`` of the motion's size, else
    None.  ``size``: per state row, its largest magnitude over the tail; with the section's, a scale per group
    (:func:`_grouped`: the section's velocities alone would be none for one coordinate, zero there)."""
    times = section_times(motion)
    need = min_periods + 1
    if len(times) < need:
        return None
    states = without_drift(motion.assembly, states_at(motion, (times)))
    scale = _grouped(np.maximum(size, np.max(np.abs(states), axis=1)))[:, None]
    for p in range(1, MAX_CROSSINGS + 1):
        last = len(times) - 1
        first = last - min_periods * p
        if first < 0:
            return None
        gaps = np.max(np.abs(states[:, first + p:last + 1] - states[:, first:last + 1 - p]) / scale, axis=0)
        if np.all(gaps <= rtol):
            if state_subcycle(states[:, :last + 1] / scale, p, SUBCYCLE_SPREAD * rtol):
                return None  # a cycle of fewer crossings still converging (the single mass's forced rule)
            periods = np.diff(times[first:last + 1:p])
            if np.ptp(periods) <= rtol * max(float(np.mean(periods)), 1e-300) * 10.0 + 1e-9 * periods[0]:
                return float(np.mean(periods)), (float(times[first]), float(times[last])), p
    return None


def without_drift(assembly: Any, states: np.ndarray) -> np.ndarray:
    """``states`` (2n, m) with each position's component along the structure's free translations removed: the
    directions d with K d = 0 and n_j . d = 0 for every contact's normal load, along which no spring, damper,
    contact or force depends on the position.  A structure free to move (no spring to the ground) can repeat
    its motion shifted along them every period (a free chain forced into a subharmonic while the belt carries it
    along): the same cycle, periodic in everything its forces see."""
    n = states.shape[0] // 2
    free = free_directions(assembly)  # (n, r) orthonormal
    if free.shape[1] == 0:
        return states
    out = np.array(states, dtype=float)
    out[:n] -= free @ (free.T @ out[:n])
    return out


def section_times(motion: Any) -> np.ndarray:
    """The times where q_i' crosses 0 downwards, for the coordinate i moving most over the run's second half."""
    t_start, t_end = float(motion.t[0]), float(motion.t[-1])
    span = (t_start + 0.5 * (t_end - t_start), t_end)
    grid = np.linspace(span[0], span[1], _grid_size(motion, span))
    states = states_at(motion, (grid))
    n = _n(motion)
    row = n + int(np.argmax(np.ptp(states[n:], axis=1)))
    v = states[row]
    hits = np.flatnonzero((v[:-1] > 0.0) & (v[1:] <= 0.0))
    return _falls(motion, row, grid[hits], grid[hits + 1])


def _falls(motion: Any, row: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Per bracket [a_i, b_i] (disjoint, ascending) of state row ``row``, the first time its sign is no longer
    the one at a_i, to rounding of the time: all brackets at once (one evaluation of the motion per step, not
    one per crossing and step: a run to 1e5 spent 3 s in single-time evaluations), by the Illinois rule where
    the row crosses 0 and by bisection where it reaches 0 and stays there -- a contact holding it on a fixed
    surface: the stick time, not a grid point after it (the rest of the structure moves on while it is stuck,
    so the states there would depend on the grid's phase)."""
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    if not len(a):
        return b
    fa, fb = states_at(motion, a)[row], states_at(motion, b)[row]
    side = np.sign(fa)
    bisect = fb == 0.0
    moved = np.zeros(len(a), dtype=np.int8)  # which end the last step moved: +1 a, -1 b, 0 none yet
    for _ in range(200):
        wide = np.flatnonzero(b - a > 4.0 * EPS * np.abs(b))
        if not len(wide):
            break
        x = np.where(bisect[wide], 0.5 * (a[wide] + b[wide]),
                     b[wide] - fb[wide] * (b[wide] - a[wide]) / (fb[wide] - fa[wide]))
        x = np.clip(x, a[wide], b[wide])
        fx = states_at(motion, np.sort(x))[row][np.argsort(np.argsort(x))]
        kept = np.sign(fx) == side[wide]
        lo, hi = wide[kept], wide[~kept]
        fb[lo[moved[lo] == 1]] *= 0.5  # Illinois: the end kept twice in a row has its value halved
        fa[hi[moved[hi] == -1]] *= 0.5
        a[lo], fa[lo], moved[lo] = x[kept], fx[kept], 1
        b[hi], fb[hi], moved[hi] = x[~kept], fx[~kept], -1
        bisect[hi] |= fx[~kept] == 0.0
    return b


def stick_fractions(motion: Any, window: tuple[float, float]) -> tuple[float, ...]:
    """Per contact, the share of ``window`` spent stuck (a sample's mode holds until the next sample)."""
    t = np.asarray(motion.t)
    t0, t1 = window
    if t1 <= t0:
        return tuple(math.nan for _ in range(_contacts(motion)))
    lo = np.clip(t[:-1], t0, t1)
    hi = np.clip(t[1:], t0, t1)
    span = hi - lo
    modes = np.asarray(motion.modes)[:, :-1]
    return tuple(float(np.sum(span[m == 0]) / (t1 - t0)) for m in modes)


def amplitudes(motion: Any, window: tuple[float, float]) -> dict[str, dict[str, float]]:
    """Each coordinate's maximum and minimum over ``window`` (at its velocity's zeros, or the window's ends)."""
    n = _n(motion)
    grid = np.linspace(window[0], window[1], _grid_size(motion, window))
    states = states_at(motion, (grid))
    out_max, out_min = {}, {}
    for i, name in enumerate(motion.dof):
        v = states[n + i]
        hits = np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0.0)
        times = np.concatenate(([window[0], window[1]], _falls(motion, n + i, grid[hits], grid[hits + 1])))
        values = states_at(motion, np.sort(times))[i]
        out_max[name], out_min[name] = float(np.max(values)), float(np.min(values))
    return {"X_max": out_max, "X_min": out_min}


def window_residual(motion: Any, window: tuple[float, float]) -> float:
    """|change of kinetic + spring energy - work of dampers, forces and contacts| over ``window``, relative.

    Relative to the largest of the energies and the works' magnitudes that
    enter it, so that a balance closed to rounding gives ~1e-15.
    """
    t0, t1 = window
    ends = states_at(motion, (np.array([t0, t1])))
    energy = sum(motion.energy(ends))
    span = t1 - t0
    works = []
    for name, powers in motion.element_power(t0, t1).items():
        if name.startswith("spring."):
            continue  # the spring energy is in `energy`
        if name.startswith("contact."):
            works += [powers["P_belt"] * span, -powers["P_heat"] * span]
        else:
            works.append(powers["P"] * span)
    scale = max(float(np.max(np.abs(energy))), *(abs(w) for w in works), 1e-300)
    return abs(float(energy[1] - energy[0]) - float(sum(works))) / scale
