"""The adaptive solver's runs of linear structures (any switch-rule law with a compiled slip curve).

:func:`frictionflow.solvers.structure.run_assembly` checks the run and names
its elements, then calls :func:`run` here: the kernel
(:mod:`frictionflow.core.structure.adaptive`) with buffers that double while
the run reports them full, and the :class:`~frictionflow.motion.Motion` of
its samples (one per step, with the accelerations :meth:`Motion.at`
interpolates from).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core import codes
from ..core.assembly import Assembly
from ..core.records import empty_derivatives
from ..core.structure.adaptive import Opts, run as run_kernel
from ..core.structure.work import n_channels
from ..estimate import SECONDS_PER, Estimate
from ..motion import Motion
from ..system.assemble import fastest_rate, state_scales
from .adaptive import Adaptive
from .base import DEFAULT_MAX_MEMORY
from .structure_motion import buffers, memory_room, motion, row_bytes, run_growing, stopped

#: the longest step, as a fraction of the fastest period's 1/(2 pi) (the single mass's 0.25): the event
#: functions are watched at the step ends only
H_MAX = 0.25
#: ... and without any rate of its own, this share of the run
H_SHARE = 1e-3
#: the first buffer size; doubled while the run reports FULL
FIRST_CAP = 4096


def h_max(assembly: Assembly, t_end: float) -> float:
    """The longest step: :data:`H_MAX` over the structure's fastest rate (its fastest natural, forcing or own
    rate: :func:`~frictionflow.system.assemble.fastest_rate`); without any (masses on belts alone, moving as
    polynomials between switches) ``H_SHARE`` of the run.  H_MAX alone, in the model's units of time, made a
    free mass in units 1e5 times longer take ten million steps."""
    rate = fastest_rate(assembly)
    return H_MAX / rate if rate > 0.0 else H_SHARE * t_end


def tolerances(assembly: Assembly, t_end: float, atol: float) -> np.ndarray:
    """The absolute tolerance of each component of the state (q, q', works): ``atol`` times the structure's
    size of positions, velocities and works (:func:`~frictionflow.system.assemble.state_scales`), so that the
    solver's accuracy does not depend on the model's units."""
    _, position, velocity, work = state_scales(assembly, t_end)
    n = len(assembly.q0)
    return atol * np.concatenate([np.full(n, position), np.full(n, velocity), np.full(n_channels(assembly), work)])


#: steps per longest step's span the estimate assumes (tight tolerances take shorter steps than h_max)
STEPS_PER_H_MAX = 8.0


def step_estimate(assembly: Assembly, t_end: float, dense_dt: float | None = None) -> Estimate:
    """What an adaptive run of ``assembly`` to ``t_end`` costs: :data:`STEPS_PER_H_MAX` steps per
    :func:`h_max`, each the single mass's step cost times the stages' n^2 work (and a sample each)."""
    n = assembly.mass.shape[0]
    steps = STEPS_PER_H_MAX * (t_end / h_max(assembly, t_end) + 1.0)
    samples = steps + (0.0 if not dense_dt else t_end / dense_dt)
    return Estimate(steps, f"steps of a {n}-dof structure", steps * SECONDS_PER["adaptive_step"] * max(n, 1) ** 2,
                    memory=samples * row_bytes(assembly, derivatives=True))


def run(assembly: Assembly, span: tuple[float, float | None], settings: Adaptive, elements: dict[str, tuple[str, ...]],
        channels: tuple[str, ...], system: Any = None, max_memory: float = DEFAULT_MAX_MEMORY) -> Motion:
    """Run ``assembly`` to t_end with the adaptive solver's ``settings`` (rtol, atol, max_steps).

    Parameters
    ----------
    assembly:
        The structure, its laws checked by the caller.
    span:
        (t_end > 0, dense_dt or None): the end time and the sampling step, in the model's units of time
        (checked by the caller: the solver's own ``dense_dt`` range is the single mass's).
    settings:
        The solver (:class:`~frictionflow.solvers.adaptive.Adaptive`) with its tolerances.
    elements:
        ``dof`` and per kind the element names.
    channels:
        The work channels' names.
    system:
        The model object the assembly came from, kept on the result.
    max_memory:
        GiB the run's records may take (:func:`~.structure_motion.memory_room`).
    """
    t_end, dense_dt = span
    room = memory_room(assembly, (float(t_end), dense_dt), max_memory, derivatives=True)
    opts = Opts(float(t_end), float(settings.rtol), tolerances(assembly, t_end, settings.atol), h_max(assembly, t_end),
                float(dense_dt or 0.0), int(settings.max_steps), state_scales(assembly, t_end)[0])
    minv = np.linalg.inv(assembly.mass)

    def attempt(cap: int) -> tuple:
        records = buffers(assembly, cap)
        der = empty_derivatives(cap, len(assembly.q0), n_channels(assembly))
        return run_kernel(assembly, minv, opts, *records, der), *records, der

    res, *records, der = run_growing(float(t_end), FIRST_CAP, attempt, step_estimate(assembly, t_end, dense_dt).seconds,
                                     room)
    if res.status not in (codes.OK, codes.CONTACT_LOST):
        raise RuntimeError(f"{stopped(res, records, elements, settings.name)} (max_steps={settings.max_steps})")
    own = {"rtol": settings.rtol, "atol": settings.atol, "max_steps": settings.max_steps}
    return motion(res, records, assembly, elements, channels, system, der, settings.name, own)
