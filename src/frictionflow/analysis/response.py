"""Frequency response of the forced oscillator: steady states against the forcing frequency.

At each frequency Omega of the sweep the oscillator runs ``periods`` forcing
periods and the end of the run is analysed as any forced run
(:func:`frictionflow.analyze`: the stroboscopic steady state, the
power averages over whole forcing periods, TR_B = max|X + 2 zeta X'| / F_ex).
The next frequency starts from the state the previous one ended in -- at the
same forcing phase, since every run spans whole periods -- so that sweeping
up and down follows each branch of a multivalued response as far as it
exists: the jumps between branches, and the hysteresis between them, appear
where a branch ends.

The result is an :class:`xarray.Dataset` over (``direction``, ``omega``) with
every quantity of the table (``frictionflow.quantities``), the amplitude
(X_max - X_min) / 2, and the period in forcing periods.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Sequence

import numpy as np

from .. import _validate as check
from .. import quantities as Q
from .._progress import progress_bar
from ..estimate import Estimate, enforce
from ..friction.base import FrictionLaw
from ..params import OMEGA, BeltOscillator
from ..simulate import simulate
from ..solvers.base import Solver
from ..solvers.registry import auto_solver
from .summary import analyze

DIRECTIONS = ("up", "down")
#: extra variables beyond the quantities table: (units, long name)
EXTRA = {
    "amplitude": ("1", "steady-state amplitude (X_max - X_min) / 2"),
    "multiple": ("1", "period of the steady state in forcing periods (0 unless periodic)"),
}


#: forcing periods a response may run at each frequency
PERIODS_RANGE = (8, 10**6)


def check_periods(periods: Any, name: str = "periods") -> int:
    """``periods`` if it is an integer in :data:`PERIODS_RANGE`, else ValueError naming it ``name``."""
    lo, hi = PERIODS_RANGE
    if not (isinstance(periods, (int, np.integer)) and not isinstance(periods, bool) and lo <= periods <= hi):
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {periods!r}")
    return int(periods)


def frequency_response(
    model: BeltOscillator,
    friction: FrictionLaw,
    omegas: Sequence[float],
    *,
    solver: Solver | None = None,
    periods: int = 300,
    directions: Sequence[str] = DIRECTIONS,
    x0: float | None = None,
    v0: float | None = None,
    rtol: float | None = None,
    progress: bool = False,
):
    """Steady states of ``model`` forced at each of ``omegas``, swept up and/or down.

    Parameters
    ----------
    model:
        The oscillator with its forcing amplitude ``fex`` > 0 (its ``omega`` is replaced by each of ``omegas``).
    friction:
        The friction law.
    omegas:
        Forcing frequencies (> 0), in increasing order.
    solver:
        A solver that supports forcing; default: the law's (exact for piecewise-constant laws, else adaptive).
    periods:
        Forcing periods simulated at each frequency (the analysis reads the second half).
    directions:
        ``"up"`` (increasing Omega), ``"down"``, or both (default), as a sequence or one bare string;
        each sweep starts from (x0, v0).
    x0, v0:
        The state each sweep starts from, at its first frequency (default: the law's start,
        :meth:`FrictionLaw.start`, as the command's); every later frequency starts from the state the previous
        one ended in.
    rtol:
        Steady-state tolerance (default: the solver's, as :func:`~frictionflow.analyze`).
    progress:
        Draw a progress bar on stderr.
    """

    check.instance("model", model, BeltOscillator, "a BeltOscillator")
    check.instance("friction", friction, FrictionLaw, "a FrictionLaw")
    omegas = _checked_omegas(omegas)
    model.refuse_moving_belt("a frequency response")
    if not model.forced:
        raise ValueError("fex must be > 0 for a frequency response (the forcing amplitude), got 0")
    check_periods(periods)
    directions = _checked_directions(directions)
    check.instance("progress", progress, (bool, np.bool_), "True or False")
    solver = solver or auto_solver(friction)
    _check_forcing(solver, model, omegas)
    enforce(response_estimate(model, friction, solver, omegas, periods).times(len(directions)))
    names = (*Q.NAMES, *EXTRA)
    out = {n: np.full((len(directions), len(omegas)), np.nan) for n in names}
    with progress_bar("response", len(directions) * len(omegas), enabled=progress) as advance:
        for d, direction in enumerate(directions):
            order = range(len(omegas)) if direction == "up" else range(len(omegas) - 1, -1, -1)
            x, v = x0, v0
            for j in order:
                forced = replace(model, omega=float(omegas[j]))
                traj = simulate(forced, friction, solver, t_end=periods * forced.forcing_period, x0=x, v0=v)
                an = analyze(traj, rtol=rtol)
                for n, value in an.quantities().items():
                    out[n][d, j] = value
                out["amplitude"][d, j] = 0.5 * (an.amplitude["X_max"] - an.amplitude["X_min"])
                out["multiple"][d, j] = an.steady_state.forcing_multiple or 0
                x, v = float(traj.x[-1]), float(traj.v[-1])
                advance(1)
    return _dataset(out, model, friction, solver, omegas, directions, periods)


def response_estimate(model: BeltOscillator, friction: FrictionLaw, solver: Solver, omegas: np.ndarray,
                      periods: int) -> Estimate:
    """One sweep through ``omegas``: a run of ``periods`` forcing periods at each (the solver's estimates, added)."""
    runs = [solver.cost(replace(model, omega=float(w)), friction, periods * 2.0 * np.pi / float(w)) for w in omegas]
    return Estimate(float(len(runs)), f"runs of {periods} forcing periods", sum(r.seconds for r in runs),
                    max(r.memory for r in runs))


#: a response file's fixed part (NetCDF header, coordinates, attributes), rounded up from the 27 kB of a
#: 3-frequency, 2-direction file
_FILE_BYTES = 64 * 2**10


def response_bytes(n_directions: int, n_omegas: int) -> float:
    """Upper estimate of the response dataset's NetCDF size: every quantity at 8 bytes a point, and the header."""
    return _FILE_BYTES + 8.0 * (len(Q.NAMES) + len(EXTRA)) * n_directions * n_omegas


def _check_forcing(solver: Solver, model: BeltOscillator, omegas: np.ndarray) -> None:
    """Refuse, before any run, a frequency the solver cannot force at (the exact solver: a resonance it has no
    closed form for), naming it: found only when the sweep reached it, it cost the runs before."""
    for w in omegas:
        problem = solver.forcing_problem(model.zeta, float(w), model.fex)
        if problem:
            raise ValueError(problem)


def _checked_directions(directions: str | Sequence[str]) -> tuple[str, ...]:
    """``directions`` as a tuple: a bare ``"up"`` or ``"down"`` is one direction, not its letters."""
    try:
        found = (directions,) if isinstance(directions, str) else tuple(directions)
    except TypeError:
        raise ValueError(f"directions must be some of {DIRECTIONS}, got {directions!r}") from None
    if not found or any(not isinstance(d, str) or d not in DIRECTIONS for d in found):
        raise ValueError(f"directions must be some of {DIRECTIONS}, got {directions!r}")
    return found


def _checked_omegas(omegas: Sequence[float]) -> np.ndarray:
    w = _numbers(omegas)
    if w is None or w.ndim != 1 or len(w) < 1:
        raise ValueError(f"omegas must be a non-empty sequence of numbers (the frequencies), got {omegas!r}")
    for value in w:
        OMEGA.check(float(value))
    if np.any(np.diff(w) <= 0):
        raise ValueError("omega must be increasing (FROM < TO)")
    return w


def _numbers(values: object) -> np.ndarray | None:
    """``values`` as a float array when they are numbers (not text, booleans or None), else None."""
    if values is None or isinstance(values, (str, bytes)):
        return None
    try:
        arr = np.asarray(values)
    except (TypeError, ValueError):  # ragged
        return None
    return arr.astype(float) if arr.dtype.kind in "iuf" else None


def _dataset(out: dict, model: BeltOscillator, friction: FrictionLaw, solver: Solver, omegas: np.ndarray,
             directions: Sequence[str], periods: int):
    import xarray as xr

    table = {q.name: q for q in Q.TABLE}
    data = {}
    for n, values in out.items():
        if n in table:
            q = table[n]
            attrs = {"units": q.units, "long_name": q.long_name}
            if q.flags:
                values = values.astype(q.dtype)
                attrs["flag_values"] = list(range(len(q.flags)))
                attrs["flag_meanings"] = " ".join(q.flags)
        else:
            units, long_name = EXTRA[n]
            attrs = {"units": units, "long_name": long_name}
            if n == "multiple":
                values = values.astype("i2")
        data[n] = (("direction", "omega"), values, attrs)
    ds = xr.Dataset(data, coords={"direction": list(directions),
                                  "omega": ("omega", omegas, {"units": "1", "long_name": OMEGA.meaning + " Omega"})})
    params = {k: v for k, v in {**model.report(), **friction.as_dict()}.items() if k != "omega"}
    ds.attrs.update({**{k: v for k, v in params.items() if isinstance(v, (int, float, str))},
                     "solver": solver.name, "periods": int(periods)})
    return ds
