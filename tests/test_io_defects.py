"""Defects of the output path found by QA: Ctrl-C during a NetCDF write, pseudo file systems, Zarr metadata,
simulate's table.

1. Ctrl-C during ``simulate --out big.nc`` hung for good: xarray's NetCDF writer takes its locks in Python
   (``with lock:``); a Ctrl-C that arrives while the library writes is raised on entry to the lock's ``__exit__``,
   before the release, and the writer's clean-up (``finally: store.close()``) then waits for that lock forever.
   The child process below delivers the signal at exactly that point (the first release after a data write).
2. /proc and /sys (no blocks, refusing new files even to root) were taken for a full disk.
3. ``simulate --out x.zarr`` was not consolidated (``xr.open_zarr`` warned).
4. simulate's table printed ``decay rate 0.05 (heading: None)``.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import textwrap
import warnings

import pytest
import xarray as xr

from frictionflow import RK4, BeltOscillator, Karnopp, simulate
from frictionflow.cli import simulate as simulate_cli
from frictionflow.cli.output import write_json
from frictionflow.io import atomic_write, check_output_path, stale_temporaries, write_error, write_trajectory

from .cli.processes import SRC, default_signals, in_process, one_line

# -- 1. Ctrl-C during a NetCDF write -----------------------------------------------------------------

#: a command line whose first NetCDF data write is followed by the signal, where a real Ctrl-C during the write lands
CHILD = textwrap.dedent("""
    import signal, sys
    from xarray.backends import locks, netCDF4_

    number = getattr(signal, sys.argv[1])
    release, write = locks.CombinedLock.__exit__, netCDF4_.NetCDF4ArrayWrapper.__setitem__
    state = []

    def release_after_signal(self, *exc):
        if state == ["written"]:  # the signal pending since the library's write is raised on entry, before the release
            state.append("signalled")
            open(sys.argv[2], "w").close()
            signal.raise_signal(number)
        return release(self, *exc)

    def data_write(self, key, value):
        state[:] = state or ["written"]
        return write(self, key, value)

    locks.CombinedLock.__exit__ = release_after_signal
    netCDF4_.NetCDF4ArrayWrapper.__setitem__ = data_write
    from frictionflow.cli import main
    sys.exit(main(sys.argv[3:]))
""")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_a_signal_during_a_netcdf_write_ends_the_command_with_exit_1_and_keeps_the_old_file(tmp_path, sig):
    script, fired, out = tmp_path / "child.py", tmp_path / "fired", tmp_path / "big.nc"
    script.write_text(CHILD)
    out.write_text("OLD")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH")])))
    argv = [sys.executable, str(script), sig, str(fired), "simulate", "--t-end", "20", "--out", str(out), "--json"]
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=tmp_path,
                         preexec_fn=default_signals)
    try:
        stdout, stderr = p.communicate(timeout=90)
    except subprocess.TimeoutExpired:
        p.kill()
        p.communicate()
        pytest.fail("the command hung after the signal (xarray's lock left held by the interrupted write)")
    assert fired.exists(), stderr  # the signal came during the write, where it is meant to
    assert p.returncode == 1 and stdout == ""
    one_line(stderr, "interrupted (Ctrl-C or SIGTERM)")
    assert out.read_text() == "OLD"
    assert stale_temporaries(out) == []


@pytest.fixture
def python_sigint():
    """Ctrl-C raising KeyboardInterrupt in this process (a test worker may ignore it), restored after."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_ctrl_c_inside_an_atomic_write_is_delivered_after_the_block_and_before_the_rename(tmp_path, python_sigint):
    target, finished = tmp_path / "r.nc", []
    target.write_text("OLD")
    with pytest.raises(KeyboardInterrupt):
        with atomic_write(target, "--out") as tmp:
            tmp.write_text("NEW")
            signal.raise_signal(signal.SIGINT)
            finished.append(True)  # the write goes on to its end: no library is left half-way
    assert finished == [True]
    assert target.read_text() == "OLD" and stale_temporaries(target) == []
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
def test_nested_atomic_writes_pass_a_held_ctrl_c_outwards(tmp_path, python_sigint):
    outer, inner = tmp_path / "a.json", tmp_path / "b.json"
    with pytest.raises(KeyboardInterrupt):
        with atomic_write(outer) as tmp_outer:
            with atomic_write(inner) as tmp_inner:
                tmp_inner.write_text("{}")
                signal.raise_signal(signal.SIGINT)
            tmp_outer.write_text("{}")
    assert not outer.exists() and not inner.exists()
    assert stale_temporaries(outer) == [] and stale_temporaries(inner) == []


def test_a_write_without_a_signal_still_renames(tmp_path, python_sigint):
    target = tmp_path / "r.json"
    with atomic_write(target) as tmp:
        tmp.write_text("{}")
    assert target.read_text() == "{}" and signal.getsignal(signal.SIGINT) is signal.default_int_handler


# -- 2. pseudo file systems ---------------------------------------------------------------------------

def _pseudo(d: str) -> bool:
    try:
        return os.statvfs(d).f_blocks == 0
    except (OSError, AttributeError):
        return False


@pytest.mark.skipif(not (_pseudo("/proc") and _pseudo("/sys")), reason="needs Linux /proc and /sys")
@pytest.mark.parametrize("argv", [
    ("simulate", "--t-end", "10", "--out", "/proc/x.nc"),
    ("simulate", "--t-end", "10", "--out", "/proc/x.nc", "--no-limit"),
    ("simulate", "--t-end", "10", "--out", "/sys/x.csv"),
    ("simulate", "--t-end", "10", "--out", "/proc/x.zarr"),
    ("orbit", "--out", "/proc/x.json"),
])
def test_a_pseudo_file_system_is_refused_as_a_path_before_any_work_not_taken_for_a_full_disk(argv):
    code, out, err, _ = in_process(*argv)
    assert code == 2 and out == ""
    line = one_line(err, "--out: ", argv[-1 if argv[-1] != "--no-limit" else -2].rsplit("/", 1)[0])
    assert line.startswith("error: --out: ")
    assert "space" not in line and "free" not in line


def test_a_directory_refusing_new_files_is_named_with_the_reason(tmp_path, monkeypatch):
    """Root passes every mode check; the file system still refuses (as /proc does): found by a probe file."""
    real_open = os.open

    def refuse(path, flags, *args):
        if ".frictionflow-probe." in os.fspath(path):
            raise OSError(errno.ENOENT, os.strerror(errno.ENOENT), os.fspath(path))
        return real_open(path, flags, *args)

    monkeypatch.setattr(os, "open", refuse)
    with pytest.raises(ValueError, match=r"^--out: cannot write files in directory .* \(no such file or directory\)$"):
        check_output_path(tmp_path / "x.nc", (".nc",), "--out")


def test_the_probe_leaves_nothing_behind(tmp_path):
    check_output_path(tmp_path / "x.nc", (".nc",), "--out")
    assert list(tmp_path.iterdir()) == []


def test_permission_denied_on_a_file_system_without_blocks_is_not_a_full_disk(tmp_path, monkeypatch):
    """/proc has f_bavail == 0 because it has no blocks at all, not because it is full."""
    stat = os.statvfs(tmp_path)
    fields = [getattr(stat, f) for f in ("f_bsize", "f_frsize", "f_blocks", "f_bfree", "f_bavail", "f_files",
                                          "f_ffree", "f_favail", "f_flag", "f_namemax")]
    fields[2:5] = [0, 0, 0]
    monkeypatch.setattr(os, "statvfs", lambda d: os.statvfs_result(fields))
    error = write_error(OSError(errno.EACCES, os.strerror(errno.EACCES)), "--out", tmp_path / "x.nc")
    assert isinstance(error, ValueError)
    assert str(error) == f"--out: cannot write {str(tmp_path / 'x.nc')!r}: permission denied"


# -- 3. Zarr stores consolidated --------------------------------------------------------------------

def test_a_trajectory_zarr_store_is_consolidated(tmp_path):
    traj = simulate(BeltOscillator(zeta=0.05, vb=0.1), Karnopp(0.02), RK4(dt=0.01), t_end=20.0)
    with warnings.catch_warnings(record=True) as written:
        warnings.simplefilter("always")
        write_trajectory(traj, tmp_path / "sim.zarr")
    assert not [w for w in written if "onsolidated" in str(w.message)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning about a store without consolidated metadata
        ds = xr.open_zarr(tmp_path / "sim.zarr", consolidated=None)
        assert set(ds) >= {"X", "V", "F_c"} and ds.sizes["tau"] == len(traj.t)
    xr.open_zarr(tmp_path / "sim.zarr", consolidated=True).close()


# -- 4. simulate's table ----------------------------------------------------------------------------

def test_an_equilibrium_prints_its_decay_rate_without_heading_none():
    code, out, err, _ = in_process("simulate", "--zeta", "0.5", "--vb", "0.1")
    assert code == 0, err
    assert "decay rate" in out and "heading" not in out and "None" not in out


def test_a_run_heading_somewhere_still_says_where(capsys):
    report = {"steady_state": {"kind": "not_settled", "window": [0.0, 10.0], "period": None, "decay_rate": 0.05,
                               "heading": "equilibrium"},
              "averages": {}, "TR_B": None, "amplitude": {}, "energy_residual": 0.0}
    simulate_cli._print_summary(report, "law x")
    assert "0.05 (heading: equilibrium)" in capsys.readouterr().out


# -- 5. --out named as given ------------------------------------------------------------------------

def test_a_failed_json_write_names_the_option_as_given(tmp_path):
    with pytest.raises(ValueError, match=r"^--out: cannot write "):
        write_json(tmp_path / "missing" / "r.json", {"a": 1})


def test_a_failed_trajectory_write_names_the_option_as_given(tmp_path):
    traj = simulate(BeltOscillator(zeta=0.05, vb=0.1), Karnopp(0.02), t_end=5.0)
    with pytest.raises(ValueError, match=r"^--out: "):
        write_trajectory(traj, tmp_path / "missing" / "r.nc", name="--out")
