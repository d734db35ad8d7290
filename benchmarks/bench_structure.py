"""Multi-DOF exact engine vs scipy solve_ivp (DOP853 with events) on chains of masses, in one run (issue 22, item 7).

    python benchmarks/bench_structure.py

Cases: chains of unit masses, each on a spring (k = 1) and a damper (c = 0.04)
to the ground, springs k = 0.5 between neighbours, one Coulomb contact per
mass on a belt at 0.1 (F_d/F_s alternating 0.2/0.4 and 0.1/0.35), started
from q_i = 0.5 sin(i) at rest: sustained stick-slip (the switch rate stays
steady over the run) with masses sticking while their neighbours slip.

1. Exact engine (``frictionflow.solvers.structure.run_assembly``) against the
   independent scipy event integrator of the tests
   (``tests/structure/reference.py``: DOP853 per phase, events for stick,
   release and contact loss, linear phase matrices formed once per phase) on
   the 2-mass and the 10-mass chain.  The reference runs at several rtol; for
   each: its largest switch-time error against the exact engine, its CPU
   time, and the ratio.  Headlines: the ratio at the loosest rtol whose
   switch times agree with the engine's to 1e-9 (all switches found, none
   added), and at rtol 1e-13, the reference's best (switch times to ~1e-11,
   the nearest scipy comes to the exact engine's accuracy: a lower bound).  Goal >= 100x, moonshot 1000x.
   The same with the outputs the engine always gives: the reference also
   integrates each element's work (``work=True``: springs, dampers, forces, belt input and heat per contact,
   what ``simulate`` reports as power flow); its accuracy is then the switch times to 1e-9 and every
   channel's final work to 1e-9 of the largest.  Both comparisons are printed: the first is the
   issue's headline (switch times only), the second says what a scipy user pays for the same answers.
2. The exact engine on chains of n = 2, 10, 30, 100 masses over the same
   time: switches, CPU time, time per switch and how it grows with n
   (the exponent between successive n).
3. The 10-mass chain over t_end = 100, 400, 1000: the time per switch of
   longer runs.  A run that outgrows its records runs again from the start
   with larger ones; they are sized from an estimate of the switches and then
   from the full run's pace, so this row shows what a rerun would cost
   (doubling from 1,024 rows cost about twice the time per switch at t_end
   400 and 1000, docs/performance.md).

Times are CPU times of this process (best of several), so that load from
other processes disturbs them less (on a loaded machine set OPENBLAS_NUM_THREADS=1:
threaded BLAS on small matrices costs the engine several times over).  Measured
(docs/performance.md, session 10): 2 masses 6.8 us per switch, 154x scipy at the same accuracy
(switch times), 223x against rtol 1e-13, 431x with every element's work; 10 masses 24 us per
switch, 29x / 36x, 64x with the works (213 of its 278 switches enter a new stuck set);
30 masses 73 us; 100 masses 0.50 ms.  The scaling table's last columns: the chain's pieces per
phase (runs of slipping masses between stuck ones) and the share of a phase's event functions x
modes in the pieces next to the contacts that switched (what per-piece phases could save).  Both sides record no dense samples
(only the switches and the ends).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from _common import header

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tests' reference integrator and chains

from tests.structure import reference  # noqa: E402
from tests.structure.chains import chain  # noqa: E402

from frictionflow import Coulomb  # noqa: E402

RTOLS = (1e-6, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13)
T_END = {2: 400.0, 10: 100.0}
#: the scaling runs' end times (the 100-mass chain switches about as often as the 10-mass one per unit time, at
#: milliseconds a switch)
T_SCALING = {2: 100.0, 10: 100.0, 30: 100.0, 100: 10.0}
ACCURACY = 1e-9


def chain_case(n: int):
    """The benchmark's chain of ``n`` masses (see the module's docstring)."""
    laws = [Coulomb(0.2, 0.4) if i % 2 == 0 else Coulomb(0.1, 0.35) for i in range(n)]
    return chain(n, [0.1] * n, laws, q0=0.5 * np.sin(np.arange(1, n + 1)))


def cpu_best_of(fn, repeat: int = 3) -> float:
    """Smallest CPU time of ``repeat`` calls."""
    best = math.inf
    for _ in range(repeat):
        t = time.process_time()
        fn()
        best = min(best, time.process_time() - t)
    return best


def repeats(seconds: float) -> int:
    """How many calls to time: a few for slow ones, more for fast ones (about 1 s in all)."""
    return int(min(50, max(3, 1.0 / max(seconds, 1e-6))))


def switch_error(ref_switches: np.ndarray, switches: np.ndarray) -> float:
    """Largest switch-time difference (inf when the two find a different number of switches)."""
    if len(ref_switches) != len(switches):
        return math.inf
    return float(np.max(np.abs(ref_switches - switches))) if len(switches) else 0.0


def engine_timing(run_assembly, asm, t_end: float) -> tuple[float, np.ndarray, np.ndarray]:
    """CPU time of the exact engine on ``asm``, its switch times and its works at ``t_end`` (after a compiling run)."""
    motion = run_assembly(asm, t_end)
    once = cpu_best_of(lambda: run_assembly(asm, t_end), 1)
    t = cpu_best_of(lambda: run_assembly(asm, t_end), repeats(once))
    sw = motion.switches
    return t, np.asarray(sw["t"] if isinstance(sw, dict) else sw, dtype=float), motion.work[:, -1]


def work_error(ref_work: np.ndarray, work: np.ndarray) -> float:
    """Largest difference of the channels' final works, relative to the largest of them."""
    return float(np.max(np.abs(ref_work - work)) / max(np.max(np.abs(work)), 1e-300))


