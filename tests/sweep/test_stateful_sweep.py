"""Sweeps of laws with internal state: every swept value is the point's own analyze(simulate(...)), bit for bit;
the law's own parameters are axes; an interrupted sweep resumes to the same dataset."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow import quantities as Q
from frictionflow.core import stiff, stiff_points
from frictionflow.friction import LuGre, law_class
from frictionflow.sweep import parse_sweep, run_sweep
from frictionflow.solvers.base import kernel_params
from frictionflow.sweep import runner

LAW = {"fd": 0.3, "fs": 0.5, "vs": 0.05, "delta": 2.0, "sigma1": 100.0}
SWEEP = {"friction": "lugre", **LAW, "t_end": 120.0,
         "grid": {"sigma0": [2e3, 1e4], "zeta": [0.02, 0.3], "vb": [0.1], "fex": [0.0, 0.05]}}


def _strip_time(ds):
    ds = ds.copy()
    ds.attrs.pop("created")
    return ds


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    return run_sweep(SWEEP, tmp_path_factory.mktemp("lugre") / "s.zarr", chunk_size=3).load()


def test_every_swept_value_is_the_points_own_run_bit_for_bit(swept):
    kinds = set()
    for sigma0 in SWEEP["grid"]["sigma0"]:
        for zeta in SWEEP["grid"]["zeta"]:
            for fex in SWEEP["grid"]["fex"]:
                model = BeltOscillator(zeta=zeta, vb=0.1, fex=fex, omega=1.0)
                law = LuGre(**LAW, sigma0=sigma0)
                want = analyze(simulate(model, law, t_end=SWEEP["t_end"], x0=law.fd, v0=0.1)).quantities()
                row = swept.sel(sigma0=sigma0, zeta=zeta, vb=0.1, fex=fex)
                got = np.array([float(row[q.name]) for q in Q.SWEPT])
                np.testing.assert_array_equal(got, np.array([want[q.name] for q in Q.SWEPT], dtype=float))
                kinds.add(Q.KINDS[int(row["kind"])])
    assert "periodic" in kinds and len(kinds) >= 2  # stick-slip cycles and settled sliding both swept


def test_the_bristle_stiffness_is_an_axis_that_changes_the_results(swept):
    a = swept.sel(sigma0=2e3, zeta=0.02, vb=0.1, fex=0.0)
    b = swept.sel(sigma0=1e4, zeta=0.02, vb=0.1, fex=0.0)
    assert float(a["period"]) != float(b["period"])
    assert swept.attrs["friction"] == "lugre" and swept["sigma0"].attrs["long_name"]


def test_an_interrupted_sweep_resumes_to_the_uninterrupted_dataset(tmp_path, monkeypatch, swept):
    calls = []
    original = runner.compute_chunk

    def fails_on_the_third(source, chunk, chunks):
        calls.append(chunk)
        if len(calls) == 3:
            raise RuntimeError("interrupted")
        return original(source, chunk, chunks)

    monkeypatch.setattr(runner, "compute_chunk", fails_on_the_third)
    out = tmp_path / "r.zarr"
    with pytest.raises(RuntimeError, match="interrupted"):
        run_sweep(SWEEP, out, chunk_size=3)
    monkeypatch.setattr(runner, "compute_chunk", original)
    resumed = run_sweep(SWEEP, out, chunk_size=3).load()
    xr.testing.assert_identical(_strip_time(resumed), _strip_time(swept))


def test_a_static_law_with_the_stiff_solver_is_still_refused():
    with pytest.raises(ValueError, match="^solver=stiff does not support friction=coulomb"):
        parse_sweep({"friction": "coulomb", "solver": "stiff", "t_end": 20.0, "grid": {"zeta": [0.05, 0.06]}})


@pytest.mark.parametrize("name", ["lugre", "dahl", "elastoplastic"])
def test_every_parameter_of_a_stateful_law_is_an_axis(name):
    law = law_class(name)()
    own = [p.name for p in law.parameters]
    assert {"sigma0"} <= set(own) and all(p.sweepable for p in law.parameters if p.kind == "real")
    for p in law.parameters:
        v = float(getattr(law, p.name))
        cfg = parse_sweep({"friction": name, "t_end": 10.0, "grid": {p.name: [v, v * 1.1 + 1e-9]}})
        assert cfg.dims == (p.name,)
        assert cfg.point_params((np.array([1]),))[p.name][0] == v * 1.1 + 1e-9


def test_the_released_kernel_is_the_stiff_engine_bit_for_bit():
    model = BeltOscillator(zeta=0.02, vb=0.1, fex=0.05, omega=0.9)
    law = LuGre(**LAW, sigma0=1e4)
    q = kernel_params(model, law)
    tol = np.array([1e-10, 1e-10, 1e-10 * law.fs / law.sigma0, 1e-8])
    steps = np.array([1e-5, 0.5, 1e7, model.forcing_period])
    runs = []
    for run in (stiff.run, stiff_points.run_released):
        t, y, w = np.empty(50_000), np.empty((3, 50_000)), np.empty((50_000, stiff.N_CHANNELS))
        n = run(q, model.zeta, model.vb, np.array([0.3, 0.0, 0.0]), 60.0, tol, steps, t, y, w, np.zeros(stiff.N_AT))[0]
        runs.append((t[:n], y[:, :n], w[:n]))
    assert all(np.array_equal(a, b) for a, b in zip(*runs)) and len(runs[0][0]) > 1000
