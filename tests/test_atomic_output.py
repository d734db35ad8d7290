"""Atomic file output: a file appears whole under its name or not at all.

Failures are forced three ways: a real full or read-only file system (a small
tmpfs, when this machine lets the tests mount one), a read-only directory for
a non-root user, and writers patched to fail half-way (everywhere).
"""

from __future__ import annotations

import errno
import os
import secrets
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from frictionflow import BeltOscillator, Karnopp, RK4, simulate
from frictionflow.io import OutputError, atomic_write, check_output_path, stale_temporaries, temporary_path, write_figure, write_trajectory

ENOSPC = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


# -- fixtures: file systems that fail ---------------------------------------------------------------

def _mount_tmpfs(where: Path, size: str) -> None:
    where.mkdir()
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)],
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({proc.stderr.strip() or 'not permitted'})")


def _umount(where: Path) -> None:
    # lazy: the NetCDF library keeps a failed file open until the process ends, which makes the mount busy
    subprocess.run(["umount", "-l", str(where)], capture_output=True, check=False)


@pytest.fixture
def full_dir(tmp_path):
    """A directory on a 64 KiB tmpfs: any sizeable file fills it (ENOSPC)."""
    where = tmp_path / "full"
    _mount_tmpfs(where, "64k")
    yield where
    _umount(where)