def headline(rows, label: str) -> None:
    """The ratio at the loosest rtol whose answers reach ACCURACY, and at the tightest rtol."""
    reached = [r for r in rows if r[1] <= ACCURACY]
    if reached:
        rtol, err, t_ref = reached[0]
        print(f"{label}: same accuracy ({ACCURACY:g}) at scipy rtol {rtol:g} (error {err:.1e}): "
              f"exact {t_ref:.0f}x faster (goal >= 100x, moonshot 1000x)")
    rtol, err, t_ref = rows[-1]
    print(f"{label}: scipy at its best (rtol {rtol:g}, error {err:.1e}): exact {t_ref:.0f}x faster")


def compare(n: int, run_assembly) -> None:
    """Part 1 for the chain of ``n`` masses: switch times only, then with every element's work."""
    asm, t_end = chain_case(n), T_END[n]
    if run_assembly is not None:
        t_exact, switches, works = engine_timing(run_assembly, asm, t_end)
    else:  # no engine yet: the reference at its tightest stands in as the target, and no ratio
        best = reference.integrate(asm, t_end, rtol=3e-14, atol=1e-16, work=True)
        t_exact, switches, works = math.nan, best.switches, best.work[:, -1]
    print(f"\n## {n}-mass chain, t_end {t_end:g}: {len(switches)} switches")
    print(f"exact engine {t_exact * 1e3:10.3f} ms  ({t_exact / max(len(switches), 1) * 1e6:.2f} us per switch)")
    print(f"{'rtol':>8} {'switches':>9} {'switch err':>11} {'CPU ms':>10} {'ratio':>9}"
          f" | with works: {'error':>9} {'CPU ms':>10} {'ratio':>9}")
    plain, full = [], []
    for rtol in RTOLS:
        run = lambda work: reference.integrate(asm, t_end, rtol=rtol, atol=rtol * 1e-2, work=work)  # noqa: E731
        ref, ref_w = run(False), run(True)
        t_ref = cpu_best_of(lambda: run(False), 3)
        t_ref_w = cpu_best_of(lambda: run(True), 3)
        err = switch_error(ref.switches, switches)
        err_w = max(switch_error(ref_w.switches, switches), work_error(ref_w.work[:, -1], works))
        plain.append((rtol, err, t_ref / t_exact))
        full.append((rtol, err_w, t_ref_w / t_exact))
        print(f"{rtol:8.0e} {len(ref.switches):9d} {err:11.2e} {t_ref * 1e3:10.1f} {t_ref / t_exact:9.0f}x"
              f" | {err_w:20.2e} {t_ref_w * 1e3:10.1f} {t_ref_w / t_exact:9.0f}x")
    headline(plain, "switch times")
    headline(full, "with every element's work")


