"""Beyond periodic for structures: the largest Lyapunov exponent from two nearby exact runs, and the revisit test.

When a structure's section does not repeat, its steady state is told as
the single mass's forced runs are (:mod:`frictionflow.analysis.forced`),
with the same constants (:mod:`frictionflow.core.strobe`):

``chaotic``
    the largest Lyapunov exponent is positive beyond its uncertainty;
``quasi_periodic``
    the exponent is indistinguishable from 0 and the section's points have
    stopped drifting: every point of the second half lies within
    ``REVISIT_SHARE`` (``frictionflow.core.strobe``) of the motion's size
    (positions and velocities each in their own units) of a point of the first half (a closed curve, revisited), and they do not
    close in on a point or a cycle (:func:`closing_in`: a focus spiralling in
    too slowly for the exponent to tell, |mu| = 0.999 a period, revisits
    itself too);
``not_settled``
    otherwise (a negative exponent: still converging; or drifting).

The exponent is Benettin's: a second run starts ``DELTA`` (relative to the
motion's size) away from the reference, both are run by the exact engine
for one block, the separation's growth is logged and the separation
renormalised back to ``DELTA`` along its own direction, block after block.
Separations are measured with positions and velocities each in units of
their own size (``size``), so that the pair of runs in other units of time
is the same pair and its exponent the same rate.
An autonomous structure's flow has a zero exponent along the motion itself
(a shift in time neither grows nor decays), which would hide a converging
transient and mimic a torus: there the separation's component along the
flow vector is removed at every block end, leaving the transverse growth --
the exponent of the section's return map, which is what the single mass's
stroboscopic section measures when forced.  The run is restarted from a
state at time t by shifting each force's phase by its omega t.  The cost:
the reference run over :data:`~frictionflow.core.strobe.LYAPUNOV_TRANSIENT`
+ :data:`~frictionflow.core.strobe.LYAPUNOV_PERIODS` blocks and one restarted
run per block (each building its modes' decompositions afresh), fewer when
the exponent is clearly negative.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..core import strobe
from ..core.strobe import (LYAPUNOV_PERIODS, LYAPUNOV_SPREAD_FLOOR, LYAPUNOV_STOP, LYAPUNOV_TRANSIENT,
                           REVISIT_SHARE)
from ..core.tangent import _negative
from ..solvers.structure import run_assembly

#: the separation of the two runs, relative to the motion's size (small against it, large against rounding)
DELTA = 1e-7
#: the flow vector is the reference's backward difference over this share of a block
FLOW_STEP = 1e-6
#: a contact whose |V_r| at a block's start is below this share of its terms' size is stuck there (its
#: velocity is put on its belt: a change far below the pair's separation, DELTA)
STUCK_SHARE = 1e-11


def restart(assembly: Any, state: np.ndarray, t: float) -> Any:
    """``assembly`` started from ``state`` (q, q') at time ``t``: the forces' phases shifted by omega t."""
    n = len(state) // 2
    return assembly._replace(q0=np.array(state[:n], dtype=float), v0=np.array(state[n:], dtype=float),
                             force_phi=np.asarray(assembly.force_phi) + np.asarray(assembly.force_omega) * t)


def _flow(reference: Any, t: float, span: float, size: np.ndarray) -> np.ndarray:
    """The unit flow vector (q', q'') of the reference run at ``t`` in units of ``size``: a second-order backward
    difference."""
    h = FLOW_STEP * span
    s = reference.states(np.array([t - 2.0 * h, t - h, t]))
    f = (3.0 * s[:, 2] - 4.0 * s[:, 1] + s[:, 0]) / (2.0 * h) / size
    size = float(np.linalg.norm(f))
    return f / size if size > 0.0 else f


def on_stick(assembly: Any, state: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(``state`` with its stuck contacts exactly on their belts, ``d`` along their stick): the pair's start.

    A contact stuck in the reference (|V_r| within :data:`STUCK_SHARE` of its
    terms) stays stuck in the perturbed run only if the perturbation keeps
    e . dq' = 0: a velocity kicked off the stick surface starts a slip, an
    O(1) departure that is no exponential growth.  So the states' velocities
    are put on the stuck contacts' belts (least-squares corrections, as the
    engine holds them) and ``d``'s velocity part projected onto e . dq' = 0.
    """
    n = len(state) // 2
    e, belt = np.asarray(assembly.contact_dir, dtype=float).reshape(-1, n), np.asarray(assembly.belt, dtype=float)
    v = state[n:]
    vr = belt - e @ v
    stuck = np.abs(vr) <= STUCK_SHARE * (np.abs(belt) + np.abs(e) @ np.abs(v))
    if not stuck.any():
        return state, d
    es = e[stuck]
    pinv = np.linalg.pinv(es)  # (n, s): the least-squares solution of es . x = r
    fixed, dd = state.copy(), d.copy()
    fixed[n:] = v + pinv @ vr[stuck]
    dd[n:] = d[n:] - pinv @ (es @ d[n:])
    return fixed, dd


def _transverse(d: np.ndarray, flow: np.ndarray | None) -> np.ndarray:
    """``d`` without its component along the unit ``flow`` (None: unchanged)."""
    return d if flow is None else d - (flow @ d) * flow


def largest_exponent(motion: Any, block: float, autonomous: bool, size: np.ndarray,
                     blocks: tuple[int, int] = (LYAPUNOV_TRANSIENT, LYAPUNOV_PERIODS),
                     stop: tuple = LYAPUNOV_STOP) -> tuple[float, float] | None:
    """(largest exponent, its uncertainty) of the structure's flow from the end of ``motion``; None if unavailable.

    The uncertainty is the range of the running estimate over the second half
    of the averaged blocks, at least ``spread_floor(block)``.
    None when a run of the pair loses a contact or the engine cannot go on.

    Parameters
    ----------
    motion:
        A run (:class:`~frictionflow.motion.Motion`) that ended ``ok``; the exponent is measured after it.
    block:
        The time between renormalisations (a forcing period, or the section's mean return time).
    autonomous:
        No force: the separation along the flow is removed at every block end (see the module's description).
    size:
        (2n,) per state row, the motion's size in the row's units (> 0): separations are measured in them.
    blocks:
        (transient blocks, averaged blocks).
    stop:
        The single mass's early end (``LYAPUNOV_STOP`` of ``frictionflow.core.strobe``): once the running
        estimate is below -factor times its uncertainty the kind is settled as not chaotic.
    """
    a, t0 = motion.assembly, float(motion.t[-1])
    n_transient, n_blocks = blocks
    floor = spread_floor(block)
    stop = (*stop[:3], stop[3] * floor / LYAPUNOV_SPREAD_FLOOR)
    try:  # the run's own solver and tolerances: its laws, its accuracy
        reference = run_assembly(restart(a, motion.state[:, -1], t0), (n_transient + n_blocks) * block,
                                 dense_dt=block, solver=motion.solver, settings=motion.settings)
    except RuntimeError:
        return None
    size = np.asarray(size, dtype=float)
    if reference.status != "ok" or not np.all(size > 0.0):
        return None
    est = np.full((n_blocks, 1), np.nan)
    ends = reference.states(block * np.arange(n_transient + n_blocks + 1))
    u = _transverse(np.ones(ends.shape[0]), _flow(reference, block, block, size) if autonomous else None)
    total = 0.0
    for b in range(n_transient + n_blocks):
        grown = _one_block(reference, a, (ends[:, b], ends[:, b + 1], size), t0 + b * block,
                           u * (DELTA / np.linalg.norm(u)), block, autonomous, b)
        if grown is None:
            return None
        u, gain = grown
        if b >= n_transient:
            k = b - n_transient
            total += math.log(gain)
            est[k, 0] = total / ((k + 1) * block)
            if _negative(est, k + 1, stop):
                return _result(est[:k + 1, 0], floor)
    return _result(est[:, 0], floor)


def _one_block(reference: Any, a: Any, states: tuple[np.ndarray, np.ndarray, np.ndarray], t: float, d: np.ndarray,
               block: float, autonomous: bool, b: int) -> tuple[np.ndarray, float] | None:
    """(the separation's new direction, its growth over the block) for the pair started ``d`` apart at ``t``
    (``d`` along the stick of the contacts stuck there: :func:`on_stick`); ``states``: the reference's states
    at the block's start and end and the size separations are measured in (``d`` is in its units)."""
    start, end, scale = states
    length = float(np.linalg.norm(d))
    start, d = on_stick(a, start, d * scale)  # the stick's projection acts on velocities alone: one unit
    d = d / scale
    norm_d = float(np.linalg.norm(d))
    if not norm_d > 0.0:
        return None
    d = d * (length / norm_d)
    try:
        other = run_assembly(restart(a, start + d * scale, t), block, solver=reference.solver,
                             settings=reference.settings)
    except RuntimeError:
        return None
    if other.status != "ok":
        return None
    flow = _flow(reference, (b + 1) * block, block, scale) if autonomous else None
    sep = _transverse((other.state[:, -1] - end) / scale, flow)
    norm = float(np.linalg.norm(sep))
    if not (math.isfinite(norm) and norm > 0.0):
        return None
    return sep / norm, norm / float(np.linalg.norm(d))


def spread_floor(block: float) -> float:
    """The least uncertainty of an exponent measured over blocks of ``block``: ``LYAPUNOV_SPREAD_FLOOR``
    (``frictionflow.core.strobe``, the single mass's, whose forcing period is about 2 pi) per 2 pi of
    ``block``.  A rate in the model's own time: the same structure in other units of time (masses times s^2,
    dampers times s, belts and frequencies over s) has its exponents over s and is told the same way; an absolute
    floor called a chaotic chain of masses 1e6 not settled."""
    return LYAPUNOV_SPREAD_FLOOR * 2.0 * math.pi / block


def _result(running: np.ndarray, floor: float) -> tuple[float, float]:
    half = running[len(running) // 2:]
    return float(running[-1]), max(float(np.ptp(half)), floor)


def revisits(points: np.ndarray, tol: float) -> bool:
    """Whether every section point (column of ``points``) of the second half lies within ``tol`` (max-norm)
    of some point of the first half; at least 8 points in each half (the single mass's
    :func:`frictionflow.core.strobe.revisits`, in any number of components)."""
    h = points.shape[1] // 2
    if h < 8:
        return False
    first = points[:, :h]
    for b in range(h, points.shape[1]):
        if not float(np.min(np.max(np.abs(first - points[:, b:b + 1]), axis=0))) <= tol:
            return False
    return True


def closing_in(points: np.ndarray) -> bool:
    """Whether the section's points (columns, in time order) close in on a point or a cycle
    (:func:`frictionflow.core.strobe.closing_in`, the single mass's test too)."""
    return bool(strobe.closing_in(np.ascontiguousarray(points, dtype=float)))


def beyond_periodic(motion: Any, section: np.ndarray, size: np.ndarray, block: float,
                    autonomous: bool) -> tuple[str, float | None]:
    """(kind, largest exponent or None) of a run whose section ``section`` (states as columns) does not repeat.

    The single mass's rule (``frictionflow.analysis.forced.classify_forced``): ``chaotic`` if the
    exponent exceeds its uncertainty, ``quasi_periodic`` if it is within it and the section revisits
    itself to ``REVISIT_SHARE`` (``frictionflow.core.strobe``) of its size without closing in on a point or a cycle
    (``closing_in``), else ``not_settled``.

    Parameters
    ----------
    motion:
        The run (:class:`~frictionflow.motion.Motion`, ended ``ok``).
    section:
        (2n, m): the states at the section's crossings, in time order.
    size:
        (2n,) per state row, the motion's size in its units (> 0): the revisit test's tolerance is a share of
        it, and the exponent's separations are measured in it.
    block:
        The exponent's renormalisation time (:func:`largest_exponent`).
    autonomous:
        No force acts: the exponent is the transverse one.
    """
    found = largest_exponent(motion, block, autonomous, size)
    if found is None:
        return "not_settled", None
    lam, spread = found
    if lam > spread:
        return "chaotic", lam
    if abs(lam) <= spread and revisits(section / size[:, None], REVISIT_SHARE) and not closing_in(section / size[:, None]):
        return "quasi_periodic", lam
    return "not_settled", lam
