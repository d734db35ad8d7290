"""Reading configs and writing trajectories (CSV, NetCDF)."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from .trajectory import MODE_NAMES, WORK_NAMES, Trajectory

TRAJECTORY_FORMATS = (".csv", ".nc")

_VARS = {
    "X": ("1", "displacement X = x / l_0"),
    "V": ("1", "velocity X' = dX/dtau"),
    "F_c": ("1", "friction force on the mass F_c = f_c / (k l_0)"),
    "mode": ("1", "friction mode: 1 slip+ (V_r > 0), 0 stick, -1 slip-"),
    "W_dv": ("1", "cumulative damper work int 2 zeta X'^2 dtau"),
    "W_fin": ("1", "cumulative friction input int max(X' F_c, 0) dtau"),
    "W_fout": ("1", "cumulative friction output int max(-X' F_c, 0) dtau"),
    "W_heat": ("1", "cumulative interface heat int F_c V_r dtau over slip"),
}


def trajectory_to_dataset(traj: Trajectory):
    """An :class:`xarray.Dataset` over ``tau`` with units and long names."""
    import xarray as xr

    data = {"X": traj.x, "V": traj.v, "F_c": traj.fc, "mode": traj.mode}
    data.update({name: traj.work[:, j] for j, name in enumerate(WORK_NAMES)})
    ds = xr.Dataset(
        {k: ("tau", np.asarray(v)) for k, v in data.items()},
        coords={"tau": ("tau", traj.t, {"units": "1", "long_name": "non-dimensional time tau = omega0 t"})},
    )
    for k, (units, long_name) in _VARS.items():
        ds[k].attrs.update(units=units, long_name=long_name)
    ds["mode"].attrs["flag_values"] = np.array(sorted(MODE_NAMES), dtype=np.int8)
    ds["mode"].attrs["flag_meanings"] = " ".join(MODE_NAMES[k].replace("+", "_pos").replace("-", "_neg") for k in sorted(MODE_NAMES))
    ds.attrs.update({"zeta": traj.model.zeta, "vb": traj.model.vb})
    ds.attrs.update({f"friction_{k}": v for k, v in traj.friction.as_dict().items()})
    ds.attrs.update({f"solver_{k}": v for k, v in traj.solver.items() if v is not None})
    return ds


def check_output_path(path: str | Path, allowed: tuple[str, ...], name: str) -> Path:
    """Refuse an output path whose extension is not one of ``allowed``, before any work."""
    p = Path(path)
    if p.suffix.lower() not in allowed:
        raise ValueError(f"{name} must end in one of {', '.join(allowed)}, got {str(path)!r}")
    if not p.parent.exists():
        raise ValueError(f"{name}: directory {str(p.parent)!r} does not exist")
    return p


def write_trajectory(traj: Trajectory, path: str | Path) -> Path:
    """Write ``traj`` as CSV or NetCDF, chosen by the extension."""
    p = check_output_path(path, TRAJECTORY_FORMATS, "out")
    if p.suffix.lower() == ".nc":
        trajectory_to_dataset(traj).to_netcdf(p)
        return p
    cols = np.column_stack([traj.t, traj.x, traj.v, traj.fc, traj.mode, traj.work])
    header = ",".join(["tau", "X", "V", "F_c", "mode", *WORK_NAMES])
    np.savetxt(p, cols, delimiter=",", header=header, comments="", fmt="%.17g")
    return p


def read_config(path: str | Path) -> dict[str, Any]:
    """Parse a TOML config; a missing or malformed file raises ValueError."""
    p = Path(path)
    try:
        with open(p, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise ValueError(f"config: file {str(path)!r} not found") from None
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"config: {str(path)!r} is not valid TOML ({e})") from None
