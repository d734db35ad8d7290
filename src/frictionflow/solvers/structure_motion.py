"""The records every structure solver's kernel writes, and the :class:`~frictionflow.motion.Motion` read from them.

Both structure engines (:mod:`frictionflow.core.structure.run`, the exact one,
and :mod:`frictionflow.core.structure.adaptive`) write the shared
:data:`~frictionflow.core.records.Samples` (y = (q, q'), one ``fc``/``mode``
row per contact, each sample's work since the previous one, a column per
channel) and :data:`~frictionflow.core.records.Events`; the adaptive one also
writes :data:`~frictionflow.core.records.Derivatives`, the slopes its Motion
interpolates with.

A run that fills its records is run again from the start with larger ones
(the kernels keep no state between calls, so the second run is the first
one's bits): :func:`first_capacity` sizes the first attempt from an estimate
of the samples, :func:`regrow` the next from the pace the full one kept.
A run estimated to take more than :data:`INTERRUPT_AFTER` seconds runs on a
thread of its own (``frictionflow._interrupt.interruptible``): a compiled run never returns to
Python before its end, so Ctrl-C and SIGTERM would wait for it (minutes for
a large model).  Shorter ones do not pay the thread (~0.15 ms a run: a
Lyapunov exponent's hundreds of short runs would).
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from ..core import codes
from ..core.assembly import Assembly
from ..core.friction import ON_LIMIT
from ..core.layout import FD, FS, RESULTANT, STICK
from ..core.records import Derivatives, Events, Samples, empty_derivatives, empty_events, empty_samples
from ..core.structure.combo import split
from ..core.structure.run import Result
from ..core.structure.stick import held, normal_load
from ..core.structure.work import n_channels
from .._interrupt import interruptible
from ..motion import Motion
from .base import check_memory


#: bytes the records of a first attempt may take; a run that needs more grows them from its own pace
FIRST_BYTES = 32_000_000
#: the margin on a full run's pace carried to its end
PACE_MARGIN = 1.25


def row_bytes(assembly: Assembly, derivatives: bool = False) -> int:
    """Bytes of one sample and one switch in :func:`buffers` (read off records of one row), with the
    adaptive solver's :data:`~frictionflow.core.records.Derivatives` if ``derivatives``."""
    records = buffers(assembly, 1)
    if derivatives:
        records = (*records, empty_derivatives(1, len(assembly.q0), n_channels(assembly)))
    return sum(part.nbytes for record in records for part in record)


def memory_room(assembly: Assembly, span: tuple[float, float | None], max_memory: float,
                derivatives: bool = False) -> Callable[[float], None]:
    """A check that records of so many rows fit ``max_memory`` GiB (a one-line ValueError otherwise), for
    :func:`run_growing`'s attempts; the dense grid's samples of ``span`` = (t_end, dense_dt), a bound from
    below on every run's, are checked at once, before any work.  ``derivatives``: as :func:`row_bytes`."""
    t_end, dense_dt = span
    row = row_bytes(assembly, derivatives)
    what = f"a run to t_end={t_end:g}" + (f" sampled every dense_dt={dense_dt:g}" if dense_dt else "")

    def room(rows: float) -> None:
        check_memory(rows, max_memory, what, row)

    room(t_end / dense_dt + 1.0 if dense_dt else 1.0)
    return room


