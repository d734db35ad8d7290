"""Sweeps: per-point results equal single runs; labelled datasets; resume after SIGKILL; Dask."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
import xarray as xr
import zarr

from frictionflow import BeltOscillator, Coulomb, Karnopp, RK4, Stribeck, analyze, simulate
from frictionflow.sweep import VARIABLES, parse_sweep, plot_cut, plot_map, run_sweep
from frictionflow.core import layout as kf
from frictionflow.friction.registry import law_classes
from frictionflow.sweep.compute import _starts

COULOMB = {
    "friction": "coulomb",
    "fs": 0.04,
    "t_end": 300.0,
    "grid": {"zeta": {"start": 0.0, "stop": 0.12, "num": 7}, "vb": [0.005, 0.02], "fd": [0.01, 0.02]},
}


def same_as_simulate(ds, point: dict, model, law, solver=None, t_end=300.0, rtol=1e-9):
    """The sweep's values at ``point`` against analyze(simulate(...)) of that point."""
    res = analyze(simulate(model, law, solver, t_end=t_end)).to_dict()
    row = ds.sel(point)
    kind = ["periodic", "equilibrium", "not_settled"][int(row["kind"])]
    assert kind == res["steady_state"]["kind"], point
    flat = {**res["averages"], **res["amplitude"], "TR_B": res["TR_B"], "period": res["steady_state"]["period"],
            "stick_fraction": res["steady_state"]["stick_fraction"]}
    for name in ("period", "P_dv", "P_df", "P_fin", "R_c", "R_f", "P_belt", "P_heat", "TR_B", "X_min", "X_max", "V_min", "V_max", "stick_fraction"):
        want = flat[name]
        got = float(row[name])
        if want is None:
            assert math.isnan(got), (point, name)
        else:
            assert got == pytest.approx(want, rel=rtol, abs=1e-15), (point, name)


@pytest.fixture(scope="module")
def coulomb_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "c.zarr"
    return run_sweep(COULOMB, out, chunk_size=6).load(), out


def test_exact_sweep_equals_simulate_per_point(coulomb_sweep):
    ds, _ = coulomb_sweep
    kinds = set(ds["kind"].values.ravel().tolist())
    assert kinds == {0, 1}  # stick-slip cycles and (at high damping) the sliding equilibrium
    for zeta in (0.0, 0.06, 0.12):
        for vb in (0.005, 0.02):
            same_as_simulate(ds, {"zeta": zeta, "vb": vb, "fd": 0.02}, BeltOscillator(zeta, vb), Coulomb(0.02, 0.04))


def test_dataset_is_labelled(coulomb_sweep):
    ds, out = coulomb_sweep
    assert ds.sizes == {"zeta": 7, "vb": 2, "fd": 2}
    assert np.allclose(ds["zeta"].values, np.linspace(0, 0.12, 7))
    for name, _, _ in VARIABLES:
        assert {"units", "long_name"} <= ds[name].attrs.keys()
        assert ds[name].dims == ("zeta", "vb", "fd")
    for d in ds.dims:
        assert {"units", "long_name"} <= ds[d].attrs.keys()
    for key in ("frictionflow_version", "config", "created", "platform", "config_sha256"):
        assert key in ds.attrs
    assert ds.attrs["fixed_fs"] == 0.04
    assert not {"_chunks_done", "chunks_done"} & set(ds.variables)  # the bookkeeping stays in the _sweep group
    with xr.open_zarr(out, consolidated=False) as back:
        xr.testing.assert_identical(back.load(), ds)


def test_netcdf_output_round_trip(tmp_path, coulomb_sweep):
    ds, _ = coulomb_sweep
    nc = run_sweep(COULOMB, tmp_path / "c.nc", chunk_size=6).load()
    with xr.open_dataset(tmp_path / "c.nc") as back:
        xr.testing.assert_identical(back.load(), nc)
    xr.testing.assert_equal(nc, ds)
    assert not (tmp_path / "c.nc.partial.zarr").exists()


def test_rk4_and_adaptive_sweeps_equal_single_runs(tmp_path):
    cfg = {"solver": "rk4", "dt": 2e-3, "t_end": 60.0, "fs": 0.04, "grid": {"zeta": [0.0, 0.05], "vb": [0.01, 0.03]}}
    ds = run_sweep(cfg, tmp_path / "r.zarr").load()
    for zeta in (0.0, 0.05):
        for vb in (0.01, 0.03):
            # The batched kernel rounds differently (SIMD fused multiply-adds); through
            # a stick band RK4 amplifies that to its cycle-to-cycle jitter, ~1e-4 here.
            same_as_simulate(ds, {"zeta": zeta, "vb": vb}, BeltOscillator(zeta, vb), Karnopp(0.02, 0.04), RK4(dt=2e-3), t_end=60.0, rtol=1e-3)
    cfg = {"friction": "stribeck", "fs": 0.04, "vs": 0.02, "t_end": 150.0, "grid": {"zeta": [0.05, 0.5]}}
    ds = run_sweep(cfg, tmp_path / "s.zarr").load()
    for zeta in (0.05, 0.5):
        same_as_simulate(ds, {"zeta": zeta}, BeltOscillator(zeta, 0.01), Stribeck(0.02, 0.04, vs=0.02), t_end=150.0, rtol=1e-9)


def test_changed_config_is_refused_unless_restart(tmp_path):
    out = tmp_path / "c.zarr"
    run_sweep({**COULOMB, "grid": {"zeta": [0.0, 0.1]}}, out)
    with pytest.raises(ValueError, match="config changed.*--restart"):
        run_sweep({**COULOMB, "grid": {"zeta": [0.0, 0.2]}}, out)
    ds = run_sweep({**COULOMB, "grid": {"zeta": [0.0, 0.2]}}, out, restart=True)
    assert list(ds["zeta"].values) == [0.0, 0.2]