def pieces(modes: np.ndarray) -> list[list[int]]:
    """The chain's pieces in one combination: the runs of masses whose contacts slip (``modes``: one per mass)."""
    out, run = [], []
    for i, mode in enumerate(modes):
        if mode == 0:
            out, run = (out + [run] if run else out), []
        else:
            run.append(i)
    return out + [run] if run else out


def piece_cost(piece: list[int], modes: np.ndarray) -> int:
    """Event functions x modal coordinates of one piece: its slipping contacts' functions, the two of each
    stuck contact bordering it, times its masses."""
    borders = {i for i in (piece[0] - 1, piece[-1] + 1) if 0 <= i < len(modes)}
    return (len(piece) + 2 * len(borders)) * len(piece)


def locality(modes: np.ndarray) -> tuple[float, float]:
    """(pieces per phase, the share of a phase's event-function work in the pieces a switch touches).

    A stuck mass cuts the chain into pieces that move independently; a walk per piece would restart only
    the pieces next to the contacts that switched.  The share compares their functions x coordinates with
    the whole chain's (what the walk evaluates today): it bounds what per-piece phases could save there.
    ``modes``: the run's modes at its samples (contacts x samples; the benchmark's chain, contact i on mass i).
    """
    counts, local, whole = [], 0, 0
    for s in range(1, modes.shape[1]):
        after, changed = modes[:, s], np.flatnonzero(modes[:, s - 1] != modes[:, s])
        if not len(changed):
            continue
        cut = pieces(after)
        counts.append(len(cut))
        whole += sum(1 if m else 2 for m in after) * sum(len(p) for p in cut)
        local += sum(piece_cost(p, after) for p in cut if any(abs(i - j) <= 1 for i in p for j in changed))
    return float(np.mean(counts)), local / max(whole, 1)


def scaling(run_assembly) -> None:
    """Part 2: the exact engine's time per switch on chains of growing n, and how local its switches are."""
    print(f"\n## exact engine on longer chains, t_end {T_SCALING}")
    print(f"{'n':>5} {'switches':>9} {'CPU ms':>10} {'us/switch':>10} {'growth':>8} {'pieces':>7} {'touched':>8}")
    prev = None
    for n in (2, 10, 30, 100):
        t, switches, _ = engine_timing(run_assembly, chain_case(n), T_SCALING[n])
        per = t / max(len(switches), 1)
        growth = "" if prev is None else f"n^{math.log(per / prev[1]) / math.log(n / prev[0]):.2f}"
        count, share = locality(np.asarray(run_assembly(chain_case(n), T_SCALING[n]).modes))
        print(f"{n:5d} {len(switches):9d} {t * 1e3:10.2f} {per * 1e6:10.2f} {growth:>8} {count:7.1f} {share:8.0%}")
        prev = (n, per)


def horizons(run_assembly) -> None:
    """Part 3: the 10-mass chain's time per switch over longer runs (a run that outgrows its first records is run
    again: the records are sized from an estimate, then from the pace of the run that filled them)."""
    print("\n## exact engine, 10 masses, longer runs")
    print(f"{'t_end':>7} {'switches':>9} {'CPU ms':>10} {'us/switch':>10}")
    for t_end in (100.0, 400.0, 1000.0):
        t, switches, _ = engine_timing(run_assembly, chain_case(10), t_end)
        print(f"{t_end:7g} {len(switches):9d} {t * 1e3:10.2f} {t / max(len(switches), 1) * 1e6:10.2f}")


def main() -> None:
    header("multi-DOF exact engine vs scipy DOP853 with events (Coulomb chains)")
    try:
        from frictionflow.solvers.structure import run_assembly
    except ImportError as err:  # the benchmark still times the reference alone
        print(f"# exact engine not available ({err}): reference timings only")
        run_assembly = None
    for n in (2, 10):
        compare(n, run_assembly)
    if run_assembly is not None:
        scaling(run_assembly)
        horizons(run_assembly)


if __name__ == "__main__":
    main()
