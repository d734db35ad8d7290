"""File formats: reading TOML configs, writing trajectories (CSV, NetCDF), checking output paths.

What a trajectory *is* as a table (its xarray form) belongs to
:meth:`frictionflow.trajectory.Trajectory.to_xarray`; this module only
imports :mod:`.trajectory`, never the other way round.
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from .trajectory import WORK_NAMES, Trajectory

TRAJECTORY_FORMATS = (".csv", ".nc")


def trajectory_to_dataset(traj: Trajectory):
    """The same as ``traj.to_xarray()``, kept for callers of this older name."""
    return traj.to_xarray()


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
        traj.to_xarray().to_netcdf(p)
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
