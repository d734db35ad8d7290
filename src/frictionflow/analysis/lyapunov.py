"""Lyapunov exponents of the non-smooth (stick-slip) flow, forced or not, on a belt at constant or varying speed.

>>> from frictionflow import BeltOscillator, Coulomb
>>> from frictionflow.analysis.lyapunov import lyapunov_exponents
>>> r = lyapunov_exponents(BeltOscillator(zeta=0.01, vb=0.1, fex=0.5, omega=1.0), Coulomb(0.5, 1.0))
>>> round(r.exponents[0], 2), r.exponents[1]      # chaotic stick-slip: the second is -inf
(0.08, -inf)

Two tangent vectors ride along the trajectory (:mod:`frictionflow.core.tangent`:
RK4 inside the phases, switches located, saltation matrices across them) and
are renormalised by QR at the end of every block -- every forcing period
when forced, every period 2 pi / Omega_b of the belt's speed on a moving belt
(V_b(tau) = V_b + A sin(Omega_b tau + phi_b); with an external force too the
two periods are one), every ``block`` time units otherwise.  Where an
averaged block grew the two vectors apart by more than ``GROWTH_CHECK``
(strongly overdamped sliding: (lambda_1 - lambda_2) block beyond ~23, the
second vector's own direction sinks towards rounding and lambda_2 would read
noise, or -inf), the run is repeated renormalising m times per block, m
enough to keep that ratio within :data:`GROWTH_BOUND` both as measured and
for the sliding linearisation (eigenvalues sqrt(c^2 - 4) apart,
c = 2 zeta + F'(V_b)); blocks, sections and running estimates stay per block
(``settings["qr_per_block"]`` says m).  After ``t_transient`` the mean
logarithmic growth of the frame gives both exponents of the (X, X') part:

* forced or on a moving belt: the trivial zero exponent of the time (phase)
  direction of the extended phase space is not among them;
* unforced: one of the two belongs to the flow direction (about 0 on a limit
  cycle, decaying like 1 / t to it).

A stick onset maps every perturbation of X' to 0 (saltation diag(1, 0)), so
the tangent map loses a dimension: while the motion keeps sticking the second
exponent is exactly ``-inf`` (and the volume contraction is total).  It is
reported as such (``None`` in JSON, with ``collapsed`` true), not as the
rounding noise that a floating-point frame would show.  ``collapsed`` needs
a stick (a stick onset, or a start or hold in stick): a run that never sticks
reports the exponent it measured.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .. import _validate as check
from .._display import Row, Summarized, num, spoken, system_row
from .._json import jsonable
from ..core import tangent
from ..estimate import enforce, located_run
from ..friction.base import STICK_RULE_WORDS, FrictionLaw
from ..friction.registry import tangent_law_names
from ..params import BeltOscillator
from ..solvers.base import DEFAULT_MAX_MEMORY, kernel_params, rk4_steps

#: the block of an unforced run: one natural period
DEFAULT_UNFORCED_BLOCK = 2.0 * math.pi
SWITCH_NAMES = ("stick_onsets", "slip_onsets", "slip_reversals", "held_at_limit", "grazing_touches")
#: the switches that only a stick explains (a slip onset leaves one: a start in stick, if no stick onset)
STICK_SWITCHES = ("stick_onsets", "slip_onsets", "held_at_limit")
#: the largest ratio of the two tangent vectors' growth allowed between two renormalisations, a priori (rounding then
#: leaves the second vector's direction about 1e-8 relative accuracy; e^36 ~ 1 / 2^-52 would leave none)
GROWTH_BOUND = 1e8
#: a ratio measured above this in one averaged renormalisation interval: the run repeated with shorter intervals
GROWTH_CHECK = 1e10
#: at most this many repeats
MAX_REFINE = 2
#: batches of consecutive blocks the standard error is estimated from (batch means), and the fewest blocks a batch
#: needs for it to be given
BATCHES = 10
BATCH_BLOCKS = 4


@dataclass(frozen=True, repr=False)
class LyapunovResult(Summarized):
    """Both Lyapunov exponents of a run, their running estimates and what happened on the way.

    Attributes
    ----------
    model, friction:
        What was run.
    exponents:
        (lambda_1, lambda_2), largest first (lambda_2 may be -inf, see the
        module docstring).
    running:
        The estimates after each averaged block (rows; column i is
        lambda_i).
    times:
        The time of each row of ``running``, since the transient ended.
    switches:
        How many switches of each kind the run went through, by name
        (stick onsets, slip onsets, slip reversals, holds at the limit,
        grazing touches).
    sections:
        (X, X', mode) at every block end, the transient's included (forced:
        the stroboscopic sequence).
    settings:
        The run's settings (transient, end, block, steps per block).
    """


    model: BeltOscillator
    friction: FrictionLaw
    exponents: tuple[float, float]
    running: np.ndarray
    times: np.ndarray
    switches: dict[str, int]
    sections: np.ndarray
    settings: dict[str, Any] = field(default_factory=dict)

    @property
    def stuck(self) -> bool:
        """Whether the run ever stuck (a stick onset, a start or hold in stick, a block ending in stick)."""
        return any(self.switches.get(k, 0) for k in STICK_SWITCHES) or bool(np.any(self.sections[:, 2] == 0))

    @property
    def collapsed(self) -> bool:
        """Whether the second exponent is -inf because the motion sticks (the stick onset's saltation makes the
        tangent map lose rank); never without a stick."""
        return self.exponents[1] == -math.inf and self.stuck

    @property
    def spread(self) -> tuple[float, float]:
        """A convergence check, max - min of each running estimate over the second half of the averaging (not an
        error bar: :attr:`stderr`)."""
        half = self.running[len(self.running) // 2:]
        out = []
        for i in range(2):
            col = half[:, i]
            out.append(float(np.ptp(col)) if np.all(np.isfinite(col)) else math.nan)
        return out[0], out[1]

    @property
    def stderr(self) -> tuple[float, float]:
        """Each exponent's standard error by batch means (the average cut into ``BATCHES`` runs of consecutive
        blocks, each batch's own exponent, their standard deviation over sqrt(BATCHES)).

        A statistical error bar, where the spread is a convergence check (the running estimate's range, which
        need not match the uncertainty either way); it holds while a batch outlasts the motion's correlation
        time.  NaN for an exponent that is not finite or with fewer than BATCHES * BATCH_BLOCKS blocks.
        """
        n = len(self.running) // BATCHES * BATCHES
        if n < BATCHES * BATCH_BLOCKS:
            return math.nan, math.nan
        last = slice(n // BATCHES - 1, n, n // BATCHES)  # each batch's last block
        spans = np.diff(self.times[last], prepend=0.0)
        out = []
        for i in range(2):
            grown = self.running[last, i] * self.times[last]  # the log growth since the transient, at each batch's end
            if not np.all(np.isfinite(grown)):
                out.append(math.nan)
                continue
            each = np.diff(grown, prepend=0.0) / spans
            out.append(float(np.std(each, ddof=1) / math.sqrt(BATCHES)))
        return out[0], out[1]

    @property
    def chaotic(self) -> bool:
        """lambda_1 > 0 by more than its spread (forced runs; an autonomous flow's 0 is not chaos)."""
        return self.exponents[0] > max(self.spread[0], 1e-6)

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready report: -inf exponents become None (``minus_infinity`` says which)."""
        return jsonable({
            "params": {**self.model.as_dict(), **self.friction.as_dict()},
            "exponents": list(self.exponents),
            "minus_infinity": [e == -math.inf for e in self.exponents],
            "collapsed": self.collapsed,
            "spread": list(self.spread),
            "stderr": list(self.stderr),
            "switches": dict(self.switches),
            "settings": dict(self.settings),
            "final_state": {"X": float(self.sections[-1, 0]), "V": float(self.sections[-1, 1])},
        })

    def summary(self) -> str:
        """The text report (the same as ``repr``)."""
        return repr(self)

    def _summary(self) -> tuple[str, list[Row]]:
        s = self.settings
        l1, l2 = self.exponents
        rows = [
            system_row(self.model, self.friction),
            ("forcing", f"F_ex={num(self.model.fex, 4)}, Omega={num(self.model.omega, 4)}" if self.model.forced else "none"),
            *([("belt", f"V_b + A sin(Omega_b tau + phi_b), A={num(self.model.vb_amplitude, 4)}, "
                        f"Omega_b={num(self.model.vb_omega, 4)}")] if self.model.belt_varies else []),
            ("lambda_1", f"{num(l1, 8)} (standard error {num(self.stderr[0], 2)}, spread {num(self.spread[0], 2)})"),
            ("lambda_2", "-inf (stick onsets collapse the tangent map)" if self.collapsed
             else "-inf (no stick: the second tangent vector sank into rounding; max_memory limits the "
                  "renormalisations)" if l2 == -math.inf
             else f"{num(l2, 8)} (standard error {num(self.stderr[1], 2)}, spread {num(self.spread[1], 2)})"),
            *([("renormalised", f"{s['qr_per_block']} times per block")] if s.get("qr_per_block", 1) > 1 else []),
            ("switches", ", ".join(f"{k.replace('_', ' ')} {v}" for k, v in self.switches.items() if v)),
            ("averaged", f"tau {num(s['t_transient'])}..{num(s['t_end'])}, {s['blocks']} blocks of {num(s['block'])}, "
                         f"{s['steps_per_block']} RK4 steps each"),
        ]
        return "LyapunovResult", rows


def _check_law(friction: FrictionLaw) -> None:
    if friction.stick_rule != "switch":
        raise ValueError(f"Lyapunov exponents need a law with Coulomb's stick rule (switch); {friction.name} has "
                         f"{STICK_RULE_WORDS[friction.stick_rule]}: use {spoken(tangent_law_names())}")
    if not friction.has_tangent_kernel:
        raise ValueError("Lyapunov exponents need a compiled slip law; a user-defined law's function cannot be "
                         "differentiated by the tangent kernel")


def _positive(name: str, value: float) -> float:
    value = check.number(name, value, "finite and > 0")
    if not value > 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return value


def _max_memory(value: float) -> float:
    """``max_memory`` as a float: a number > 0 (inf: no limit)."""
    if isinstance(value, (bool, str)) or value is None:
        raise ValueError(f"max_memory must be a number of GiB > 0, got {value!r}")
    try:
        gib = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"max_memory must be a number of GiB > 0, got {value!r}") from None
    if not gib > 0.0:  # (NaN too)
        raise ValueError(f"max_memory must be > 0 (GiB), got {value!r}")
    return gib


#: what one block keeps (X, X', mode at its end; two running estimates), in bytes
_BYTES_PER_BLOCK = (3 + 2) * 8


def _check_size(n_transient: int, n_blocks: int, steps_per_block: int, t_end: float, max_memory: float,
                qr_per_block: int = 1) -> None:
    """Refuse, before any work, a run whose per-block record (one per renormalisation: ``qr_per_block`` per block)
    exceeds ``max_memory`` GiB (its size and steps said)."""
    blocks = n_transient + n_blocks
    need = blocks * qr_per_block * _BYTES_PER_BLOCK / 2**30
    if not need <= max_memory:
        raise ValueError(f"t_end={t_end:g} makes {blocks:.3g} blocks ({blocks * steps_per_block:.3g} RK4 steps with their "
                         f"tangents), whose record needs {need:.3g} GiB but max_memory={max_memory:g} GiB: shorten t_end "
                         "or raise max_memory (the argument; on the command line a 'max_memory = <GiB>' line in the "
                         "--config file)")


def _check_stop(stop: tuple[int, int, float, float] | None) -> None:
    """ValueError unless ``stop`` is None or (first >= 2, every >= 1, factor > 0, floor >= 0)."""
    if stop is None:
        return
    ok = isinstance(stop, (tuple, list)) and len(stop) == 4
    if ok:
        first, every, factor, floor = stop
        ok = (int(first) == first >= 2 and int(every) == every >= 1 and math.isfinite(factor) and factor > 0.0
              and math.isfinite(floor) and floor >= 0.0)
    if not ok:
        raise ValueError(f"stop must be (first >= 2, every >= 1, factor > 0, floor >= 0) or None, got {stop!r}")


def _check_run(x0: float, v0: float, t_transient: float, t_end: float, steps_per_block: int) -> tuple[float, float]:
    """ValueError naming the first argument of :func:`lyapunov_exponents` out of its range (or of its type: text, a
    boolean); returns (t_transient, t_end) as floats."""
    for name, value in (("x0", x0), ("v0", v0)):
        check.number(name, value, "a finite real number")
    t_transient = check.number("t_transient", t_transient, "finite and >= 0")
    if not t_transient >= 0.0:
        raise ValueError(f"t_transient must be finite and >= 0, got {t_transient!r}")
    t_end = _positive("t_end", t_end)
    if not t_end > t_transient:
        raise ValueError(f"t_end ({t_end!r}) must exceed t_transient ({t_transient!r})")
    whole = isinstance(steps_per_block, (int, np.integer, float, np.floating)) and not isinstance(steps_per_block, bool)
    if not (whole and math.isfinite(steps_per_block) and int(steps_per_block) == steps_per_block >= 4):
        raise ValueError(f"steps_per_block must be an integer >= 4, got {steps_per_block!r}")
    return t_transient, t_end


#: RK4's stability limit on the negative real axis: |1 + z + z^2/2 + z^3/6 + z^4/24| <= 1 for z in [-RK4_REAL_LIMIT, 0]
RK4_REAL_LIMIT = 2.785293563405282


def _check_stable(zeta: float, block: float, steps_per_block: int) -> None:
    """Refuse steps RK4 cannot take stably: an overdamped slip phase (zeta > 1) decays at the rate
    zeta + sqrt(zeta^2 - 1), whose product with the step must stay within RK4's real stability limit (for
    zeta <= 1 the rates are 1 and any 4 steps per block are stable).  An unstable step does not fail: it
    gives an exponent of the wrong sign and millions of spurious grazing switches."""
    rate = zeta + math.sqrt(zeta * zeta - 1.0) if zeta > 1.0 else 1.0
    h = block / steps_per_block
    if h * rate > RK4_REAL_LIMIT:
        need = math.ceil(block * rate / RK4_REAL_LIMIT)
        raise ValueError(f"steps_per_block={steps_per_block}: RK4 steps of {h:.3g} are unstable at zeta={zeta:g} (the fast "
                         f"slip mode decays at rate {rate:.4g}; rate x step must stay below {RK4_REAL_LIMIT:.4g}): "
                         f"use at least {need} steps per block (--steps-per-period)")


def _block(model: BeltOscillator, block: float | None) -> float:
    """The renormalisation interval: the drive's period when the flow depends on time (the forcing period, or
    the belt's 2 pi / Omega_b on a moving belt alone; ``block`` must then be it or None), else ``block`` or
    :data:`DEFAULT_UNFORCED_BLOCK`."""
    problem = model.section_problem()
    if problem is not None:
        raise ValueError(problem)
    if block is not None:
        block = _positive("block", block)
    if not model.driven:
        return DEFAULT_UNFORCED_BLOCK if block is None else block
    period = model.drive_period
    if block is not None and not math.isclose(block, period, rel_tol=1e-12):
        what = "forcing period" if model.forced else "period of the belt's speed"
        raise ValueError(f"a {'forced' if model.forced else 'moving-belt'} run renormalises once per {what} "
                         f"{period:.12g}; got block={block!r}")
    return period


def _tangent_run(model: BeltOscillator, friction: FrictionLaw, start: tuple[float, float, float, int],
                 blocks: tuple[int, int], stop: tuple[int, int, float, float] | None) -> tuple:
    """The tangent kernel's run from ``start`` = (x0, v0, block, steps per block) over ``blocks`` = (transient,
    averaged): (s1, s2, averaged blocks done, sections, running estimates, switch counts); RuntimeError where
    it cannot continue."""
    x0, v0, block, steps = start
    n_transient, n_blocks = blocks
    strobe = np.zeros((n_transient + n_blocks, 3))
    est = np.full((n_blocks, 2), np.nan)
    counts = np.zeros(tangent.N_COUNTS, dtype=np.int64)
    rule = (n_blocks + 1, n_blocks + 1, 0.0, 0.0) if stop is None else tuple(stop)  # (never ends early)
    status, s1, s2, n_done = tangent.run_until(x0, v0, float(model.zeta), float(model.vb), kernel_params(model, friction),
                                               block, steps, blocks, (int(rule[0]), int(rule[1]), float(rule[2]),
                                                                      float(rule[3])), strobe, est, counts)
    if status == tangent.ZERO_PHASES:
        raise RuntimeError("the motion is caught switching without moving (repeated zero-length phases): "
                           "a grazing or sliding motion the switch model cannot continue")
    if status == tangent.NOT_FINITE:
        raise RuntimeError("the tangent vectors left the floating-point range (a grazing switch?)")
    return s1, s2, n_done, strobe, est, counts


def _slip_spread(model: BeltOscillator, friction: FrictionLaw) -> float:
    """lambda_1 - lambda_2 of the slip field's linearisation at the sliding state (|V_r| = V_b, on a moving belt
    V_b +- A too): the Jacobian [[0, 1], [-1, -c]], c = 2 zeta + F'(|V_r|), has sqrt(c^2 - 4) between its real
    eigenvalues (0 for a complex pair: equal real parts)."""
    vb, amp = abs(float(model.vb)), abs(float(model.vb_amplitude)) if model.belt_varies else 0.0
    spread = 0.0
    for speed in {vb, vb + amp, max(vb - amp, 0.0)}:
        slope = friction.slip_slope(speed)
        c = 2.0 * float(model.zeta) + (slope if math.isfinite(slope) else 0.0)
        spread = max(spread, math.sqrt(c * c - 4.0) if abs(c) > 2.0 else 0.0)
    return spread


def _split(need: int, steps: int, most: float = math.inf) -> tuple[int, int]:
    """(m, n): renormalise m >= ``need`` times per block, n RK4 steps each time: a divisor m of ``steps`` up to 2
    ``need`` (the grid of one renormalisation per block, the steps the same), else ``need`` and n = ceil(steps /
    need); at most one renormalisation per step, and at most ``most`` (>= 1) per block."""
    need = int(min(max(1, need), steps, most))
    for m in range(need, int(min(2 * need, steps, most)) + 1):
        if steps % m == 0:
            return m, steps // m
    return need, math.ceil(steps / need)


def _stuck(counts: np.ndarray, strobe: np.ndarray) -> bool:
    """Whether a kernel run stuck: a switch only a stick explains (:data:`STICK_SWITCHES`) or an interval ending
    in stick."""
    return any(counts[SWITCH_NAMES.index(k)] for k in STICK_SWITCHES) or bool(np.any(strobe[:, 2] == 0))


def _worst_growth(est: np.ndarray, interval: float) -> float:
    """The largest log(r11 / |r22|) of the renormalisation intervals of ``est`` (running estimates, an interval of
    length ``interval`` each), read back from their sums; inf where log |r22| is -inf (the second vector lost)."""
    sums = est * (interval * np.arange(1, len(est) + 1))[:, None]
    if not np.all(np.isfinite(sums)):
        return math.inf
    logs = np.diff(sums, axis=0, prepend=np.zeros((1, 2)))
    return float(np.max(logs[:, 0] - logs[:, 1])) if len(logs) else 0.0


def _more(model: BeltOscillator, friction: FrictionLaw, block: float, m: int, worst: float) -> int:
    """Renormalisations per block for a repeat of a run of ``m`` whose worst interval grew the two vectors apart by
    e^``worst``: enough to bring that within :data:`GROWTH_BOUND`, and the sliding linearisation's
    (:func:`_slip_spread`) too; at least twice ``m``."""
    bound = math.log(GROWTH_BOUND)
    prior = math.ceil(_slip_spread(model, friction) * block / bound - 1e-9)
    measured = 4 * m if math.isinf(worst) else m * math.ceil(worst / bound)
    return max(2 * m, prior, measured)


def _refined_run(model: BeltOscillator, friction: FrictionLaw, start: tuple[float, float, float, int],
                 blocks: tuple[int, int], stop: tuple[int, int, float, float] | None, most: float) -> tuple:
    """:func:`_tangent_run` from ``start`` = (x0, v0, block, steps per block), renormalising once per block, then,
    if an averaged block grew the two tangent vectors apart by more than ``GROWTH_CHECK`` (the second
    vector's direction sinking into rounding; log |r22| = -inf without a stick counts as that), repeated m
    times per block (:func:`_more`, :func:`_split`; m at most ``most``, the record's limit under max_memory): at
    most :data:`MAX_REFINE` repeats.  A run that collapsed at a stick needs no repeat (lambda_2 is -inf whatever
    the frame), nor does one with ``stop`` (the forced classifier's arithmetic, which
    ``frictionflow.core.batch_forced`` reproduces).  Returns (m, RK4 steps per renormalisation, the last run)."""
    x0, v0, block, steps = start
    m, n_sub = 1, steps
    for attempt in range(MAX_REFINE + 1):
        run = _tangent_run(model, friction, (x0, v0, block / m, n_sub), (blocks[0] * m, blocks[1] * m), stop)
        s2, n_done, strobe, est, counts = run[1:]
        if stop is not None or attempt == MAX_REFINE or m >= steps or (s2 == -math.inf and _stuck(counts, strobe)):
            break
        worst = _worst_growth(est[:n_done], block / m)
        if worst <= math.log(GROWTH_CHECK):
            break
        more, n_more = _split(_more(model, friction, block, m, worst), steps, most)
        if not m < more <= most:
            break
        m, n_sub = more, n_more
    return m, n_sub, run


def lyapunov_exponents(
    model: BeltOscillator,
    friction: FrictionLaw,
    x0: float | None = None,
    v0: float | None = None,
    t_transient: float = 1000.0,
    t_end: float = 6000.0,
    *,
    steps_per_block: int | None = None,
    block: float | None = None,
    max_memory: float = DEFAULT_MAX_MEMORY,
    stop: tuple[int, int, float, float] | None = None,
) -> LyapunovResult:
    """Both Lyapunov exponents of the motion from (x0, v0), averaged over tau in [t_transient, t_end].

    Parameters
    ----------
    model, friction:
        The oscillator (forced or not, its belt at constant speed or
        moving, with one common period when both) and a law with Coulomb's
        stick rule (Coulomb, Stribeck, cubic; Karnopp's band law is refused).
    x0, v0:
        Start state at tau = 0; by default the law's start (:meth:`FrictionLaw.start`, as :func:`simulate` and
        every command: the paper's X(0) = F_d, X'(0) = V_b).
    t_transient, t_end:
        The frame is renormalised but not averaged before ``t_transient``;
        both are rounded up to whole blocks.
    steps_per_block:
        RK4 steps per block (the slip phases' accuracy; switches are located
        whatever it is); None: 512, doubled while a step would exceed 2 pi / 64.
    block:
        Renormalisation interval: the forcing period 2 pi / Omega when forced,
        the belt's 2 pi / Omega_b on a moving belt alone (and then it must
        be), 2 pi otherwise unless given.  A block over which the two
        tangent vectors' growth parts by more than ``GROWTH_CHECK``
        (strong overdamping) is renormalised m times instead, the run
        repeated (see the module docstring; ``settings["qr_per_block"]``).
    max_memory:
        GiB (> 0) the per-block record (the section and the running
        estimates) may take; a longer run is refused before any work, with
        its size and its number of RK4 steps.
    stop:
        (first, every, factor, floor): end the averaging once lambda_1 is
        below -factor max(spread, floor) after first, first + every, ...
        blocks (``frictionflow.core.tangent.run_until``; the forced
        classifier's rule).  ``running``, ``sections`` and the settings then
        cover the blocks done, renormalised once per block whatever the
        growth (the classifier's arithmetic: lambda_1 is its aim; lambda_2
        is then only reliable while (lambda_1 - lambda_2) block stays below
        ~23).  None: every block.

    Raises
    ------
    TypeError
        A ``model`` or ``friction`` of the wrong type.
    ValueError
        Naming the argument out of its range or not a number (text, a boolean).
    """
    check.instance("model", model, BeltOscillator, "a BeltOscillator")
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")
    _check_law(friction)
    block = _block(model, block)
    steps_per_block = rk4_steps(block, steps_per_block)
    t_transient, t_end = _check_run(0.0 if x0 is None else x0, 0.0 if v0 is None else v0, t_transient, t_end,
                                    steps_per_block)
    x0, v0 = friction.start(model.vb, x0, v0)
    _check_stop(stop)
    max_memory = _max_memory(max_memory)
    steps = int(steps_per_block)
    _check_stable(float(model.zeta), block, steps)
    n_transient = math.ceil(t_transient / block - 1e-9)
    n_blocks = max(1, math.ceil((t_end - n_transient * block) / block - 1e-9))
    _check_size(n_transient, n_blocks, steps, t_end, max_memory)
    blocks = n_transient + n_blocks
    run = located_run(float(blocks) * steps, blocks * block, "tangent_step", 2.0 * math.pi / block if model.driven else 1.0)
    enforce(replace(run, memory=blocks * _BYTES_PER_BLOCK))  # within the limits in force (frictionflow.estimate.limited)
    start = (float(x0), float(v0), float(block), steps)
    most = max_memory * 2**30 / (blocks * _BYTES_PER_BLOCK)  # renormalisations per block the record has room for
    refined = _refined_run(model, friction, start, (n_transient, n_blocks), stop, most)
    return _result(model, friction, start, n_transient, refined)


def _result(model: BeltOscillator, friction: FrictionLaw, start: tuple[float, float, float, int], n_transient: int,
            refined: tuple) -> LyapunovResult:
    """The :class:`LyapunovResult` of :func:`_refined_run`'s ``refined`` = (m, steps per renormalisation, run) from
    ``start`` = (x0, v0, block, steps per block): the exponents over the time averaged, the records per block."""
    x0, v0, block, _ = start
    m, n_sub, (s1, s2, n_sub_done, strobe, est, counts) = refined
    n_done = n_sub_done // m
    elapsed = n_sub_done * (block / m)
    exps = (s1 / elapsed, s2 / elapsed)
    if exps[1] > exps[0]:  # only rounding can put them out of order (equal exponents)
        exps = (exps[1], exps[0])
    return LyapunovResult(
        model=model,
        friction=friction,
        exponents=(float(exps[0]), float(exps[1])),
        running=est[:n_done * m][m - 1::m],
        times=block * np.arange(1, n_done + 1),
        switches={name: int(c) for name, c in zip(SWITCH_NAMES, counts, strict=True)},
        sections=strobe[:(n_transient + n_done) * m][m - 1::m],
        settings={"x0": x0, "v0": v0, "t_transient": n_transient * block,
                  "t_end": (n_transient + n_done) * block, "block": block, "blocks": n_done,
                  "steps_per_block": m * n_sub, "qr_per_block": m,
                  "method": "RK4 + located switches + saltation, QR " + ("per block" if m == 1 else f"{m} times per block")},
    )
