"""Issue 20, item 2: every fault a clear line and nothing half-done.

A full disk, a scheduler that cannot be reached, a Dask worker killed in the
middle of a sweep and a read-only output directory each end the command with
one line ``error: ...`` and the exit code of the documented table (docs/exit_codes.md) (1: the
environment failed, the same command succeeds once the cause is gone; 2: a
path that cannot be written is bad input) -- no traceback, no ignored
exception -- and leave nothing half-written: a sweep's store resumes to a
result identical to an undisturbed run's.

The faults are real where this machine allows it (a tmpfs of a few hundred
KiB that fills up, a tmpfs remounted read-only, worker processes killed with
SIGKILL, a port nobody listens on, a web server where a scheduler should be);
each test skips when it cannot mount.
"""

from __future__ import annotations

import errno
import os
import signal
import socket
import socketserver
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
import xarray as xr

from frictionflow.cli import EXIT_CODES, main
from frictionflow.io import OutputError, write_error
from frictionflow.sweep import run_sweep, runner
from frictionflow.sweep.store import SweepStore, verify_sweep
from tests.cli.processes import SRC, cli, one_line
from tests.sweep.store_cases import CFG, CFG_TOML
from tests.test_atomic_output import readonly_dir  # noqa: F401  (fixture)

#: the sweep of tests/sweep/store_cases.py, 4 chunks of 4 points: about 100 KiB of metadata, then 68 KiB per chunk
#: --no-limit: these runs meet a disk that fills while they write; one refused before any work because its
#: output is estimated larger than the free space is tests/cli/test_estimates.py's (exit 2)
SWEEP = ["--chunk-size", "4", "--no-limit"]


# -- helpers -----------------------------------------------------------------------------------------



def listing(d: Path) -> list[str]:
    """Everything in ``d``, hidden temporaries included."""
    return sorted(p.name for p in d.iterdir())


def leftovers(store: Path) -> list[str]:
    """Temporaries inside a Zarr store (zarr writes FILE.HEX.partial, then renames it)."""
    return [str(p) for p in store.rglob("*.partial")]


def same(a: xr.Dataset, b: xr.Dataset) -> None:
    """Identical data, coordinates and attributes but the time of creation."""
    a, b = a.copy(), b.copy()
    for ds in (a, b):
        ds.attrs.pop("created", None)
    xr.testing.assert_identical(a, b)


def opened(path: Path) -> xr.Dataset:
    with (xr.open_zarr(path) if path.suffix == ".zarr" else xr.open_dataset(path)) as ds:
        return ds.load()


class Tmpfs:
    """A tmpfs of a given size mounted at ``where``; resized (space back) with :meth:`resize`."""

    def __init__(self, where: Path, size: str) -> None:
        where.mkdir()
        self.where = where
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)], capture_output=True,
                              text=True, check=False)
        if done.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here ({done.stderr.strip() or 'not permitted'})")

    def resize(self, size: str) -> None:
        subprocess.run(["mount", "-o", f"remount,size={size}", str(self.where)], check=True, capture_output=True)


    def fill(self) -> Path:
        """A file taking every free byte (the disk is then full); remove it to give the space back."""
        filler = self.where / "filler"
        fd = os.open(filler, os.O_WRONLY | os.O_CREAT)
        try:
            while os.write(fd, b"\0" * 4096):
                pass
        except OSError as e:
            assert e.errno == errno.ENOSPC
        finally:
            os.close(fd)
        return filler

    def umount(self) -> None:
        # lazy: the NetCDF library keeps a failed file open until the process ends
        subprocess.run(["umount", "-l", str(self.where)], capture_output=True, check=False)