def _strip_time(ds):
    ds = ds.copy()
    ds.attrs.pop("created")
    return ds


SLOW_CFG = """friction = "coulomb"
fs = 0.04
t_end = 300.0
[grid]
zeta = {{ start = 0.0, stop = 0.1, num = {n} }}
vb = {{ start = 0.002, stop = 0.05, num = 6, scale = "log" }}
fd = [0.01, 0.02, 0.03]
"""


def test_sigkill_and_resume_gives_the_uninterrupted_dataset(tmp_path):
    cfg = tmp_path / "s.toml"
    cfg.write_text(SLOW_CFG.format(n=40))
    out = tmp_path / "s.zarr"
    cmd = [sys.executable, "-m", "frictionflow", "sweep", str(cfg), "--out", str(out), "--chunk-size", "18"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.time() + 120
    done = 0
    while time.time() < deadline and proc.poll() is None:
        try:
            done = int(np.count_nonzero(zarr.open_group(str(out), mode="r")["_sweep/chunks_done"][:]))
        except Exception:
            done = 0
        if done >= 5:
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the sweep finished before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    total = 40
    assert 0 < done < total
    # started again with the same command: it resumes and completes, taking over the killed run's lock
    again = subprocess.run(cmd, capture_output=True, text=True, check=False)
    assert again.returncode == 0 and f"taking over a stale lock of PID {proc.pid} " in again.stderr, again.stderr
    resumed = xr.open_zarr(out, consolidated=False).load()
    fresh = run_sweep(tmp_path / "s.toml", tmp_path / "fresh.zarr", chunk_size=18).load()
    xr.testing.assert_identical(_strip_time(resumed), _strip_time(fresh))
    assert int((resumed["kind"] < 0).sum()) == 0


# slow: tests/cli/test_faults_io.py covers both claims on its one cluster -- a dask sweep equal to the local one
# (test_what_dask_recovers_from_by_itself_is_not_printed) and every worker SIGKILLed mid-sweep, deterministically
# after the first committed chunk, still giving the identical result
# (test_a_sweep_whose_workers_are_killed_completes_with_the_same_result)
@pytest.mark.slow
def test_dask_cluster_with_a_worker_killed_gives_identical_results(tmp_path):
    distributed = pytest.importorskip("distributed")
    cfg = parse_sweep({**COULOMB, "grid": {"zeta": {"start": 0.0, "stop": 0.12, "num": 24}, "vb": [0.005, 0.02], "fd": [0.01, 0.02]}})
    local = run_sweep(cfg, tmp_path / "local.zarr", chunk_size=4).load()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            plain = run_sweep(cfg, tmp_path / "dask.zarr", client=client, chunk_size=4).load()
            xr.testing.assert_identical(_strip_time(plain), _strip_time(local))
            pids = client.run(os.getpid)
            victim = sorted(pids)[0]
            result = {}

            def go():
                result["ds"] = run_sweep(cfg, tmp_path / "killed.zarr", client=client, chunk_size=4)

            th = threading.Thread(target=go)
            th.start()
            while not (tmp_path / "killed.zarr").exists():
                time.sleep(0.01)
            time.sleep(0.3)
            os.kill(pids[victim], signal.SIGKILL)
            th.join(timeout=300)
            assert not th.is_alive()
            killed = result["ds"].load()
            xr.testing.assert_identical(_strip_time(killed), _strip_time(local))


def test_plot_helpers(tmp_path, coulomb_sweep):
    ds, _ = coulomb_sweep
    plot_map(ds, "R_c", "zeta", "vb", tmp_path / "map.png", fd=0.02)
    plot_cut(ds, "TR_B", "zeta", tmp_path / "cut.png", hue="vb", fd=0.02)
    assert (tmp_path / "map.png").stat().st_size > 1000 and (tmp_path / "cut.png").stat().st_size > 1000
    with pytest.raises(ValueError, match="varies along fd"):
        plot_map(ds, "R_c", "zeta", "vb")
    # a name the dataset does not have is named (it once read "still varies along vb" or a raw KeyError)
    for call, words in ((lambda: plot_map(ds, "R_c", "zeta", "bogus", fd=0.02), "'bogus' is not a dimension of R_c"),
                        (lambda: plot_map(ds, "R_c", "zeta", "zeta", fd=0.02), "the plotted dimensions must differ"),
                        (lambda: plot_cut(ds, "TR_B", "zeta", hue="bogus", fd=0.02), "'bogus' is not a dimension"),
                        (lambda: plot_cut(ds, "TR_B", "zeta", bogus=1.0), "'bogus' is not a dimension"),
                        (lambda: plot_map(ds, "nope", "zeta", "vb", fd=0.02), "var must be one of the dataset's")):
        with pytest.raises(ValueError, match=words):
            call()


@pytest.mark.parametrize("cls", [c for c in law_classes() if c.compiled_slip], ids=lambda c: c.name)
def test_a_batched_points_default_start_is_the_laws_own(cls):
    # the batched kernels (laws with a compiled slip force) take (X(0), X'(0)) as columns: where none is given
    # they must be law.start's, per point
    law = cls.from_values({})
    vb = np.array([0.01, 0.2])
    p = np.tile(law.kernel_params(), (2, 1))
    x0, v0 = _starts(p, {"x0": np.array([np.nan, 0.3]), "v0": np.array([np.nan, -0.1]), "vb": vb})
    assert (x0[0], v0[0]) == law.start(float(vb[0]))
    assert (x0[1], v0[1]) == (0.3, -0.1)
    assert p[0, kf.FD] == x0[0]
