"""Trajectory files: NetCDF round trip and CSV contents."""

import numpy as np
import xarray as xr

from frictionflow import BeltOscillator, Karnopp, RK4, simulate
from frictionflow.io import trajectory_to_dataset, write_trajectory


def test_netcdf_round_trip_is_identical(tmp_path):
    tr = simulate(BeltOscillator(zeta=0.02, vb=0.01), Karnopp(0.02, fs=0.03), RK4(dt=1e-2), t_end=20.0)
    ds = tr.to_xarray()
    path = write_trajectory(tr, tmp_path / "t.nc")
    with xr.open_dataset(path) as back:
        xr.testing.assert_identical(back.load(), ds)
    assert ds["mode"].dtype == np.int8


def test_csv_holds_the_samples_to_full_precision(tmp_path):
    tr = simulate(BeltOscillator(zeta=0.02, vb=0.01), Karnopp(0.02), RK4(dt=1e-2), t_end=5.0)
    path = write_trajectory(tr, tmp_path / "t.csv")
    data = np.genfromtxt(path, delimiter=",", names=True)
    assert np.array_equal(data["X"], tr.x) and np.array_equal(data["W_fin"], tr.work[:, 1])


def test_the_dataset_names_the_sample_modes_and_keeps_the_old_entry_point():
    tr = simulate(BeltOscillator(zeta=0.02, vb=0.01), Karnopp(0.02, fs=0.03), RK4(dt=1e-2), t_end=5.0)
    ds = tr.to_xarray()
    # Trajectory.mode: -1 slip- (V_r < 0), 0 stick, +1 slip+, as CF flags
    assert ds["mode"].attrs["flag_values"].tolist() == [-1, 0, 1]
    assert ds["mode"].attrs["flag_meanings"] == "slip_neg stick slip_pos"
    xr.testing.assert_identical(trajectory_to_dataset(tr), ds)
