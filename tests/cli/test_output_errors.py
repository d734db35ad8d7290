"""Paths the CLI cannot write or read: one line naming the option and the path, exit 2, nothing written.

A good path on a full disk is not bad input: the same one line, exit 1 (the README's exit codes).

Every path is checked before any work: the commands' computations are
replaced by a tripwire, so a test fails if a bad path is found only after
computing.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from frictionflow.cli import main
from tests.cli.processes import SRC
from tests.test_atomic_output import full_dir, readonly_dir  # noqa: F401  (fixtures)

FAST = ["--solver", "rk4", "--dt", "0.01", "--t-end", "20"]  # well over 64 KiB of CSV or NetCDF
COULOMB = ["--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--vb", "0.01"]
CONTINUE = ["continue", *COULOMB, "--param", "zeta", "--from", "0.01", "--to", "0.05"]


def run(capsys, *argv: str) -> tuple[int, str]:
    code = main(list(argv))
    return code, capsys.readouterr().err


def assert_refused(code: int, err: str, option: str, path: Path | str, *words: str, expect: int = 2) -> None:
    """Exit ``expect`` (2: bad input) and one line ``error: OPTION: ...`` naming the path (and ``words``), no traceback."""
    assert code == expect, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {option}"), err
    assert repr(str(path))[1:-1] in lines[0] and all(w in lines[0] for w in words), err


#: every command's computation, where the command looks it up when it runs (its own module)
WORK = ("frictionflow.cli.simulate.run_simulation", "frictionflow.cli.orbit.find_orbit",
        "frictionflow.cli.orbit.continuation", "frictionflow.paper.pipeline.compute_jobs")


def tripwire(*args, **kwargs):
    raise AssertionError("computed before refusing a bad path")


def trip_every_command(monkeypatch) -> None:
    """Replace each of :data:`WORK` by a tripwire, in the module that uses it: a module first imported now (and
    binding names from another) keeps nothing of it once ``monkeypatch`` is undone."""
    for target in WORK:
        monkeypatch.setattr(target, tripwire)


@pytest.fixture
def no_work(monkeypatch):
    """Make every command's computation fail the test if it is reached."""
    trip_every_command(monkeypatch)


