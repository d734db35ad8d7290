"""Units and long names for every quantity, and writing data sets and figures.

Everything in the paper is non-dimensional (Eq. 3), so every unit is "1";
the long names say what each quantity is in the paper's symbols.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


from .._lazy import lazy_module
from ..io import DEFAULT_DPI, atomic_write, write_figure
from .style import freeze_layout

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

#: the option named when a file of the reproduction cannot be written
OPTION = "out"


#: name -> long_name of every variable and coordinate the studies write
LONG_NAMES: dict[str, str] = {
    "solver": "rk4: the paper's method (fixed-step RK4 through the Karnopp band); exact: event-driven closed form",
    "case": "parameter point",
    "label": "parameter point",
    "tau": "non-dimensional time tau = omega0 t",
    "zeta": "damping ratio zeta = c / (2 m omega0)",
    "vb": "belt speed V_b",
    "fd": "kinetic friction F_d (= maximum static friction F_s)",
    "X": "displacement X",
    "V": "velocity X'",
    "F_c": "friction force F_c",
    "P_f": "instantaneous friction power P_f = X' F_c",
    "P_dv_inst": "instantaneous damper power P_dv = 2 zeta X'^2",
    "P_dv": "time-averaged damper power (Eq. 9a)",
    "P_fin": "time-averaged friction input power, mean of max(P_f, 0) (Eq. 9c)",
    "P_df": "time-averaged friction dissipated power, mean of max(-P_f, 0) (Eq. 9b)",
    "R_c": "damper dissipation ratio R_c = P_dv / P_fin",
    "R_f": "friction dissipation ratio R_f = P_df / P_fin",
    "TR_B": "force transmissibility TR_B = max|X + 2 zeta X'| / F_d (Eq. 6)",
    "net_friction": "net friction power P_fin - P_df (mean of X' F_c)",
    "dE": "mean rate of change of K + U over the window",
    "amplitude": "half the range of X over the window",
    "window_start": "start of the averaging window (a maximum of X)",
    "window_end": "end of the averaging window (the next maximum of X)",
    "peak_P_dv": "largest instantaneous damper power over the shown span",
    "peak_P_f": "largest |P_f| over the shown span",
    "kind": "steady state found by frictionflow.analyze: periodic, equilibrium or not_settled",
    "period": "period of the steady state (NaN unless periodic)",
    "decay_rate": "exponential decay rate of the cycle amplitudes (fitted)",
    "t_terminal": "time after which the exact solver proves the band is never reached again (NaN: never)",
    "energy_residual": "relative residual of the energy balance over the steady-state window",
    "V_max": "largest X' in the steady-state window",
    "V_min": "smallest X' in the steady-state window",
    "X_max": "largest X in the steady-state window",
    "X_min": "smallest X in the steady-state window",
    "stick_fraction": "share of the steady-state window spent in the band (Karnopp 'stick')",
    "cycle_start": "where each averaging cycle starts: at a maximum or at a minimum of X",
    "model": "friction model and solver",
    "model_description": "friction model and solver",
    "X_long": "displacement X over the long run",
    "run_W_dv": "energy dissipated by the damper over the whole run, int P_dv dtau",
    "run_W_f_net": "net work of the friction over the whole run, int X' F_c dtau",
    "initial_K": "initial kinetic energy V_b^2 / 2 (X(0) = F_d is the sliding equilibrium)",
    "V_half": "velocity X' at V_b = V_d / 2",
    "mode_half": "friction mode at V_b = V_d / 2: 1 slip+, 0 band ('stick'), -1 slip-",
    "band_share_half": "share of the time in the band ('stick') at V_b = V_d / 2, over whole shuttles",
    "backward_share_half": "share of the time moving against the belt (X' < 0) at V_b = V_d / 2, over whole shuttles",
    "tau_half": "non-dimensional time tau (the V_b = V_d / 2 run)",
    "tau_short": "non-dimensional time tau (the first turns)",
    "tau_long": "non-dimensional time tau (the whole long run)",
    "creep_speed": "RK4's residual velocity X' inside the band at tau = 100 (V_b = V_d)",
    "dt": "RK4 step",
    "paper_number": "a number the paper reports",
    "last_net_friction_from_min": "over the last whole cycle from a minimum of X to the next: net friction power P_fin - P_df",
    "last_R_f_from_min": "over the last whole cycle from a minimum of X to the next: R_f = P_df / P_fin",
    "P_fin_closed_form": "F_d (V_b - V_d) / pi: Case I's P_fin on the circle of radius V_b - V_d",
}


def annotate(ds: xr.Dataset, title: str, settings: dict[str, Any] | None = None) -> xr.Dataset:
    """Attach units and long names to every variable and coordinate, and global attributes.

    Variables with a ``steady_``/``last_``/``exact_`` style prefix take the long
    name of their base quantity with the prefix spelled out.
    """
    for name in list(ds.data_vars) + list(ds.coords):
        var = ds[name]
        if var.dtype.kind in "fiu":
            var.attrs.setdefault("units", "1")
        if "long_name" not in var.attrs:
            var.attrs["long_name"] = long_name(str(name))
    ds.attrs["title"] = title
    ds.attrs["source"] = "frictionflow reproduce"
    ds.attrs["reference"] = "Vibration power dissipation in a spring-damper-mass system excited by dry friction"
    for k, v in (settings or {}).items():
        ds.attrs[f"setting_{k}"] = str(v) if isinstance(v, tuple) else v
    return ds


def long_name(name: str) -> str:
    """The long name of ``name``; prefixes say which run or window it comes from."""
    if name in LONG_NAMES:
        return LONG_NAMES[name]
    prefixes = {
        "steady_": "in the steady state found by frictionflow.analyze: ",
        "last_": "over the last whole cycle before t_end: ",
        "window_": "over the cycle starting at window_start: ",
    }
    for prefix, words in prefixes.items():
        if name.startswith(prefix) and name[len(prefix):] in LONG_NAMES:
            return words + LONG_NAMES[name[len(prefix):]]
    raise KeyError(f"no long name for {name!r}: add it to frictionflow.paper.export.LONG_NAMES")


def write_dataset(ds: xr.Dataset, out_dir: Path, stem: str) -> list[Path]:
    """Write ``stem.nc`` and CSV tables: ``stem.csv`` for the variables with the most
    dimensions, ``stem_<dims>.csv`` for each other group of variables sharing dimensions."""
    out_dir = Path(out_dir)
    paths = [out_dir / f"{stem}.nc"]
    with atomic_write(paths[0], OPTION) as tmp:
        ds.to_netcdf(tmp)
    groups: dict[tuple[str, ...], list[str]] = {}
    for name, var in ds.data_vars.items():
        groups.setdefault(tuple(str(d) for d in var.dims), []).append(str(name))
    primary = max(groups, key=len)
    for dims, names in groups.items():
        path = out_dir / (f"{stem}.csv" if dims == primary else f"{stem}_{'-'.join(dims) or 'scalars'}.csv")
        with atomic_write(path, OPTION) as tmp:
            ds[names].to_dataframe().to_csv(tmp)
        paths.append(path)
    return paths


def save_figure(fig, out_dir: Path, stem: str, dpi: float = DEFAULT_DPI) -> list[Path]:
    """Save ``fig`` as ``stem.png`` (``dpi`` dots per inch) and ``stem.pdf`` (each atomically) and close it.

    The layout is computed once, for the PNG, and kept for the PDF
    (:func:`.style.freeze_layout`).
    """
    import matplotlib.pyplot as plt

    paths = [Path(out_dir) / f"{stem}.png", Path(out_dir) / f"{stem}.pdf"]
    try:
        write_figure(fig, paths[0], OPTION, close=False, dpi=dpi)
        freeze_layout(fig)
        write_figure(fig, paths[1], OPTION, close=False, dpi=dpi)
    finally:
        plt.close(fig)
    return paths