@pytest.fixture
def tmpfs(tmp_path):
    """Mount tmpfs file systems under tmp_path: ``tmpfs(size)`` (unmounted at the end)."""
    mounted = []

    def mount(size: str, name: str = "disk") -> Tmpfs:
        fs = Tmpfs(tmp_path / name, size)
        mounted.append(fs)
        return fs

    yield mount
    for fs in mounted:
        fs.umount()


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> dict[str, xr.Dataset]:
    """The sweep computed undisturbed, as .zarr and as .nc, with the chunks the tests use."""
    d = tmp_path_factory.mktemp("reference")
    (d / "s.toml").write_text(CFG_TOML)
    return {suffix: run_and_load(d / "s.toml", d / f"r{suffix}") for suffix in (".zarr", ".nc")}


def run_and_load(config: Path, out: Path) -> xr.Dataset:
    with run_sweep(str(config), out, chunk_size=4) as ds:
        return ds.load()


def test_the_exit_codes_are_one_table_and_the_docs_give_it():
    assert set(EXIT_CODES) == {0, 1, 2}
    page = (Path(__file__).resolve().parents[2] / "docs" / "exit_codes.md").read_text()  # the CLI reference's
    table = page[page.index("**Exit codes**"):]
    for code in EXIT_CODES:
        assert f"\n| {code} | " in table[:2000]
    assert "a disk that fills" in table[:2000] and "read-only directory" in table[:2000] and "--no-limit" in table[:2000]


@pytest.mark.parametrize("number, kind", [
    (errno.ENOSPC, OutputError), (errno.EDQUOT, OutputError), (errno.EIO, OutputError), (errno.EFBIG, OutputError),
    (errno.EACCES, ValueError), (errno.EROFS, ValueError), (errno.EISDIR, ValueError), (errno.ENAMETOOLONG, ValueError),
])
def test_a_write_error_is_bad_input_only_when_the_path_is_at_fault(number, kind):
    e = write_error(OSError(number, os.strerror(number)), "--out", "/x/t.nc", "kept")
    assert type(e) is kind and str(e) == f"--out: cannot write '/x/t.nc': {os.strerror(number).lower()}; kept"
    assert write_error(KeyError("bug"), "--out", "/x/t.nc") is None  # not the file system's: raised as it is


@pytest.mark.parametrize("number, code", [(errno.ENOSPC, 1), (errno.EIO, 1), (errno.EACCES, 2), (errno.EROFS, 2)])
def test_a_system_error_no_writer_put_into_words_is_still_one_line_with_its_code(monkeypatch, capsys, number, code):
    def fails(*args, **kwargs):
        raise OSError(number, os.strerror(number), "/somewhere/t.nc")

    monkeypatch.setattr("frictionflow.cli.simulate.run_simulation", fails)
    assert main(["simulate", "--t-end", "1"]) == code
    assert capsys.readouterr().err == f"error: {os.strerror(number)}: '/somewhere/t.nc'\n"


# -- a full disk -------------------------------------------------------------------------------------

@pytest.mark.parametrize("suffix", [".zarr", ".nc"])
def test_a_sweep_that_fills_its_disk_stops_in_one_line_and_resumes_to_the_same_result(tmpfs, tmp_path, reference, suffix):
    disk = tmpfs("200k")  # the store's metadata and one chunk fit, the second chunk does not
    (tmp_path / "s.toml").write_text(CFG_TOML)
    out = disk.where / f"r{suffix}"
    journal = disk.where / "r.nc.partial.zarr" if suffix == ".nc" else out
    code, stdout, err, _ = cli("sweep", "s.toml", "--out", str(out), *SWEEP, cwd=tmp_path)
    assert code == 1 and stdout == "", err  # was: a traceback ending in OSError: [Errno 28]
    one_line(err, f"out: cannot write {str(out)!r}: no space left on device",
             "the chunks finished so far are kept: run the same command again to resume")
    assert listing(disk.where) == [journal.name] and not leftovers(journal)  # no lock, no temporary, no r.nc
    found = verify_sweep(out)
    assert found.intact and 1 <= found.done < found.n_chunks  # what was committed verifies
    code, _, err, _ = cli("sweep", "s.toml", "--out", str(out), *SWEEP, cwd=tmp_path)  # still full: the same line
    assert code == 1
    one_line(err, "no space left on device")
    assert listing(disk.where) == [journal.name]
    disk.resize("2m")  # the space back
    code, stdout, err, _ = cli("sweep", "s.toml", "--out", str(out), *SWEEP, cwd=tmp_path)
    assert code == 0, err
    assert listing(disk.where) == [out.name]
    same(opened(out), reference[suffix])
    assert verify_sweep(out).intact


