"""Sweep stores that detect damage and lock (issue 10, point 5; examples 9 and 10).

Damaged chunks are found on resume (checksums recorded with the done-flags)
and recomputed, with a message; ``sweep --verify`` checks a store without
computing; one run at a time per output; an unreachable scheduler and an
output that is not a sweep are one-line errors.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

from frictionflow.cli import main
from frictionflow.sweep import run_sweep
from frictionflow.sweep.lock import OutputInUseError, StaleLockWarning, SweepLock, lock_path
from frictionflow.sweep.store import RepairWarning, verify_sweep

from .store_cases import CFG, CFG_TOML, interrupted, run_small


def _strip_time(ds: xr.Dataset) -> xr.Dataset:
    ds = ds.copy()
    ds.attrs.pop("created")
    return ds


def _same(ds: xr.Dataset, ref: xr.Dataset) -> None:
    xr.testing.assert_identical(_strip_time(ds), _strip_time(ref))


def _chunk_file(out, var: str, chunk: int):
    """The file of chunk ``chunk`` (along zeta) of variable ``var`` in a Zarr store."""
    return out / var / "c" / str(chunk) / "0" / "0"


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> xr.Dataset:
    """The uninterrupted, undamaged sweep."""
    return run_small(tmp_path_factory.mktemp("fresh") / "fresh.zarr")


@pytest.fixture
def config_file(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(CFG_TOML)
    return path


# -- damage found on resume (example 10) ------------------------------------------------------

def test_deleted_truncated_and_altered_chunks_are_recomputed_with_a_message(tmp_path, fresh):
    out = tmp_path / "c.zarr"
    run_small(out)
    _chunk_file(out, "P_belt", 1).unlink()  # missing: read back as NaN
    _chunk_file(out, "kind", 2).write_bytes(_chunk_file(out, "kind", 2).read_bytes()[:5])  # truncated
    shutil.copy(_chunk_file(out, "X_max", 0), _chunk_file(out, "X_max", 3))  # valid data, wrong values
    with pytest.warns(RepairWarning, match=r"recomputing 3 of 4 chunks that were damaged: 1 missing, 1 unreadable, 1 checksum mismatch"):
        ds = run_small(out)
    _same(ds, fresh)
    assert verify_sweep(out).intact


@pytest.mark.parametrize("damage", ["flag files emptied", "flag metadata emptied", "bookkeeping deleted"])
def test_damaged_done_flags_are_rebuilt_from_the_data(tmp_path, fresh, damage):
    """'An empty done-flag breaks every resume without a hint': now it is repaired, and said so."""
    out = tmp_path / "c.zarr"
    run_small(out)
    flags = out / "_sweep" / "chunks_done"
    if damage == "flag files emptied":
        for f in (flags / "c").iterdir():
            f.write_bytes(b"")
    elif damage == "flag metadata emptied":
        (flags / "zarr.json").write_bytes(b"")
    else:
        shutil.rmtree(out / "_sweep")
    _chunk_file(out, "P_belt", 1).unlink()  # without checksums a missing file must still be found
    assert not verify_sweep(out).intact or damage == "bookkeeping deleted"
    with pytest.warns(RepairWarning) as record:
        ds = run_small(out)
    messages = [str(w.message) for w in record]
    assert any("checked every chunk's data instead, kept 3 complete chunks" in m for m in messages), messages
    assert any("recomputing 1 of 4 chunks that were damaged: 1 missing" in m for m in messages), messages
    _same(ds, fresh)
    found = verify_sweep(out)
    assert found.intact and not found.unrecorded  # the checksums are recorded again


def test_interrupted_run_releases_its_lock_and_an_emptied_flag_is_repaired(tmp_path, fresh, monkeypatch):
    out = tmp_path / "c.zarr"
    interrupted(out, monkeypatch, after=2)
    assert not lock_path(out).exists()
    (out / "_sweep" / "chunks_done" / "c" / "0").write_bytes(b"")  # one done-flag emptied
    with pytest.warns(RepairWarning, match=r"done-flags: 1 of 4 unreadable.*kept 1 complete chunks"):
        ds = run_small(out)
    _same(ds, fresh)


def test_netcdf_output_is_checked_and_repaired_too(tmp_path):
    netCDF4 = pytest.importorskip("netCDF4")
    ref = run_small(tmp_path / "fresh.nc")
    out = tmp_path / "c.nc"
    run_small(out)
    assert verify_sweep(out).intact
    with netCDF4.Dataset(out, "a") as nc:  # one value of chunk 2 changed, the file still valid
        nc["X_max"][2, 0, 0] = nc["X_max"][2, 0, 0] + 1e-3
    found = verify_sweep(out)
    assert [(b.chunk, b.reason) for b in found.bad] == [((2, 0, 0), "checksum mismatch")]
    with pytest.warns(RepairWarning, match="recomputing 1 of 4 chunks that were damaged: 1 checksum mismatch"):
        ds = run_small(out)
    _same(ds, ref)
    assert verify_sweep(out).intact and not (tmp_path / "c.nc.partial.zarr").exists()


# -- sweep --verify --------------------------------------------------------------------------------

def test_verify_reports_each_bad_chunk_and_exits_1_only_when_damaged(tmp_path, capsys):
    out = tmp_path / "v.zarr"
    run_small(out)
    assert main(["sweep", "--verify", str(out)]) == 0
    got = capsys.readouterr()
    assert got.out.strip() == f"{out}: intact: 4 of 4 chunks verified (complete)" and got.err == ""
    _chunk_file(out, "P_belt", 1).unlink()
    _chunk_file(out, "kind", 2).write_bytes(b"\x28\xb5")
    assert main(["sweep", "--verify", str(out)]) == 1
    got = capsys.readouterr()
    lines = got.out.splitlines()
    assert len(lines) == 2 and lines[0] == f"{out}: chunk (1, 0, 0) (zeta[1:2] vb[0:2] fd[0:2]): missing: P_belt"
    assert lines[1].startswith(f"{out}: chunk (2, 0, 0) (zeta[2:3] vb[0:2] fd[0:2]): unreadable: kind (")
    assert got.err.splitlines() == [f"error: {out}: damaged: 2 of 4 chunks bad (1 missing, 1 unreadable); run the same sweep again to recompute what is bad"]
    assert main(["sweep", "--verify", str(out), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["intact"] is False and [b["chunk"] for b in report["bad"]] == [[1, 0, 0], [2, 0, 0]]
    assert not _chunk_file(out, "P_belt", 1).exists()  # verifying computes and repairs nothing


def test_verify_of_an_unfinished_store_and_of_an_unreadable_netcdf(tmp_path, capsys, monkeypatch):
    out = tmp_path / "u.zarr"
    interrupted(out, monkeypatch, after=1)
    assert main(["sweep", "--verify", str(out)]) == 0
    assert "intact: 1 of 4 chunks verified (incomplete, 3 chunks still to compute)" in capsys.readouterr().out
    nc = tmp_path / "t.nc"
    run_small(nc)
    nc.write_bytes(nc.read_bytes()[:3000])  # truncated: HDF5 signature, unreadable
    assert main(["sweep", "--verify", str(nc)]) == 1
    err = capsys.readouterr().err.strip()
    # (its attributes unread, it cannot be told a sweep's: --restart does not replace it)
    assert err.startswith(f"error: {nc}: damaged: a NetCDF file that cannot be opened") and err.endswith("remove it yourself to start over")


# -- one run at a time (example 10) ----------------------------------------------------------------

def test_a_run_on_a_locked_output_fails_at_once_naming_the_holder(tmp_path, config_file, capsys):
    out = tmp_path / "c.zarr"
    with SweepLock(out) as held:
        info = json.loads(held.path.read_text())
        t0 = time.monotonic()
        assert main(["sweep", str(config_file), "--out", str(out)]) == 1
        assert time.monotonic() - t0 < 5
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {out} is in use by PID {os.getpid()} (started {info['started']}); wait for it to finish or stop it (lock file {out}.lock)"]
    assert not out.exists() and not lock_path(out).exists()


def test_two_runs_on_one_output_one_fails_at_once_the_other_finishes(tmp_path):
    cfg = tmp_path / "slow.toml"
    cfg.write_text(CFG_TOML.replace("t_end = 100.0", "t_end = 300.0").replace("zeta = [0.0, 0.04, 0.08, 0.12]", "zeta = { start = 0.0, stop = 0.12, num = 80 }"))
    out = tmp_path / "s.zarr"
    cmd = [sys.executable, "-m", "frictionflow", "sweep", str(cfg), "--out", str(out), "--chunk-size", "8"]
    procs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(2)]
    ends = [p.communicate(timeout=300) for p in procs]
    codes = [p.returncode for p in procs]
    assert sorted(codes) == [0, 1], ends
    winner, loser = (0, 1) if codes[0] == 0 else (1, 0)
    err = ends[loser][1].strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {out} is in use by PID {procs[winner].pid} (started "), err
    with xr.open_zarr(out, consolidated=False) as ds:
        done = ds.load()
    _same(done, run_sweep(cfg, tmp_path / "fresh.zarr", chunk_size=8).load())
    assert not lock_path(out).exists()


def test_stale_locks_are_taken_over_with_a_warning(tmp_path, fresh):
    out = tmp_path / "c.zarr"
    lock = lock_path(out)
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    lock.write_text(json.dumps({"pid": gone.pid, "host": socket.gethostname(), "started": "2020-01-01T00:00:00+00:00"}))
    with pytest.warns(StaleLockWarning, match=rf"taking over a stale lock of PID {gone.pid} \(started 2020-01-01.*\): PID {gone.pid} is no longer running"):
        _same(run_small(out), fresh)
    assert not lock.exists()
    # another host's lock: held while it is refreshed, stale once older than lock_stale_after
    lock.write_text(json.dumps({"pid": 4242, "host": "elsewhere.invalid", "started": "2020-01-01T00:00:00+00:00"}))
    with pytest.raises(OutputInUseError, match=r"in use by PID 4242 on host elsewhere.invalid \(started 2020-01-01"):
        run_small(out)
    old = time.time() - 3600
    os.utime(lock, (old, old))
    with pytest.warns(StaleLockWarning, match=r"PID 4242 on host elsewhere.invalid .*not refreshed for 60 min \(stale after 10 min\)"):
        run_small(out)
    assert not lock.exists()


def test_without_flock_a_lock_is_judged_by_its_pid_and_start_time(tmp_path, monkeypatch):
    from frictionflow.sweep import lock as lk

    monkeypatch.setattr(lk, "fcntl", None)  # a file system without flock
    out, live = tmp_path / "c.zarr", os.getppid()
    if lk._proc_start(live) is None:
        pytest.skip("no /proc: process start times unknown")
    record = {"pid": live, "host": socket.gethostname(), "started": "2020-01-01T00:00:00+00:00", "proc_start": lk._proc_start(live)}
    lock_path(out).write_text(json.dumps(record))
    with pytest.raises(OutputInUseError, match=rf"in use by PID {live} \(started 2020-01-01"):
        SweepLock(out).acquire()
    lock_path(out).write_text(json.dumps({**record, "proc_start": "1"}))  # that PID now belongs to another process
    with pytest.warns(StaleLockWarning, match=f"PID {live} is no longer running"):
        with SweepLock(out):
            pass
    assert not lock_path(out).exists()


def test_the_lock_is_released_on_error(tmp_path):
    out = tmp_path / "c.zarr"
    run_small(out)
    with pytest.raises(ValueError, match="config changed"):
        run_small(out, {**CFG, "t_end": 50.0})
    assert not lock_path(out).exists()


# -- an unreachable scheduler (example 9) -------------------------------------------------------

def test_an_unreachable_scheduler_is_a_prompt_one_line_error(tmp_path, config_file, capsys):
    pytest.importorskip("distributed")
    out = tmp_path / "s.zarr"
    t0 = time.monotonic()
    code = main(["sweep", str(config_file), "--out", str(out), "--scheduler", "tcp://127.0.0.1:1", "--scheduler-timeout", "1"])
    elapsed = time.monotonic() - t0
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 1 and elapsed < 8, (code, elapsed)
    assert len(err) == 1 and err[0].startswith("error: cannot connect to the Dask scheduler at tcp://127.0.0.1:1: no answer within 1 s"), err
    assert not out.exists() and not lock_path(out).exists()  # nothing written
    assert main(["sweep", str(config_file), "--out", str(out), "--scheduler", "nowhere"]) == 2
    assert "bad address 'nowhere'" in capsys.readouterr().err


# -- an output that is not a sweep (example 6) ----------------------------------------------------

def _text(p):
    p.write_text("not a sweep\n")


def _dir_with_a_file(p):
    p.mkdir()
    (p / "notes.txt").write_text("x")


def _foreign_netcdf(p):
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(p)


@pytest.mark.parametrize(
    "name, make, says",
    [
        ("garbage.nc", _text, "exists and is not a NetCDF file"),
        ("folder.nc", _dir_with_a_file, "is a directory, not a NetCDF file"),
        ("foreign.nc", _foreign_netcdf, "is a NetCDF file but not a frictionflow sweep"),
        ("garbage.zarr", _text, "exists and is not a Zarr store (it is a file)"),
        ("folder.zarr", _dir_with_a_file, "exists and is not a Zarr store"),
    ],
)
def test_an_output_that_is_not_a_sweep_is_named_as_such(tmp_path, config_file, capsys, name, make, says):
    target = tmp_path / name
    make(target)
    # (never "use --restart": a run replaces only what a sweep wrote)
    keep = "frictionflow did not write it, so it is never replaced: give another --out or remove it yourself"
    for argv, name, advice in ((["sweep", str(config_file), "--out", str(target)], "--out", keep),
                               (["sweep", "--verify", str(target)], "--verify",  # (--verify takes no --restart)
                                "nothing to verify: give the .zarr or .nc a sweep wrote")):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err == [f"error: {name}: {str(target)!r} {says}; {advice}"], err
    assert target.exists() and not lock_path(target).exists()