def first_capacity(assembly: Assembly, expected: float, floor: int) -> int:
    """Rows of the first attempt's records: ``expected`` (an estimate of the samples), at least ``floor``, at most
    what :data:`FIRST_BYTES` holds."""
    most = max(floor, FIRST_BYTES // row_bytes(assembly))
    return int(min(max(float(expected), floor), most))


def regrow(res: Result, records: tuple[Samples, Events], t_end: float, cap: int) -> int:
    """Rows for running again a run ``res`` that outgrew records of ``cap`` rows.

    The samples' pace up to the last one written, carried to ``t_end`` with
    :data:`PACE_MARGIN` to spare (a run that filled its records early needs
    one more attempt, not several doublings), at least twice ``cap`` and
    the switches counted.
    """
    s = res.n_samples
    reached = float(records[0].t[s - 1]) if s else 0.0
    pace = s * t_end / reached if reached > 0.0 else 0.0
    return int(max(2 * cap, res.n_switches + 1, math.ceil(PACE_MARGIN * pace)))


#: a run estimated (by its solver's own estimate, an upper bound) to take longer goes on its own thread
INTERRUPT_AFTER = 0.1


def run_growing(t_end: float, cap: int, attempt: Callable[[int], tuple], seconds: float,
                room: Callable[[float], None]) -> tuple:
    """``attempt(cap)``'s answer once its records hold the whole run, :func:`regrow` between attempts.

    ``attempt`` runs a kernel from the start on new records of ``cap`` rows
    and returns (its Result, the Samples, the Events, any further records); each attempt runs
    ``interruptible`` when the run's estimate ``seconds`` exceeds :data:`INTERRUPT_AFTER`.
    ``room(cap)`` (:func:`memory_room`) refuses records too large before each attempt.
    """
    while True:
        room(cap)
        out = interruptible(lambda: attempt(cap)) if seconds > INTERRUPT_AFTER else attempt(cap)
        res = out[0]
        if res.status != codes.FULL and res.n_switches <= cap:
            return out
        cap = regrow(res, out[1:3], t_end, cap)


def buffers(assembly: Assembly, cap: int) -> tuple[Samples, Events]:
    """The shared records (:mod:`frictionflow.core.records`) for ``cap`` samples and switches of ``assembly``."""
    n, k = len(assembly.q0), len(assembly.belt)
    return empty_samples(cap, 2 * n, k, n_channels(assembly)), empty_events(cap)


def stopped(res: Result, records: tuple[Samples, Events], names: dict[str, tuple[str, ...]], solver: str,
            assembly: Assembly | None = None) -> str:
    """The one line for a run that stopped before its end: the solver, when, the status, and for repeated
    zero-length phases the contact whose mode flipped last (with ``assembly``: why, where :func:`sliding_hint` can
    tell)."""
    out, events = records
    t = float(out.t[res.n_samples - 1]) if res.n_samples > 0 else 0.0
    text = f"solver={solver}: the run stopped at t={t:.12g} with status '{codes.NAMES[res.status]}'"
    if res.status == codes.STUCK and 0 < res.n_switches <= len(events.t) and res.n_samples > 0:
        j = int(events.contact[res.n_switches - 1])
        text += f" ({names['contact'][j]} switched without time passing)"
        if assembly is not None:
            i = res.n_samples - 1
            text += sliding_hint(assembly, (out.y[:, i], t, out.mode[:, i]), j)
    return text


def sliding_hint(assembly: Assembly, at: tuple[np.ndarray, float, np.ndarray], j: int) -> str:
    """Why contact ``j`` flipped without time passing at ``at`` = (state (q, q'), t, modes), where the reason is the
    "spring" stick rule's: it says let go (its held force without the dampers' is on or over F_s N), but the whole
    held force is below F_d N, so slipping either way turns V_r straight back to 0 -- a sliding motion the switch model
    cannot represent (the single mass's exact solver says the same).  "" when that is not the reason."""
    if assembly.law[j, RESULTANT] != 0.0:
        return ""
    n = len(assembly.q0)
    y, t, modes = at
    q, v = np.ascontiguousarray(y[:n]), np.ascontiguousarray(y[n:2 * n])
    stuck = np.array(modes, dtype=np.int8)  # (int8, as the engine's: the split and held forces compiled once)
    stuck[j] = STICK
    cb = split(assembly, np.linalg.inv(assembly.mass), stuck)
    rule, whole = held(assembly, cb, q, v, float(t))
    i = int(np.flatnonzero(cb.stuck == j)[0])
    load = float(normal_load(assembly, j, q))
    if abs(rule[i]) < assembly.law[j, FS] * load * (1.0 - ON_LIMIT) or abs(whole[i]) >= assembly.law[j, FD] * load:
        return ""
    return (f": its stick rule (stick_force \"spring\") says slip (held force without the dampers' {abs(rule[i]):.6g} "
            f">= F_s N = {assembly.law[j, FS] * load:.6g}) but both slip directions return it to its belt (the whole "
            f"held force {abs(whole[i]):.6g} < F_d N = {assembly.law[j, FD] * load:.6g}), a sliding motion the switch "
            "model cannot represent; use stick_force = \"resultant\"")


def motion(res: Result, records: tuple[Samples, Events], assembly: Assembly, names: dict[str, tuple[str, ...]],
           channels: tuple[str, ...], system: Any = None, derivatives: Derivatives | None = None,
           solver: str = "exact", settings: dict[str, Any] | None = None) -> Motion:
    """The :class:`~frictionflow.motion.Motion` of the run ``res`` (status OK or CONTACT_LOST) from its records.

    Parameters
    ----------
    res:
        The kernel's :data:`~frictionflow.core.structure.run.Result`: the samples and switches written.
    records:
        The :data:`~frictionflow.core.records.Samples` and :data:`~frictionflow.core.records.Events` it wrote.
    assembly:
        The structure that ran.
    names:
        ``dof`` and per kind the element names.
    channels:
        The work channels' names (the order of the samples' work columns).
    system:
        The model object the assembly came from, kept on the result.
    derivatives:
        The slopes at the samples (the adaptive kernel's), or None.
    solver:
        The solver's name.
    settings:
        The solver's own settings by keyword (:attr:`~frictionflow.motion.Motion.settings`).
    """
    out, events = records
    s, w = res.n_samples, res.n_switches
    lost = None if res.status == codes.OK else (names["contact"][res.lost_contact], float(res.lost_time))
    der = {} if derivatives is None else {"accel": derivatives.accel[:, :s].copy(),
                                          "power": derivatives.power[:, :s].copy()}
    return Motion(  # Motion keeps the cumulative work, a row per channel: the records hold each sample's share
        t=out.t[:s].copy(), state=out.y[:, :s].copy(), force=out.fc[:, :s].copy(),
        modes=out.mode[:, :s].copy(), work=np.cumsum(out.work[:s], axis=0).T.copy(), channels=channels,
        switches=events.t[:w].copy(), switch_contact=events.contact[:w].copy(),
        switch_mode=events.mode[:w].astype(np.int8),
        dof=names["dof"], contacts=names["contact"], status="ok" if lost is None else "contact_lost",
        assembly=assembly, lost=lost, system=system, elements={k: v for k, v in names.items() if k != "dof"},
        solver=solver, settings=dict(settings or {}), **der,
    )