@pytest.fixture
def cwd(tmp_path, monkeypatch):
    """Work in an empty directory, with a directory ``adir.png``, a file ``afile`` and a config ``c.toml``."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "adir.png").mkdir()
    (tmp_path / "afile").write_text("")
    (tmp_path / "c.toml").write_text("zeta = 0.05\n")
    return tmp_path


BEFORE = ["adir.png", "afile", "c.toml"]


def listing(d: Path) -> list[str]:
    return sorted(p.name for p in d.iterdir())


# -- simulate --------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["t.csv", "t.nc"])
def test_simulate_into_a_read_only_directory(capsys, no_work, readonly_dir, name):
    path = readonly_dir / name
    assert_refused(*run(capsys, "simulate", *FAST, "--out", str(path)), "--out", readonly_dir)
    assert listing(readonly_dir) == []


@pytest.mark.parametrize("args, option, path, words", [
    (["--out", "adir.png"], "--out", "adir.png", ["must end in"]),  # a directory with the wrong extension
    (["--out", "adir.csv"], "--out", "adir.csv", ["is a directory"]),
    (["--out", "afile/t.csv"], "--out", "afile", ["is a file, not a directory"]),
    (["--out", "no/t.nc"], "--out", "no", ["does not exist"]),
    (["--out", "a" * 300 + ".csv"], "--out", "a" * 300 + ".csv", ["too long"]),
    (["--plot", "adir.png"], "--plot", "adir.png", ["is a directory"]),
    (["--plot", "afile/f.svg"], "--plot", "afile", ["is a file, not a directory"]),
    (["--plot", "b" * 300 + ".pdf"], "--plot", "b" * 300 + ".pdf", ["too long"]),
    (["--config", "adir.png"], "--config", "adir.png", ["is a directory"]),
    (["--config", "afile/c.toml"], "--config", "afile", ["is a file, not a directory"]),
    (["--config", "c" * 300 + ".toml"], "--config", "c" * 300 + ".toml", ["too long"]),
])
def test_simulate_refuses_a_bad_path_before_any_work(capsys, cwd, no_work, args, option, path, words):
    if path == "adir.csv":
        (cwd / "adir.csv").mkdir()
    before = listing(cwd)
    assert_refused(*run(capsys, "simulate", *FAST, *args), option, path, *words)
    assert listing(cwd) == before


def test_simulate_with_a_good_out_and_a_bad_plot_writes_nothing(capsys, cwd, no_work):
    code, err = run(capsys, "simulate", *FAST, "--out", "t.csv", "--plot", "adir.png")
    assert_refused(code, err, "--plot", "adir.png", "is a directory")
    assert listing(cwd) == BEFORE  # no t.csv


@pytest.mark.parametrize("name", ["t.csv", "t.nc"])
def test_simulate_on_a_full_disk_leaves_no_file(capsys, full_dir, name):
    """A disk already too small for the estimated output: refused before any work (exit 2); one that fills while
    the file is written is exit 1 (the test below and tests/cli/test_faults_io.py)."""
    path = full_dir / name
    assert_refused(*run(capsys, "simulate", *FAST, "--out", str(path)), "--out", path, "no space left on device", expect=2)
    assert listing(full_dir) == []


@pytest.mark.parametrize("name, writer", [("t.csv", "numpy.savetxt"), ("t.nc", "xarray.Dataset.to_netcdf")])
def test_simulate_when_the_writer_fails_half_way_leaves_no_file(capsys, tmp_path, monkeypatch, name, writer):
    from tests.test_atomic_output import ENOSPC, half_then_fail

    monkeypatch.setattr(writer, half_then_fail(ENOSPC))
    path = tmp_path / name
    assert_refused(*run(capsys, "simulate", *FAST, "--out", str(path)), "--out", path, "no space left on device", expect=1)
    assert listing(tmp_path) == []


def test_simulate_plot_on_a_full_disk_leaves_no_file(capsys, full_dir):
    path = full_dir / "f.svg"  # the time history alone is far over 64 KiB as SVG
    assert_refused(*run(capsys, "simulate", *FAST, "--plot", str(path)), "--plot", path, "no space left on device", expect=1)
    assert listing(full_dir) == []


# -- orbit and continue ------------------------------------------------------------------------------

@pytest.mark.parametrize("command", [["orbit", *COULOMB], CONTINUE], ids=["orbit", "continue"])
@pytest.mark.parametrize("args, option, path, words", [
    (["--plot", "adir.png"], "--plot", "adir.png", ["is a directory"]),
    (["--plot", "afile/f.png"], "--plot", "afile", ["is a file, not a directory"]),
    (["--plot", "p" * 300 + ".png"], "--plot", "p" * 300 + ".png", ["too long"]),
    (["--config", "adir.png"], "--config", "adir.png", ["is a directory"]),
    (["--config", "afile/c.toml"], "--config", "afile", ["is a file, not a directory"]),
])
def test_orbit_and_continue_refuse_a_bad_path_before_any_work(capsys, cwd, no_work, command, args, option, path, words):
    assert_refused(*run(capsys, *command, *args), option, path, *words)
    assert listing(cwd) == BEFORE


@pytest.mark.parametrize("command", [["orbit", *COULOMB], CONTINUE], ids=["orbit", "continue"])
def test_orbit_and_continue_refuse_a_read_only_directory_before_any_work(capsys, no_work, readonly_dir, command):
    assert_refused(*run(capsys, *command, "--plot", str(readonly_dir / "f.png")), "--plot", readonly_dir)


# -- reproduce ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("out, path, words", [
    ("afile/out", "afile", ["is a file, not a directory"]),
    ("out", "report.html", ["is a directory"]),
    ("r" * 300, "r" * 300, ["too long"]),
])
def test_reproduce_refuses_an_output_it_cannot_write_before_any_work(capsys, cwd, no_work, out, path, words):
    if path == "report.html":
        (cwd / "out" / "report.html").mkdir(parents=True)
    assert_refused(*run(capsys, "reproduce", "--out", out, "--quick"), "--out", path, *words)


def test_reproduce_into_a_read_only_directory(capsys, no_work, readonly_dir):
    assert_refused(*run(capsys, "reproduce", "--out", str(readonly_dir / "out"), "--quick"), "--out", readonly_dir)
    assert listing(readonly_dir) == []


def test_reproduce_on_a_full_disk_fails_in_one_line_and_leaves_no_partial_file(capsys, full_dir):
    out = full_dir / "out"
    code, err = run(capsys, "reproduce", "--out", str(out), "--quick", "--workers", "1")
    assert_refused(code, err, "--out", out, "no space left on device", expect=1)
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]  # no temporary left either


@pytest.mark.parametrize("name", ["claims.json", "report.html"])
def test_reproduce_failing_to_write_claims_or_report_leaves_no_such_file(capsys, tmp_path, monkeypatch, name):
    from tests.test_atomic_output import ENOSPC

    original = Path.write_text

    def fails_for_name(self, *args, **kwargs):
        if self.suffix != Path(name).suffix:
            return original(self, *args, **kwargs)
        original(self, "partial")
        raise ENOSPC

    monkeypatch.setattr(Path, "write_text", fails_for_name)
    out = tmp_path / "out"
    code, err = run(capsys, "reproduce", "--out", str(out), "--quick", "--workers", "1")
    assert_refused(code, err, "--out", out / name, "no space left on device", expect=1)
    written = listing(out)
    assert name not in written and not [n for n in written if n.startswith(".")]


def test_the_tripwires_leave_nothing_behind_when_the_commands_are_first_imported_under_them():
    """A command module first imported while the tripwires are in place, as a test in a random order may, runs its
    real computation once they are undone (a tripwire on ``frictionflow.orbits`` would stay in ``cli.orbit``)."""
    script = """
import sys
from _pytest.monkeypatch import MonkeyPatch
from tests.cli.test_output_errors import WORK, trip_every_command
assert "frictionflow.cli.orbit" not in sys.modules
import importlib
with MonkeyPatch.context() as mp:
    trip_every_command(mp)
    importlib.import_module("frictionflow.cli.orbit")  # as running the command would
from frictionflow import orbits
orbit = importlib.import_module("frictionflow.cli.orbit")
assert orbit.find_orbit is orbits.find_orbit and orbit.continuation is orbits.continuation
for target in WORK:
    module, name = target.rsplit(".", 1)
    assert getattr(importlib.import_module(module), name).__name__ != "tripwire", target
print("ok")
"""
    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([SRC, str(root)]))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=root, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr
