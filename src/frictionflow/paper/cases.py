"""Data sets of a few parameter points run with both solvers (Figs. 2, 3 and 4)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .._lazy import lazy_module
from .results import PointResult, Runner
from .runs import SOLVERS, Point

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

#: per-(solver, case) scalars: name -> how to read it off a PointResult
SCALARS = {
    "last_P_dv": lambda r: r.last.P_dv,
    "last_P_fin": lambda r: r.last.P_fin,
    "last_P_df": lambda r: r.last.P_df,
    "last_R_c": lambda r: r.last.R_c,
    "last_R_f": lambda r: r.last.R_f,
    "last_TR_B": lambda r: r.last.TR_B,
    "last_amplitude": lambda r: r.last.amplitude,
    "last_net_friction": lambda r: r.last.net_friction,
    "last_dE": lambda r: r.last.dE,
    "last_net_friction_from_min": lambda r: r.last_from_min.net_friction,
    "last_R_f_from_min": lambda r: r.last_from_min.R_f,
    "window_start": lambda r: r.last.t0,
    "window_end": lambda r: r.last.t1,
    "peak_P_dv": lambda r: r.peaks["P_dv"],
    "peak_P_f": lambda r: r.peaks["P_f"],
    "period": lambda r: r.period,
    "decay_rate": lambda r: r.decay_rate,
    "t_terminal": lambda r: r.t_terminal,
    "steady_P_dv": lambda r: r.steady["P_dv"],
    "steady_P_fin": lambda r: r.steady["P_fin"],
    "steady_P_df": lambda r: r.steady["P_df"],
    "steady_TR_B": lambda r: r.steady["TR_B"],
    "steady_V_max": lambda r: r.steady["V_max"],
    "energy_residual": lambda r: r.steady["energy_residual"],
    "stick_fraction": lambda r: r.steady["stick_fraction"],
}


def cases_dataset(runner: Runner, cases: Sequence[Point]) -> xr.Dataset:
    """The shown end of each run and its scalars, over (solver, case[, tau])."""
    res: list[list[PointResult]] = [[runner.result(p, s) for p in cases] for s in SOLVERS]
    tau = res[0][0].tau

    def stack(get) -> np.ndarray:
        return np.array([[get(r) for r in row] for row in res])

    hist = {
        "X": stack(lambda r: r.x),
        "V": stack(lambda r: r.v),
        "F_c": stack(lambda r: r.fc),
        "P_f": stack(lambda r: r.p_f),
        "P_dv_inst": stack(lambda r: r.p_dv),
    }
    data = {k: (("solver", "case", "tau"), v) for k, v in hist.items()}
    data.update({k: (("solver", "case"), stack(f).astype(float)) for k, f in SCALARS.items()})
    data["kind"] = (("solver", "case"), stack(lambda r: r.kind).astype(str))
    coords = {
        "solver": list(SOLVERS),
        "case": np.arange(len(cases)),
        "tau": tau,
        "zeta": ("case", [p.zeta for p in cases]),
        "vb": ("case", [p.vb for p in cases]),
        "fd": ("case", [p.fd for p in cases]),
        "label": ("case", [p.label for p in cases]),
    }
    return xr.Dataset(data, coords=coords)


def select(ds: xr.Dataset, zeta: float, vb: float, fd: float) -> xr.Dataset:
    """The case with these parameters."""
    hit = np.isclose(ds.zeta.values, zeta) & np.isclose(ds.vb.values, vb) & np.isclose(ds.fd.values, fd)
    idx = np.flatnonzero(hit)
    if len(idx) != 1:
        raise KeyError(f"no single case with zeta={zeta}, V_b={vb}, F_d={fd}")
    return ds.isel(case=int(idx[0]))