def test_a_lock_whose_record_cannot_be_written_is_one_line_and_not_left_behind(tmpfs, tmp_path, capsys):
    disk = tmpfs("1m")
    filler = disk.fill()
    out = disk.where / "r.zarr"
    assert main(["sweep", str(_config(tmp_path)), "--out", str(out), *SWEEP]) == 1
    one_line(capsys.readouterr().err, f"out: cannot write {str(disk.where / 'r.zarr.lock')!r}: no space left on device",
             "nothing was computed or written")
    assert listing(disk.where) == ["filler"]  # a lock left behind would be taken over with a warning next time
    filler.unlink()
    assert main(["sweep", str(_config(tmp_path)), "--out", str(out), *SWEEP]) == 0
    assert listing(disk.where) == ["r.zarr"]


def test_a_store_the_disk_cannot_hold_even_empty_is_not_left_half_created(tmpfs, tmp_path, reference, capsys):
    disk = tmpfs("60k")  # not even the store's metadata fits
    (tmp_path / "s.toml").write_text(CFG_TOML)
    out = disk.where / "r.zarr"
    assert main(["sweep", str(tmp_path / "s.toml"), "--out", str(out), *SWEEP]) == 1
    err = capsys.readouterr().err
    one_line(err, f"out: cannot write {str(out)!r}: no space left on device; nothing was written")
    assert "kept" not in err  # no chunk was finished: there is nothing to resume from
    assert listing(disk.where) == []  # a half-made store could not say which sweep it is: only --restart would help
    disk.resize("2m")
    assert main(["sweep", str(tmp_path / "s.toml"), "--out", str(out), *SWEEP]) == 0  # no --restart needed
    same(opened(out), reference[".zarr"])


@pytest.fixture
def late_siblings(monkeypatch):
    """zarr's writes with the race a full disk brings, made certain: the first write that starts while another is in
    flight fails at once with ENOSPC, and every other write waits 0.1 s first (zarr writes a batch of keys at once,
    each in a worker thread, and a failed call returns while its siblings are still writing)."""
    local = pytest.importorskip("zarr.storage._local")
    real, lock, state = local._put, threading.Lock(), {"active": 0, "failed": False}

    def put(path, value, exclusive=False):
        with lock:
            state["active"] += 1
            fail = state["active"] > 1 and not state["failed"]
            state["failed"] |= fail
        try:
            if fail:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
            time.sleep(0.1)
            return real(path, value, exclusive)
        finally:
            with lock:
                state["active"] -= 1

    monkeypatch.setattr(local, "_put", put)
    return state


@pytest.mark.parametrize("command", [["sweep", "s.toml", *SWEEP], ["simulate", "--t-end", "5"]], ids=["sweep", "simulate"])
def test_a_store_that_fails_while_zarr_still_writes_is_not_left_behind(late_siblings, tmp_path, capsys, command):
    """The failed store is removed after the writes still in flight, which would otherwise make its directories
    again (seen once in CI as a ``.r.<token>.tmp.zarr`` left by a sweep on a full disk)."""
    (tmp_path / "s.toml").write_text(CFG_TOML)
    out = tmp_path / "disk"
    out.mkdir()
    code = main([*command, "--out", str(out / "r.zarr")] if command[0] == "simulate" else
                [command[0], str(tmp_path / "s.toml"), "--out", str(out / "r.zarr"), *command[2:]])
    assert late_siblings["failed"], "zarr wrote no two keys at once here: the race was not exercised"
    assert code == 1
    one_line(capsys.readouterr().err, "no space left on device")
    time.sleep(0.3)  # any write still on its way has landed
    assert listing(out) == []


