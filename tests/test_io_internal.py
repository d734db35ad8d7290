"""A law's internal states and stored energy through every trajectory backend: the dataset, NetCDF, Zarr, CSV.

The states are labelled by the law's ``internal_names``; the stored energy is
checked against the law's formula (sigma0 z^2 / 2) written here, the belt's
work against the running sum of the increments the run recorded.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from frictionflow import BeltOscillator, Coulomb, simulate
from frictionflow.friction import Dahl, LuGre
from frictionflow.io import check_output_path, write_trajectory

LAWS = {"lugre": LuGre(fd=0.3, fs=0.5, vs=0.05, sigma0=1e3, sigma1=60.0), "dahl": Dahl(fd=0.3, sigma0=1e3)}


@pytest.fixture(scope="module", params=sorted(LAWS))
def run(request):
    law = LAWS[request.param]
    return simulate(BeltOscillator(zeta=0.02, vb=0.1), law, t_end=30.0, x0=0.0, v0=0.0)


def _read(path):
    if path.suffix == ".nc":
        with xr.open_dataset(path) as ds:
            return ds.load()
    return xr.open_zarr(path, consolidated=False).load()


@pytest.mark.parametrize("backend", ["memory", "nc", "zarr"])
@pytest.mark.parametrize("dense", [True, False])
def test_the_dataset_round_trips_the_internal_states_and_stored_energy(run, backend, dense, tmp_path):
    ds = run.to_xarray(dense=dense)
    if backend == "memory":
        back = ds
    else:
        path = tmp_path / f"t.{backend}"
        if dense:
            write_trajectory(run, path)
        elif backend == "nc":
            ds.to_netcdf(path)
        else:
            ds.to_zarr(path, consolidated=False)
        back = _read(path)
        xr.testing.assert_identical(back, ds)
    law = run.friction
    (name,) = law.internal_names
    assert back[name].attrs["long_name"] == f"internal state {name} of friction={law.name}"
    samples = back.where(back["is_sample"], drop=True)
    np.testing.assert_array_equal(samples[name].values, run.internal[0])
    np.testing.assert_allclose(back["E_s"].values, 0.5 * law.sigma0 * back[name].values ** 2, rtol=1e-14, atol=0.0)
    assert samples["W_belt"].values[-1] == pytest.approx(run.dbelt.sum(), rel=1e-12)


def test_csv_holds_the_internal_states_by_name(run, tmp_path):
    path = write_trajectory(run, tmp_path / "t.csv")
    data = np.genfromtxt(path, delimiter=",", names=True)
    law = run.friction
    (name,) = law.internal_names
    np.testing.assert_array_equal(data[name], run.internal[0])
    np.testing.assert_allclose(data["E_s"], 0.5 * law.sigma0 * run.internal[0] ** 2, rtol=1e-15, atol=0.0)
    np.testing.assert_array_equal(data["W_belt"], np.cumsum(run.dbelt))
    np.testing.assert_array_equal(data["X"], run.x)


def test_an_existing_zarr_store_is_replaced_and_anything_else_refused_in_one_line(run, tmp_path):
    # as basins and map treat their stores: the new store in place once complete, the old one gone
    path = write_trajectory(run, tmp_path / "t.zarr")
    shorter = simulate(BeltOscillator(zeta=0.05, vb=0.1), Coulomb(), t_end=5.0)
    assert write_trajectory(shorter, path) == path
    with xr.open_zarr(path) as ds:
        np.testing.assert_array_equal(ds["X"].values, shorter.to_xarray()["X"].values)
    (tmp_path / "plain.zarr").mkdir()
    (tmp_path / "plain.zarr" / "notes.txt").write_text("mine")
    (tmp_path / "file.zarr").write_text("mine")
    for other in ("plain.zarr", "file.zarr"):
        with pytest.raises(ValueError, match=rf"^out: '.+{other}' exists and is not a Zarr store.*it would be replaced"):
            write_trajectory(run, tmp_path / other)
    assert (tmp_path / "plain.zarr" / "notes.txt").read_text() == "mine" and (tmp_path / "file.zarr").read_text() == "mine"
    assert check_output_path(tmp_path / "other.zarr", (".zarr",), "out") == tmp_path / "other.zarr"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary left behind
