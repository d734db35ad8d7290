"""What a structure's transient tells the shooting (:mod:`.structure`): the count of the cycle it settles on or
nears, the default number of returns, and what a stalled Newton's line adds about it.

A transient settles on a cycle when its section states repeat to simulate's 1e-6 (its analysis's periodic
test, :func:`~frictionflow.analysis.structure.repeating`), and nears one when they repeat to
:data:`NEARING_RTOL`.  Shooting with that cycle's count finds the cycle simulate finds; with another count the
return map jumps between the cycle's crossings (or, forced, its forcing periods), Newton stalls, and the line
says which count to use -- or that the transient is too short, or never settles.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..analysis.structure import repeating, slowest_period
from ..core.assembly import Assembly
from .structure_flow import Flow, crossings

#: the looser repetition test: a transient nearing its cycle
NEARING_RTOL = 1e-3


def cycle_count(flow: Flow, transient: Any, row: int) -> tuple[float, int, str] | None:
    """(period, downward crossings of q'_row = 0 a period, what the transient does in words) of the cycle the
    ``transient`` settles on (simulate's periodic test, 1e-6) or nears (:data:`NEARING_RTOL`), else None."""
    for rtol, how in ((1e-6, "settles on a cycle of period {} (as simulate --model finds it)"),
                      (NEARING_RTOL, f"nears a cycle of period {{}} (its section states repeat to {NEARING_RTOL:g})")):
        found = repeating(transient, rtol=rtol)
        if found is not None:
            period, (t0, t1), _ = found
            times = crossings(flow, transient, row, t0)
            m = int(round(float(np.sum((times >= t0) & (times < t1 - 1e-9 * period))) * period / (t1 - t0)))
            return period, m, how.format(f"{period:.6g}")
    return None


def strobe_count(transient: Any, forcing: float) -> int | None:
    """The forcing periods (1 to 64) of the cycle a forced ``transient`` settles on (simulate's periodic test,
    1e-6) or nears (:data:`NEARING_RTOL`), as simulate's analysis finds its period; None if it has none, or
    one that is not a whole number of forcing periods."""
    for rtol in (1e-6, NEARING_RTOL):
        found = repeating(transient, rtol=rtol)
        if found is not None:
            m = int(round(found[0] / forcing))
            return m if 1 <= m <= 64 and abs(found[0] / forcing - m) <= 1e-2 else None
    return None


def transient_hint(flow: Flow, dof: tuple[str, ...], transient: Any, row: int, returns: int) -> str:
    """What to add to Newton's failure about the ``transient`` (None: none was run; ``dof``: the coordinates'
    names): when it settles on a cycle (the periodic test of simulate's analysis) that crosses the section
    another number of times a period than ``returns``: the return map then jumps between the cycle's crossings, and Newton stalls far from any fixed
    point (QA: a 3-mass chain's cycle crossing x2' = 0 twice a period, "no periodic orbit near this start").

    A transient still converging repeats only to :data:`NEARING_RTOL`; its count is said too.  The map of the
    wrong count has no fixed point, and Newton can creep towards a switch's boundary there down to a residual
    of 1e-9 before it stalls (a random 3-dof structure, its cycle crossing twice).  A transient that does not
    repeat even so is said to be too short.
    """
    if transient is None:
        return ""
    found = cycle_count(flow, transient, row)
    if found is None:
        return too_short("")
    _, m, said = found
    if m < 1 or m == returns:
        return ""
    return (f"; the transient {said} that crosses the section "
            f"{dof[row - flow.n]}' = 0 {m} times a period: returns={m} (orbit --model: --returns {m}) "
            "shoots for it")


def strobe_hint(transient: Any, forcing: float, periods: int) -> str:
    """What to add to Newton's failure on a forced structure about its ``transient`` (None: none was run): the
    cycle it settles on or nears lasting another number of forcing periods than ``periods`` (:func:`strobe_count`:
    then that count), or none (then too short)."""
    if transient is None:
        return ""
    m = strobe_count(transient, forcing)
    if m is None:
        return too_short(" on a cycle of whole forcing periods")
    if m == periods:
        return ""
    return (f"; the transient nears a cycle of {m} forcing periods (its section states repeat to "
            f"{NEARING_RTOL:g}): returns={m} (orbit --model: --returns {m}) shoots for it")


def too_short(what: str) -> str:
    """The stall's hint for a transient that does not repeat even to :data:`NEARING_RTOL`: too short, or a motion
    that never settles on a cycle (chaotic and quasi-periodic ones; a longer transient would not help there)."""
    return (f"; the transient has not settled{what} (its section states do not repeat to {NEARING_RTOL:g} over its "
            "second half): a longer one (t_transient; orbit --model: --t-end) starts nearer a cycle if the motion "
            "settles on one (simulate --model says whether it does: quasi-periodic and chaotic motions do not)")


def slow_hint(asm: Assembly, t_transient: float) -> str:
    """What to add to Newton's failure when the transient was shorter than the structure's slowest time scale
    (a stiff damper's creep or a heavy mass's swing: the start is then far from the orbit along a direction of
    multiplier near 1, where Newton's steps are long and crossing a switch turns them back)."""
    slow = slowest_period(asm)
    if not 0.0 < t_transient < slow:
        return ""
    return (f"; the structure's slowest time scale, 2 pi / its least |lambda| = {slow:.3g}, is longer than the "
            f"transient ({t_transient:g}): a longer one (t_transient; orbit --model: --t-end) starts nearer the orbit")
