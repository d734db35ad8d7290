"""The records the single-run kernels take: their output buffers.

Module-level named tuples (numba types them as records, and a kernel that
takes them can still be cached): a kernel unpacks them once at its top.

==============  ==========================================================
``Samples``     the arrays a run writes its samples into, one row per
                sample: tau, X, X', F_c, the friction mode (int8) and the
                work integrals since the previous sample (``(cap, N_WORK)``)
``Events``      the arrays of the switches: tau and the mode entered
                (int64); a run counts every switch but writes only as
                many as fit
==============  ==========================================================

The force record ``p`` (:mod:`.layout`), the initial state and the run's
settings (end, tail, dense grid, stop rules) stay plain arguments: a record
passed from Python costs the call about 0.5 us more than its fields would
(numba types a named tuple in Python, arrays and floats in C), so only the
buffers, which go together everywhere, are records.
"""

from __future__ import annotations

from collections import namedtuple

Samples = namedtuple("Samples", "t x v fc mode work")
Events = namedtuple("Events", "t mode")