@pytest.fixture
def readonly_dir(tmp_path):
    """A directory nothing can be created in.

    Root ignores permission bits, so as root it is a tmpfs remounted read-only;
    as another user, a directory with mode 0555.
    """
    where = tmp_path / "ro"
    if os.geteuid() != 0:
        where.mkdir()
        where.chmod(0o555)
        yield where
        where.chmod(0o755)
        return
    _mount_tmpfs(where, "1m")
    proc = subprocess.run(["mount", "-o", "remount,ro", str(where)], capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        _umount(where)
        pytest.skip(f"cannot remount a tmpfs read-only here ({proc.stderr.strip()})")
    yield where
    _umount(where)


def entries(d: Path) -> list[str]:
    """Everything in ``d``, hidden temporaries included."""
    return sorted(p.name for p in d.iterdir())


def half_then_fail(error: BaseException):
    """A writer (function or method) that writes part of its file, then fails with ``error``."""

    def write(*args, **kwargs):
        path = next(a for a in args if isinstance(a, (str, os.PathLike)))
        Path(path).write_bytes(b"partial")
        raise error

    return write


@pytest.fixture(scope="module")
def traj():
    return simulate(BeltOscillator(zeta=0.02, vb=0.01), Karnopp(0.02, fs=0.03), RK4(dt=1e-2), t_end=20.0)


# -- the helper -------------------------------------------------------------------------------------

def test_a_completed_write_replaces_the_target_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "a.csv"
    target.write_text("old")
    with atomic_write(target) as tmp:
        assert tmp.parent == tmp_path and tmp.suffix == ".csv" and not tmp.exists()
        tmp.write_text("new")
        assert target.read_text() == "old"  # nothing is visible under the name until the end
    assert target.read_text() == "new" and entries(tmp_path) == ["a.csv"]


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "a.csv"
    target.write_text("old")
    with pytest.raises(OutputError, match=r"^--out: cannot write '.*a\.csv': no space left on device$"):
        with atomic_write(target, "--out") as tmp:
            tmp.write_text("partial")
            raise ENOSPC
    assert target.read_text() == "old" and entries(tmp_path) == ["a.csv"]


def test_an_error_that_is_not_the_file_systems_passes_through_and_cleans_up(tmp_path):
    with pytest.raises(KeyError):
        with atomic_write(tmp_path / "a.nc") as tmp:
            tmp.write_text("partial")
            raise KeyError("bug")
    assert entries(tmp_path) == []


def test_a_directory_in_the_way_is_found_at_the_rename(tmp_path):
    (tmp_path / "d.png").mkdir()
    with pytest.raises(ValueError, match=r"^--plot: cannot write .*d\.png"):
        with atomic_write(tmp_path / "d.png", "--plot") as tmp:
            tmp.write_text("whole")
    assert entries(tmp_path) == ["d.png"] and (tmp_path / "d.png").is_dir()


def test_temporaries_are_hidden_keep_the_extension_and_fit_where_the_target_fits(tmp_path):
    long = tmp_path / ("x" * 250 + ".nc")
    tmp = temporary_path(long)
    assert tmp.name.startswith(".") and tmp.suffix == ".nc" and len(tmp.name) < 100
    assert temporary_path(long) != tmp  # each writer its own
    stale = temporary_path(tmp_path / "r.nc")
    stale.write_text("left by a killed writer")
    (tmp_path / "r.nc").write_text("the target itself is not a temporary")
    assert stale_temporaries(tmp_path / "r.nc") == [stale]


# -- checks before any work -------------------------------------------------------------------------

def test_check_output_path_refuses_a_directory_and_a_path_under_a_file(tmp_path):
    (tmp_path / "t.csv").mkdir()
    with pytest.raises(ValueError, match=r"^--out: '.*t\.csv' is a directory$"):
        check_output_path(tmp_path / "t.csv", (".csv",), "--out")
    (tmp_path / "file").write_text("")
    with pytest.raises(ValueError, match=r"^--out: '.*file' is a file, not a directory$"):
        check_output_path(tmp_path / "file" / "t.csv", (".csv",), "--out")


def test_check_output_path_refuses_a_name_too_long_and_a_missing_directory(tmp_path):
    with pytest.raises(ValueError, match=r"^--out: the file name of .* is too long \(304 bytes"):
        check_output_path(tmp_path / ("a" * 300 + ".csv"), (".csv",), "--out")
    with pytest.raises(ValueError, match=r"^--out: directory .*nope' does not exist$"):
        check_output_path(tmp_path / "nope" / "t.csv", (".csv",), "--out")


def test_check_output_path_refuses_a_read_only_directory(readonly_dir):
    with pytest.raises(ValueError, match=r"^--out: directory .*ro' is (on a read-only file system|not writable)"):
        check_output_path(readonly_dir / "t.nc", (".nc",), "--out")


# -- every writer -----------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["t.csv", "t.nc"])
def test_trajectory_on_a_full_disk_leaves_no_file(traj, full_dir, name):
    with pytest.raises(OutputError, match=rf"^out: cannot write '.*{name}': no space left on device$"):
        write_trajectory(traj, full_dir / name)
    assert entries(full_dir) == []


@pytest.mark.parametrize("name, writer", [("t.csv", "numpy.savetxt"), ("t.nc", "xarray.Dataset.to_netcdf")])
def test_trajectory_writer_failing_half_way_leaves_no_file(traj, tmp_path, monkeypatch, name, writer):
    monkeypatch.setattr(writer, half_then_fail(ENOSPC))
    with pytest.raises(OutputError, match=rf"^--out: cannot write .*{name}': no space left on device$"):
        write_trajectory(traj, tmp_path / name, name="--out")
    assert entries(tmp_path) == []


def test_a_netcdf_library_failure_is_reported_and_leaves_no_file(traj, tmp_path, monkeypatch):
    monkeypatch.setattr("xarray.Dataset.to_netcdf", half_then_fail(RuntimeError("NetCDF: HDF error")))
    with pytest.raises(OutputError, match=r"^out: cannot write .*NetCDF: HDF error$"):
        write_trajectory(traj, tmp_path / "t.nc")
    assert entries(tmp_path) == []


def test_trajectory_into_a_read_only_directory_is_refused(traj, readonly_dir):
    with pytest.raises(ValueError, match=r"^out: directory .*ro'"):
        write_trajectory(traj, readonly_dir / "t.csv")


@pytest.mark.parametrize("suffix", [".png", ".pdf", ".svg"])
def test_a_figure_on_a_full_disk_leaves_no_file_and_is_closed(full_dir, suffix):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.imshow(np.random.default_rng(0).random((600, 600)))  # noise: far more than 64 KiB in any format
    with pytest.raises(OutputError, match=r"^--plot: cannot write .*: no space left on device$"):
        write_figure(fig, full_dir / f"f{suffix}", "--plot")
    assert entries(full_dir) == [] and not plt.fignum_exists(fig.number)


def test_every_plot_function_saves_through_the_atomic_writer(traj, tmp_path, monkeypatch):
    from frictionflow import analyze
    from frictionflow.plotting import plot_run

    monkeypatch.setattr("matplotlib.figure.Figure.savefig", half_then_fail(ENOSPC))
    with pytest.raises(OutputError, match=r"^--plot: cannot write .*run\.png'"):
        plot_run(analyze(traj), tmp_path / "run.png", name="--plot")
    assert entries(tmp_path) == []


def test_paper_data_and_figures_failing_half_way_leave_nothing(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from frictionflow.paper.export import save_figure, write_dataset

    ds = xr.Dataset({"X": ("tau", np.arange(3.0)), "TR_B": ((), 1.0)}, coords={"tau": np.arange(3.0)})
    monkeypatch.setattr("pandas.DataFrame.to_csv", half_then_fail(ENOSPC))
    with pytest.raises(OutputError, match=r"^out: cannot write .*fig2\.csv'"):
        write_dataset(ds, tmp_path, "fig2")
    assert entries(tmp_path) == ["fig2.nc"]  # complete, written before the CSV failed
    monkeypatch.setattr("matplotlib.figure.Figure.savefig", half_then_fail(ENOSPC))
    fig, _ = plt.subplots()
    with pytest.raises(OutputError, match=r"^out: cannot write .*fig3\.png'"):
        save_figure(fig, tmp_path, "fig3")
    assert entries(tmp_path) == ["fig2.nc"] and not plt.fignum_exists(fig.number)


# -- reproduce's output directory -------------------------------------------------------------------

def test_reproduce_refuses_an_unwritable_output_before_any_work(tmp_path, readonly_dir):
    from frictionflow.paper.pipeline import check_out_dir

    (tmp_path / "file").write_text("")
    with pytest.raises(ValueError, match=r"^out: .*file' is a file, not a directory$"):
        check_out_dir(tmp_path / "file" / "out")
    (tmp_path / "out" / "report.html").mkdir(parents=True)
    with pytest.raises(ValueError, match=r"^out: .*report\.html' is a directory$"):
        check_out_dir(tmp_path / "out")
    with pytest.raises(ValueError, match=r"^out: directory .*ro' is"):
        check_out_dir(readonly_dir / "out")


# -- the sweep's final NetCDF -----------------------------------------------------------------------

SWEEP = {"friction": "coulomb", "fs": 0.04, "t_end": 50.0, "grid": {"zeta": [0.0, 0.1], "vb": [0.01, 0.02]}}


def test_a_failing_sweep_conversion_leaves_no_netcdf_and_the_rerun_cleans_up(tmp_path, monkeypatch):
    from frictionflow.sweep import run_sweep

    out = tmp_path / "r.nc"
    original = xr.Dataset.to_netcdf

    def incomplete_then_full(self, path, *args, **kwargs):
        original(self.isel(zeta=[0]), path, *args, **kwargs)  # a file that would open as if valid
        raise ENOSPC

    with monkeypatch.context() as m:
        m.setattr(xr.Dataset, "to_netcdf", incomplete_then_full)
        with pytest.raises(OutputError, match=r"^out: cannot write .*r\.nc': no space left on device; every chunk is kept in .*r\.nc\.partial\.zarr.: run the same command again to convert it$"):
            run_sweep(SWEEP, out, chunk_size=2)
    assert entries(tmp_path) == ["r.nc.partial.zarr"]  # the journal only: no r.nc, no temporary
    # what a conversion killed outright leaves: its temporary (and, before, r.nc.tmp)
    for p in (temporary_path(out, secrets.token_hex(4)), tmp_path / "r.nc.tmp"):
        p.write_bytes(b"half a NetCDF file")
    ds = run_sweep(SWEEP, out, chunk_size=2)  # the journal is converted again
    assert ds.sizes == {"zeta": 2, "vb": 2} and not np.isnan(ds["TR_B"].values).any()
    ds.close()
    assert entries(tmp_path) == ["r.nc"]
