"""The structure engine's entry points that release the GIL, so that many points run at once on threads.

A model sweep's points each run the engine (:func:`.run.run`) and then
evaluate the exact motion on grids (:func:`.evaluate.states`) for their
analysis.  Called through these wrappers, compiled with ``nogil=True``, the
compiled parts of several points proceed in parallel on the threads of
:func:`frictionflow.core.threads.over_points`, while the Python parts take
turns.  The wrappers pass their arguments through unchanged, so a run
gives the same bits whichever way it is called.
"""

from __future__ import annotations

from numba import njit

from .evaluate import states
from .run import run


@njit(cache=True, nogil=True)
def run_released(*args):
    """:func:`.run.run` with the GIL released (same arguments, same result)."""
    return run(*args)


@njit(cache=True, nogil=True)
def states_released(*args):
    """:func:`.evaluate.states` with the GIL released (same arguments, same result)."""
    return states(*args)
