"""Defects of the sweep's store and its commands found by QA: ``--restart`` removed any directory given as the
output, ``map --store`` took the chart's own path and a ``.nc``, messages named ``out`` instead of the option, a
name too long for the lock file was refused late naming the lock, and the map's dataset lacked what its JSON holds."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from frictionflow.cli import main
from frictionflow.orbits.chart import stability_chart
from frictionflow import BeltOscillator, Stribeck
from frictionflow.sweep import run_sweep
from frictionflow.sweep.lock import lock_path
from frictionflow.sweep.store import foreign

TOML = 'friction = "coulomb"\nfd = 0.02\nfs = 0.04\nt_end = 50.0\n[grid]\nvb = [0.01, 0.02]\n'
CFG = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "t_end": 50.0, "grid": {"vb": [0.01, 0.02]}}
#: a cheap unforced Karnopp case (two points) for the basins paths
BASINS = ["basins", "--fd", "0.02", "--fs", "0.04", "--zeta", "0.05", "--vb", "0.01", "--t-end", "50",
          "--x0-range=-0.1:0.1:2", "--v0-range=-0.1:-0.1:1"]
MAP = ["map", "--x", "vb=0.004:0.03:3", "--y", "zeta=0:1:11", "--overlay", "2x2", "--t-end", "50"]


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: "), err
    return err[0]


@pytest.fixture
def config(tmp_path):
    path = tmp_path / "sw.toml"
    path.write_text(TOML)
    return path


@pytest.fixture
def no_compute(monkeypatch):
    """Any chunk computed fails the test: what is refused must be refused before the sweep."""
    from frictionflow.sweep import runner

    def compute(*args):
        raise AssertionError("a chunk was computed")

    monkeypatch.setattr(runner, "compute_chunk", compute)


def _precious(path):
    path.mkdir()
    (path / "thesis.tex").write_text("precious\n")


# -- 1. --restart replaces only what a sweep wrote ---------------------------------------------------

@pytest.mark.parametrize("name", ["userdir2.zarr", "userdir.nc"])
@pytest.mark.parametrize("restart", [[], ["--restart"]])
def test_restart_never_removes_a_directory_a_sweep_did_not_write(tmp_path, config, capsys, no_compute, name, restart):
    target = tmp_path / name
    _precious(target)
    assert main(["sweep", str(config), "--out", str(target), *restart]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"error: --out: {str(target)!r} ") and "--restart" not in line, line
    assert "never replaced: give another --out or remove it yourself" in line
    assert (target / "thesis.tex").read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([name, "sw.toml"])  # no lock, journal or store left


def test_restart_of_basins_keeps_a_users_directory_given_as_its_store(tmp_path, capsys, no_compute):
    store = tmp_path / "ud4.zarr"
    _precious(store)
    assert main([*BASINS, "--store", str(store), "--restart"]) == 2
    line = _one_line(capsys)
    assert line.startswith(f"error: --store: {str(store)!r} ") and "--restart" not in line
    assert (store / "thesis.tex").exists()
    beside = tmp_path / "ud5.zarr.sweep.zarr"  # the store a --out puts beside it
    _precious(beside)
    assert main([*BASINS, "--out", str(tmp_path / "ud5.zarr"), "--restart"]) == 2
    assert _one_line(capsys).startswith(f"error: --out: {str(beside)!r} ")
    assert (beside / "thesis.tex").exists()


def test_restart_still_replaces_what_a_sweep_wrote(tmp_path):
    for name in ("r.zarr", "r.nc"):
        out = tmp_path / name
        run_sweep(CFG, out)
        assert foreign(out) is None
        other = {**CFG, "grid": {"vb": [0.01, 0.03]}}
        with pytest.raises(ValueError, match="config changed.*--restart"):
            run_sweep(other, out)
        ds = run_sweep(other, out, restart=True)
        assert list(ds["vb"].values) == [0.01, 0.03]
        ds.close()
    # a journal whose metadata is damaged is still the sweep's: its bookkeeping tells
    journal = tmp_path / "j.zarr"
    run_sweep(CFG, journal)
    (journal / "zarr.json").write_bytes(b"")
    (journal / "_sweep" / "zarr.json").write_bytes(b"")
    assert foreign(journal) is None
    run_sweep(CFG, journal, restart=True).close()


def test_the_rule_of_what_a_sweep_wrote(tmp_path):
    plain = tmp_path / "plain.nc"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(plain)
    zarr_store = tmp_path / "other.zarr"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_zarr(zarr_store)
    text = tmp_path / "notes.zarr"
    text.write_text("x")
    for p in (plain, zarr_store, text):
        assert foreign(p) is not None, p
        with pytest.raises(ValueError, match="never replaced") as e:
            run_sweep(CFG, p, restart=True)
        assert "--restart" not in str(e.value)
        assert p.exists()
    assert foreign(tmp_path / "missing.zarr") is None


def test_a_truncated_netcdf_is_not_replaced_and_not_advised_so(tmp_path, capsys):
    nc = tmp_path / "t.nc"
    run_sweep(CFG, nc).close()
    nc.write_bytes(nc.read_bytes()[:3000])  # HDF5 signature, attributes gone: it cannot be told a sweep's
    assert foreign(nc) is not None
    with pytest.raises(RuntimeError, match="cannot be opened.*remove it yourself to start over") as e:
        run_sweep(CFG, nc)
    assert "--restart" not in str(e.value)
    with pytest.raises(ValueError, match="attributes cannot be read; .*never replaced"):
        run_sweep(CFG, nc, restart=True)
    assert nc.stat().st_size == 3000


# -- 2. map --store: a .zarr, and not --out -----------------------------------------------------------

@pytest.mark.parametrize("store, out, says", [
    ("mm.zarr", "mm.zarr", "--store must not be --out ('mm.zarr')"),
    ("./mm.zarr", "mm.zarr", "--store must not be --out ('mm.zarr')"),
    ("m2.nc", None, "--store must end in .zarr, got 'm2.nc'"),
])
def test_map_store_must_be_a_zarr_other_than_out(tmp_path, monkeypatch, capsys, no_compute, store, out, says):
    monkeypatch.chdir(tmp_path)
    assert main([*MAP, "--store", store, *(["--out", out] if out else [])]) == 2
    assert says in _one_line(capsys)
    assert not list(tmp_path.iterdir())


# -- 3. messages name the option ------------------------------------------------------------------------

def test_map_store_problems_name_store(tmp_path, monkeypatch, capsys, no_compute):
    from frictionflow.sweep import store as store_module

    monkeypatch.setattr(store_module, "_directory_problem", lambda d: f"directory {str(d)!r} is on a read-only file system")
    assert main([*MAP, "--store", str(tmp_path / "ro" / "s.zarr")]) == 2
    assert _one_line(capsys).startswith("error: --store: directory ")
    monkeypatch.undo()
    _precious(tmp_path / "u.zarr")  # found when the sweep opens it: named by the option too
    assert main([*MAP, "--store", str(tmp_path / "u.zarr")]) == 2
    assert _one_line(capsys).startswith(f"error: --store: {str(tmp_path / 'u.zarr')!r} ")


def test_sweep_and_reproduce_out_problems_name_out(tmp_path, config, capsys):
    other = tmp_path / "o.zarr"
    run_sweep(CFG, other)
    assert main(["sweep", str(config), "--out", str(other)]) == 0
    capsys.readouterr()
    changed = tmp_path / "changed.toml"
    changed.write_text(TOML.replace("t_end = 50.0", "t_end = 60.0"))
    assert main(["sweep", str(changed), "--out", str(other)]) == 2
    assert _one_line(capsys).startswith("error: --out: ")
    assert main(["reproduce", "--out", str(tmp_path / "none" / "r"), "--quick"]) == 2
    assert _one_line(capsys).startswith("error: --out: parent directory ")
    (tmp_path / "rp").mkdir()
    (tmp_path / "rp" / "fig2.png").mkdir()
    assert main(["reproduce", "--out", str(tmp_path / "rp"), "--quick"]) == 2
    assert _one_line(capsys).startswith("error: --out: ")


# -- 4. a name too long for the files beside it ------------------------------------------------------------

@pytest.mark.parametrize("suffix, need", [(".nc", 10), (".zarr", 2)])
def test_a_name_too_long_for_its_sidecars_is_refused_naming_out(tmp_path, config, capsys, no_compute, suffix, need):
    target = tmp_path / ("a" * (252 - len(suffix)) + suffix)  # 252 bytes: fits, its lock (and journal) do not
    assert main(["sweep", str(config), "--out", str(target)]) == 2
    line = _one_line(capsys)
    assert line.startswith("error: --out: ") and f"too long: its lock/partial files need {need} more bytes" in line
    assert ".lock" not in line
    assert not target.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["sw.toml"]
    assert not lock_path(tmp_path / "short.zarr").exists()


# -- 5. the map's dataset holds what its JSON holds ------------------------------------------------------

@pytest.fixture(scope="module")
def chart():
    model, law = BeltOscillator(zeta=0.3, vb=0.016), Stribeck(0.02, 0.04, 0.01)
    return stability_chart(model, law, "vb", np.linspace(0.004, 0.03, 8), "zeta", (0.0, 1.0), fold_every=1)


def test_the_chart_dataset_holds_every_json_curve_field(chart, tmp_path):
    path = tmp_path / "chart.nc"
    chart.to_xarray().to_netcdf(path)
    with xr.open_dataset(path) as ds:
        found = chart.to_dict()
        assert json.loads(ds.attrs["codim2"]) == found["codim2"] and json.loads(ds.attrs["params"]) == found["params"]
        assert ds["vb"].attrs["units"] and ds["vb"].attrs["long_name"]
        fields = {"hopf": {"l1", "criticality"}, "grazing": {"stick_slip_below"}, "fold": {"X", "vr_min"},
                  "fold_at_grazing": {"smooth"}}
        for c in found["curves"]:
            assert {f"{c['kind']}_{k}" for k in fields[c["kind"]]} <= set(ds.data_vars)
            seen = {}
            for p in c["points"]:
                i = int(np.nonzero(ds["vb"].values == p["x"])[0][0])
                k = seen[i] = seen.get(i, -1) + 1  # roots in increasing zeta
                row = sorted((q for q in c["points"] if q["x"] == p["x"]), key=lambda q: q["y"])
                p = row[k]
                assert ds[f"{c['kind']}_zeta"].values[i, k] == p["y"]
                for key, value in p.items():
                    if key in ("x", "y") or value is None:
                        continue
                    stored = ds[f"{c['kind']}_{key}"].values[i, k]
                    assert stored == value, (c["kind"], key, stored, value)
            empty = [i for i in range(len(ds["vb"])) if i not in seen]
            for i in empty:
                assert all(v == "" or (isinstance(v, float) and math.isnan(v))
                           for key in fields[c["kind"]] for v in [ds[f"{c['kind']}_{key}"].values[i, 0].item()])
        assert all(c["points"] for c in found["curves"] if c["kind"] in ("hopf", "grazing", "fold"))