def test_a_creation_killed_half_way_leaves_a_temporary_the_next_run_removes(tmp_path, reference):
    out = tmp_path / "r.zarr"
    stale = tmp_path / ".r.0badcafe.tmp.zarr"  # what a run killed while creating its store leaves
    (stale / "kind").mkdir(parents=True)
    same(run_and_load(_config(tmp_path), out), reference[".zarr"])
    assert listing(tmp_path) == ["r.zarr", "s.toml"]


def _config(d: Path) -> Path:
    (d / "s.toml").write_text(CFG_TOML)
    return d / "s.toml"


def test_a_netcdf_conversion_on_a_full_disk_keeps_the_journal_and_converts_it_next_time(tmpfs, tmp_path, reference, monkeypatch, capsys):
    disk = tmpfs("1m")
    out = disk.where / "r.nc"
    filler = []
    real_finish = SweepStore.finish

    def full_then_finish(self):
        filler.append(disk.fill())  # every chunk is in the journal: now the disk is full
        return real_finish(self)

    config = _config(tmp_path)
    with monkeypatch.context() as m:
        m.setattr(SweepStore, "finish", full_then_finish)
        assert main(["sweep", str(config), "--out", str(out), *SWEEP]) == 1
    one_line(capsys.readouterr().err, f"out: cannot write {str(out)!r}: no space left on device",
             f"every chunk is kept in {str(disk.where / 'r.nc.partial.zarr')!r}: run the same command again to convert it")
    assert listing(disk.where) == ["filler", "r.nc.partial.zarr"]
    filler[0].unlink()
    calls = []
    monkeypatch.setattr(runner, "compute_chunk", lambda *a: calls.append(a) or pytest.fail("recomputed a chunk"))
    assert main(["sweep", str(config), "--out", str(out), *SWEEP]) == 0
    assert calls == [] and listing(disk.where) == ["r.nc"]
    same(opened(out), reference[".nc"])


@pytest.mark.parametrize("node", ["", "kind"], ids=["root", "kind"])
def test_a_repair_on_a_full_disk_stops_in_one_line_and_the_store_still_repairs_and_resumes(tmpfs, tmp_path, reference,
                                                                                          monkeypatch, capsys, node):
    """``sweep --verify OUT --repair`` rebuilds an emptied ``zarr.json``: on a disk that is full once it holds the
    lock, it says what the sweep says there (exit 1), writes no half file, and the same repair succeeds once there is
    room, keeping the finished chunk."""
    disk = tmpfs("200k")  # the store's metadata and one chunk fit, the second chunk does not
    config, out = _config(tmp_path), disk.where / "r.zarr"
    assert cli("sweep", str(config), "--out", str(out), *SWEEP)[0] == 1  # a real full disk left it half done
    done = verify_sweep(out).done
    assert 1 <= done < 4
    (out / node / "zarr.json").write_bytes(b"")  # damaged metadata: what --repair rebuilds
    filler = []

    class FillsTheDisk(runner.SweepLock):
        def acquire(self):
            super().acquire()
            filler.append(disk.fill())  # the lock is taken: now the disk is full

    with monkeypatch.context() as m:
        m.setattr(runner, "SweepLock", FillsTheDisk)
        assert main(["sweep", "--verify", str(out), "--repair"]) == 1
    got = capsys.readouterr()
    assert got.out == "" and filler  # was: the generic line, without what is kept and how to go on
    one_line(got.err, f"--verify: cannot write {str(out)!r}: no space left on device",
             "the chunks finished so far are kept: run the same command again to resume")
    assert listing(disk.where) == ["filler", out.name] and not leftovers(out)  # no lock, no temporary
    filler[0].unlink()
    disk.resize("2m")  # room: the page the sweep left free held the lock, not the rebuilt metadata
    assert main(["sweep", "--verify", str(out), "--repair"]) == 0
    got = capsys.readouterr()
    assert got.out.startswith(f"{out}: repaired: rebuilt the metadata of {node or 'root'} from the sweep's settings; "
                              f"kept {done} finished chunk") and got.err == "", got
    calls = []
    real = runner.compute_chunk
    monkeypatch.setattr(runner, "compute_chunk", lambda *a: calls.append(a) or real(*a))
    assert main(["sweep", str(config), "--out", str(out), *SWEEP]) == 0
    assert 0 < len(calls) == verify_sweep(out).n_chunks - done  # the finished chunks kept
    same(opened(out), reference[".zarr"])


