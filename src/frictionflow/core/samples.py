"""Writing samples into a run's output arrays (shared by the event-driven kernels)."""

from numba import njit

from .layout import N_WORK


# Inlined by numba (inline="always"), not by LLVM (forceinline): a call of a compiled
# function costs two atomic reference-count updates per array argument -- here seven
# arrays, several times the writes -- and LLVM's inlining keeps them (exact solver
# 496 -> 374 ns per switch).  Small scalar callees are forceinline: cheaper to compile.
@njit(inline="always")
def emit(outs, k, t, x, v, fc, mode, w):
    """Write the single mass's sample ``k`` into ``outs`` (:data:`.records.Samples`); False when the arrays are full.

    (x, v) is the state, ``fc`` and ``mode`` the one contact's.  ``w`` holds
    the N_WORK work integrals accumulated since the previous sample; they
    are written and restart from zero.
    """
    out_t, out_y, out_fc, out_mode, out_w = outs
    if k >= len(out_t):
        return False
    out_t[k] = t
    out_y[0, k] = x
    out_y[1, k] = v
    out_fc[0, k] = fc
    out_mode[0, k] = mode
    for j in range(N_WORK):
        out_w[k, j] = w[j]
        w[j] = 0.0
    return True
