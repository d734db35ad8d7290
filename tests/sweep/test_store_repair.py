"""Damaged metadata repaired instead of restarted (issue 20, item 3).

An emptied ``zarr.json`` (the root's, or one variable's) of a partly finished
store is rebuilt from the sweep's settings on resume, or by
``sweep --verify OUT --repair`` without computing; every finished chunk that
verifies against its checksum is kept (the compute function is recorded to
prove it), only the rest is recomputed, and the result is identical to an
undamaged run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr

import frictionflow

from frictionflow.cli import main
from frictionflow.sweep import repair_sweep, runner
from frictionflow.sweep.store import RepairWarning, verify_sweep

from .store_cases import CFG, CFG_TOML, interrupted, run_small

def _same(ds: xr.Dataset, ref: xr.Dataset) -> None:
    a, b = ds.copy(), ref.copy()
    a.attrs.pop("created"), b.attrs.pop("created")
    xr.testing.assert_identical(a, b)


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> xr.Dataset:
    return run_small(tmp_path_factory.mktemp("fresh") / "fresh.zarr")


def _empty(out, node: str) -> None:
    (out / node / "zarr.json").write_bytes(b"")


@pytest.mark.parametrize("node", ["", "P_belt", "kind"], ids=["root", "P_belt", "kind"])
def test_resume_rebuilds_emptied_metadata_and_keeps_the_finished_chunks(tmp_path, fresh, monkeypatch, node):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=2)
    _empty(out, node)
    found = verify_sweep(out)
    assert not found.intact and "metadata is unreadable" in found.summary() and "--repair" in found.summary()
    calls = []
    with monkeypatch.context() as m:
        real = runner.compute_chunk
        m.setattr(runner, "compute_chunk", lambda *a: calls.append(a[1]) or real(*a))
        with pytest.warns(RepairWarning) as record:
            ds = run_small(out)
    assert calls == [(2, 0, 0), (3, 0, 0)]  # the two finished chunks kept
    lines = [str(w.message) for w in record]
    name = node or "root"
    assert lines == [f"{out}: repaired: rebuilt the metadata of {name} from the sweep's settings; kept 2 finished chunks that verify"]
    _same(ds, fresh)
    assert verify_sweep(out).intact


def test_verify_repair_rebuilds_without_computing(tmp_path, fresh, monkeypatch, capsys):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=2)
    _empty(out, "")
    _empty(out, "X_max")

    def refuse(*args):
        raise AssertionError("--verify --repair computed a chunk")

    with monkeypatch.context() as m:
        m.setattr(runner, "compute_chunk", refuse)
        assert main(["sweep", "--verify", str(out), "--repair"]) == 0
    got = capsys.readouterr()
    assert got.out.strip() == f"{out}: repaired: rebuilt the metadata of root, X_max from the sweep's settings; kept 2 finished chunks that verify"
    assert got.err == ""
    assert main(["sweep", "--verify", str(out)]) == 0
    assert "intact: 2 of 4 chunks verified (incomplete, 2 chunks still to compute)" in capsys.readouterr().out
    calls = []
    with monkeypatch.context() as m:
        real = runner.compute_chunk
        m.setattr(runner, "compute_chunk", lambda *a: calls.append(a[1]) or real(*a))
        ds = run_small(out)
    assert calls == [(2, 0, 0), (3, 0, 0)]
    _same(ds, fresh)


def test_api_repair_with_the_config_and_as_json(tmp_path, monkeypatch, capsys):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=3)
    _empty(out, "kind")
    found = repair_sweep(out, CFG)
    assert found.rebuilt == ["kind"] and found.done == 3 and found.intact
    _empty(out, "fd")  # a coordinate's metadata too
    config = tmp_path / "c.toml"
    config.write_text(CFG_TOML)
    assert main(["sweep", str(config), "--verify", str(out), "--repair", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["rebuilt"] == ["fd"] and report["verified"] == 3 and report["intact"]


def test_a_damaged_chunk_next_to_damaged_metadata_is_recomputed(tmp_path, fresh, monkeypatch):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=3)
    _empty(out, "")
    chunk = out / "X_max" / "c" / "1" / "0" / "0"
    chunk.write_bytes(chunk.read_bytes()[:5])  # truncated
    calls = []
    with monkeypatch.context() as m:
        real = runner.compute_chunk
        m.setattr(runner, "compute_chunk", lambda *a: calls.append(a[1]) or real(*a))
        with pytest.warns(RepairWarning) as record:
            ds = run_small(out)
    assert sorted(calls) == [(1, 0, 0), (3, 0, 0)]  # the damaged one and the one never computed
    lines = [str(w.message) for w in record]
    assert lines == [f"{out}: repaired: rebuilt the metadata of root from the sweep's settings; kept 2 finished chunks that verify; "
                     "1 damaged chunks (1 unreadable) recomputed"]
    _same(ds, fresh)
    assert verify_sweep(out).intact


def test_verify_repair_leaves_a_damaged_chunk_to_the_next_run(tmp_path, fresh, monkeypatch, capsys):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=3)
    _empty(out, "P_belt")
    (out / "kind" / "c" / "0" / "0" / "0").unlink()
    assert main(["sweep", "--verify", str(out), "--repair"]) == 0
    assert capsys.readouterr().out.strip().endswith("kept 2 finished chunks that verify; 1 damaged chunks (1 missing) left to recompute")
    calls = []
    with monkeypatch.context() as m:
        real = runner.compute_chunk
        m.setattr(runner, "compute_chunk", lambda *a: calls.append(a[1]) or real(*a))
        ds = run_small(out)
    assert sorted(calls) == [(0, 0, 0), (3, 0, 0)]
    _same(ds, fresh)


def test_a_store_that_cannot_be_matched_still_needs_restart(tmp_path, monkeypatch, capsys):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=2)
    _empty(out, "")
    with pytest.raises(ValueError, match="holds a different sweep .*use --restart"):
        run_small(out, {**CFG, "t_end": 50.0})
    _empty(out, "_sweep")  # nothing left that names its settings
    with pytest.raises(ValueError, match=r"exists and is not a Zarr store; use --restart to replace it"):
        run_small(out)
    assert main(["sweep", "--verify", str(out), "--repair"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "records no readable settings" in err[0] and "--restart" in err[0]
    assert main(["sweep", "--repair"]) == 2
    assert "--repair goes with --verify OUT" in capsys.readouterr().err


def test_cli_resume_in_a_subprocess_says_what_was_repaired_in_one_line(tmp_path, monkeypatch):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=2)
    _empty(out, "")
    config = tmp_path / "c.toml"
    config.write_text(CFG_TOML)
    src = str(Path(frictionflow.__file__).parents[1])  # this checkout's package, in the subprocess too
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (src, os.environ.get("PYTHONPATH")) if p)}
    done = subprocess.run([sys.executable, "-m", "frictionflow", "sweep", str(config), "--out", str(out), "--chunk-size", "4"],
                          capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    repaired = [line for line in done.stderr.splitlines() if "repaired:" in line]
    assert len(repaired) == 1 and "rebuilt the metadata of root" in repaired[0] and "kept 2 finished chunks" in repaired[0]