@pytest.mark.parametrize("command, name", [
    (["simulate", "--solver", "rk4", "--dt", "0.01", "--t-end", "20", "--no-limit"], "t.nc"),
    (["response", "--vary", "omega=0.5:1.5:3", "--fex", "0.01", "--zeta", "0.05", "--periods", "20", "--no-limit"], "r.nc"),
])
def test_a_single_run_output_on_a_full_disk_is_one_line_exit_1_and_no_file(tmpfs, tmp_path, capsys, command, name):
    disk = tmpfs("1m")
    filler = disk.fill()
    out = disk.where / name
    assert main([*command, "--out", str(out)]) == 1
    one_line(capsys.readouterr().err, f"--out: cannot write {str(out)!r}: no space left on device")
    assert listing(disk.where) == ["filler"]
    filler.unlink()
    assert main([*command, "--out", str(out)]) == 0
    assert listing(disk.where) == [name]
    capsys.readouterr()
    assert main([*command, "--out", str(tmp_path / name)]) == 0  # the same as written where there was room
    xr.testing.assert_identical(opened(out), opened(tmp_path / name))


BASINS = ["basins", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--vb", "0.01", "--zeta", "0.05",
          "--t-end", "100", "--x0-range", "-0.05:0.05:3", "--v0-range", "-0.05:0.05:3", "--chunk-size", "3",
          "--no-limit"]


def test_basins_on_a_full_disk_keep_their_store_and_resume_without_recomputing(tmpfs, tmp_path, monkeypatch, capsys):
    disk = tmpfs("1m")
    filler = disk.fill()
    out, store = disk.where / "b.nc", tmp_path / "b.zarr"
    assert main([*BASINS, "--out", str(out), "--store", str(store)]) == 1
    one_line(capsys.readouterr().err, f"out: cannot write {str(out)!r}: no space left on device")
    assert listing(disk.where) == ["filler"] and verify_sweep(store).intact  # the computed sweep is kept
    filler.unlink()
    monkeypatch.setattr(runner, "compute_chunk", lambda *a: pytest.fail("recomputed a chunk"))
    assert main([*BASINS, "--out", str(out), "--store", str(store)]) == 0
    monkeypatch.undo()
    assert main([*BASINS, "--out", str(tmp_path / "ref.nc")]) == 0
    same(opened(out), opened(tmp_path / "ref.nc"))


def test_basins_whose_store_fills_the_disk_stop_in_one_line(tmpfs, capsys):
    disk = tmpfs("200k")
    out = disk.where / "b.nc"
    assert main([*BASINS, "--out", str(out)]) == 1
    one_line(capsys.readouterr().err, "no space left on device", "run the same command again to resume")
    assert listing(disk.where) == ["b.nc.sweep.zarr"]  # the store, kept to resume; no b.nc


# -- a read-only output directory --------------------------------------------------------------------

@pytest.mark.parametrize("command, name", [
    (["sweep", "{config}", *SWEEP], "r.zarr"),
    (["sweep", "{config}", *SWEEP], "r.nc"),
    (BASINS, "b.nc"),
    (["response", "--vary", "omega=0.5:1.5:3", "--fex", "0.01"], "r.nc"),
    (["simulate", "--t-end", "10"], "t.csv"),
])
def test_a_read_only_output_directory_is_refused_in_one_line_before_any_work(readonly_dir, tmp_path, command, name):
    argv = [a.replace("{config}", str(_config(tmp_path))) for a in command]
    code, stdout, err, _ = cli(*argv, "--out", str(readonly_dir / name))
    assert code == 2 and stdout == ""
    one_line(err, str(readonly_dir), "read-only file system")
    assert listing(readonly_dir) == []


def _mount(*args: str) -> None:
    done = subprocess.run(["mount", *args], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        pytest.skip(f"cannot mount here ({done.stderr.strip() or 'not permitted'})")


def test_a_store_made_read_only_during_a_sweep_stops_it_in_one_line_and_it_resumes(tmp_path, reference, monkeypatch, capsys):
    out = tmp_path / "r.zarr"
    config = _config(tmp_path)
    real_write, written = SweepStore.write, []

    def write_then_read_only(self, chunk, results):
        real_write(self, chunk, results)
        written.append(chunk)
        if len(written) == 2:  # the store, mounted read-only over itself (the lock beside it stays open for writing)
            _mount("--bind", str(out), str(out))
            _mount("-o", "remount,ro,bind", str(out))

    try:
        with monkeypatch.context() as m:
            m.setattr(SweepStore, "write", write_then_read_only)
            assert main(["sweep", str(config), "--out", str(out), *SWEEP]) == 2
    finally:
        subprocess.run(["umount", str(out)], capture_output=True, check=False)
    one_line(capsys.readouterr().err, f"out: cannot write {str(out)!r}: read-only file system",
             "the chunks finished so far are kept")
    assert not leftovers(out) and verify_sweep(out).done == 2
    calls = []
    real = runner.compute_chunk
    monkeypatch.setattr(runner, "compute_chunk", lambda *a: calls.append(a[1]) or real(*a))
    assert main(["sweep", str(config), "--out", str(out), *SWEEP]) == 0
    assert calls == [(2, 0, 0), (3, 0, 0)]  # only what was not finished
    same(opened(out), reference[".zarr"])


# -- a scheduler that cannot be reached --------------------------------------------------------------

def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_well_formed_address_nobody_listens_on_is_one_line_without_a_stall(tmp_path):
    pytest.importorskip("distributed")
    address = f"tcp://127.0.0.1:{_free_port()}"
    code, stdout, err, seconds = cli("sweep", str(_config(tmp_path)), "--out", "r.zarr", "--scheduler", address,
                                     "--scheduler-timeout", "1", cwd=tmp_path)
    assert code == 1 and stdout == ""
    one_line(err, f"cannot connect to the Dask scheduler at {address}: no answer within 1 s")
    assert "Exception ignored" not in err and seconds < 9, seconds  # no half-made Client closing at exit
    assert listing(tmp_path) == ["s.toml"]  # no store, no lock


class _WebServer(socketserver.BaseRequestHandler):
    """Answers anything at once as a web server (or a proxy) does: a status line and headers."""

    def handle(self) -> None:
        self.request.sendall(b"HTTP/1.1 400 Bad Request\r\nconnection: close\r\ncontent-length: 0\r\n\r\n")
        self.request.recv(4096)


def test_a_web_server_where_the_scheduler_should_be_is_one_line_without_an_ignored_exception(tmp_path):
    pytest.importorskip("distributed")
    server = socketserver.ThreadingTCPServer(("127.0.0.1", 0), _WebServer)
    server.daemon_threads = True
    threading.Thread(target=server.serve_forever, daemon=True).start()
    address = f"tcp://127.0.0.1:{server.server_address[1]}"
    try:
        code, stdout, err, seconds = cli("sweep", str(_config(tmp_path)), "--out", "r.zarr", "--scheduler", address,
                                         "--scheduler-timeout", "2", cwd=tmp_path)
    finally:
        server.shutdown()
        server.server_close()
    assert code == 1 and stdout == ""  # was: a MemoryError about 3 EiB, then Client.__del__'s ignored TimeoutError
    one_line(err, f"at {address}: something answers there, but not")
    assert "Exception ignored" not in err and seconds < 9, seconds
    assert listing(tmp_path) == ["s.toml"]


# -- a killed Dask worker ----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def cluster():
    """Two worker processes (each under a nanny that restarts it when it is killed)."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as c:
        yield c


def _kill_workers_once(client, monkeypatch) -> list:
    """SIGKILL every worker process right after the first chunk is committed (others are then in flight)."""
    pids, committed = list(client.run(os.getpid).values()), []
    real = SweepStore.write

    def write(self, chunk, results):
        real(self, chunk, results)
        if not committed:
            for pid in pids:
                os.kill(pid, signal.SIGKILL)
        committed.append(chunk)

    monkeypatch.setattr(SweepStore, "write", write)
    return committed


def test_a_sweep_whose_workers_are_killed_completes_with_the_same_result(cluster, tmp_path, reference, monkeypatch):
    from distributed import Client

    with Client(cluster) as client:
        committed = _kill_workers_once(client, monkeypatch)
        with run_sweep(str(_config(tmp_path)), tmp_path / "r.zarr", client=client, chunk_size=4) as ds:
            same(ds.load(), reference[".zarr"])  # the lost tasks rerun on the restarted workers
    assert sorted(committed) == [(i, 0, 0) for i in range(4)]


def test_what_dask_recovers_from_by_itself_is_not_printed(cluster, tmp_path, reference, monkeypatch):
    import io
    import logging

    client_log, terminal = logging.getLogger("distributed.client"), io.StringIO()
    handler = logging.StreamHandler(terminal)  # as distributed's own, which writes to the terminal
    real = SweepStore.write

    def write(self, chunk, results):  # what the client logs when a result's worker died before it was gathered
        client_log.warning("Couldn't gather 1 keys, rescheduling")
        real(self, chunk, results)

    monkeypatch.setattr(SweepStore, "write", write)
    client_log.addHandler(handler)
    try:
        out = tmp_path / "r.zarr"
        assert main(["sweep", str(_config(tmp_path)), "--out", str(out), *SWEEP, "--scheduler", cluster.scheduler_address]) == 0
        assert terminal.getvalue() == ""
        client_log.warning("after the run")  # the client's log is back as it was
        assert terminal.getvalue() == "after the run\n"
    finally:
        client_log.removeHandler(handler)
    same(opened(out), reference[".zarr"])


def _slow_chunks(seconds: float) -> None:
    """On a worker: every chunk takes at least ``seconds`` (so that a kill lands while chunks run)."""
    from frictionflow.sweep import compute

    real = compute.compute_chunk

    def slow(*args):
        time.sleep(seconds)
        return real(*args)

    compute.compute_chunk = slow  # the tasks name the function by its module: they find this one


def test_a_chunk_lost_with_its_workers_stops_the_sweep_in_one_line_and_it_resumes(cluster, tmp_path, reference, monkeypatch):
    from distributed import Client

    out = tmp_path / "r.zarr"
    config = str(_config(tmp_path))
    monkeypatch.setattr(cluster.scheduler, "allowed_failures", 0)  # one death of a worker running it: KilledWorker
    with Client(cluster) as client:
        client.wait_for_workers(2)
        client.run(_slow_chunks, 1.0)
        pids = list(client.run(os.getpid).values())
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH")])))
        run = subprocess.Popen([sys.executable, "-m", "frictionflow", "sweep", config, "--out", str(out), *SWEEP,
                                "--scheduler", cluster.scheduler_address], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
        flags = out / "_sweep" / "chunks_done" / "c"
        deadline = time.monotonic() + 240
        while not (flags.is_dir() and any(flags.iterdir())) and run.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        for pid in pids:  # the first chunk is committed, the others are running or queued on these
            os.kill(pid, signal.SIGKILL)
        stdout, err = run.communicate(timeout=240)
    assert run.returncode == 1 and stdout == ""
    one_line(err, "the Dask cluster lost chunk", "every worker that ran it died",
             "the chunks finished so far are kept: run the same command again to resume")
    assert not (tmp_path / "r.zarr.lock").exists()
    found = verify_sweep(out)
    assert found.intact and 1 <= found.done < found.n_chunks
    monkeypatch.undo()
    same(run_and_load(Path(config), out), reference[".zarr"])  # resumed here, without the cluster
