"""``frictionflow sweep FILE --out r.nc|r.zarr`` with a model sweep file: the summary, SIGKILL and resume, --verify,
bad grids refused in one line with exit code 2 and nothing written.  The SIGKILL test runs the command in its own
processes; the others call the entry point in this one (``in_process``: the same exit codes and output)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr
import zarr

from frictionflow.analysis.structure import STRUCTURE_KINDS, analyze_structure
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import load_system
from tests.structure.test_structure_sweep import SWEEP, TWO

from .processes import SRC, in_process, one_line


@pytest.fixture()
def files(tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "two.toml").write_text(TWO)
    (tmp_path / "s.toml").write_text(SWEEP.replace('"two.toml"', '"models/two.toml"'))
    return tmp_path


@pytest.mark.parametrize("ext", [".nc", ".zarr"])
def test_sweep_over_model_entries(files, ext):
    out = files / f"r{ext}"
    code, stdout, err, _ = in_process("sweep", str(files / "s.toml"), "--out", str(out), "--json", cwd=files)
    assert code == 0, err
    summary = json.loads(stdout)
    assert summary["dims"]["contact.0.belt"] == 2 and summary["dims"]["spring.2.k"] == 2 and summary["points"] == 4
    assert set(summary["kinds"]) == set(STRUCTURE_KINDS) and sum(summary["kinds"].values()) == 4
    ds = xr.open_dataset(out, engine="zarr" if ext == ".zarr" else None).load()
    system = load_system(files / "models" / "two.toml").with_entry("contact.0.belt", 0.01).with_entry("spring.2.k", 0.6)
    a = analyze_structure(simulate_system(system, 150.0))
    point = ds.sel({"contact.0.belt": 0.01, "spring.2.k": 0.6})
    assert STRUCTURE_KINDS[int(point["kind"])] == a.steady_state.kind
    assert float(point["P_heat"].sel(contact="contact.1")) == a.elements["contact.1"]["P_heat"]
    assert float(point["P"].sel(element="spring.2")) == a.elements["spring.2"]["P"]
    code, stdout, err, _ = in_process("sweep", "--verify", str(out))
    assert code == 0 and "intact: 1 of 1 chunks verified (complete)" in stdout, (stdout, err)  # 8 points a chunk


def test_sigkill_and_resume_gives_the_uninterrupted_dataset(files):
    out = files / "k.zarr"
    cmd = [sys.executable, "-m", "frictionflow", "sweep", str(files / "s.toml"), "--out", str(out), "--chunk-size", "1"]
    env = dict(os.environ, PYTHONPATH=SRC)
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    deadline, done = time.time() + 240, 0
    while time.time() < deadline and proc.poll() is None:
        try:
            done = int(np.count_nonzero(zarr.open_group(str(out), mode="r")["_sweep/chunks_done"][:]))
        except Exception:
            done = 0
        if done >= 1:
            break
        time.sleep(0.01)
    assert proc.poll() is None, "the sweep finished before it could be killed"
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert 0 < done < 4
    again = subprocess.run(cmd, capture_output=True, text=True, check=False, env=env)
    assert again.returncode == 0, again.stderr
    resumed = xr.open_zarr(out, consolidated=False).load()
    code, _, err, _ = in_process("sweep", str(files / "s.toml"), "--out", str(files / "fresh.zarr"), "--chunk-size", "1")
    assert code == 0, err
    fresh = xr.open_zarr(files / "fresh.zarr", consolidated=False).load()
    for name in fresh.data_vars:
        np.testing.assert_array_equal(resumed[name].values, fresh[name].values, err_msg=name)
    assert int((resumed["kind"] < 0).sum()) == 0


@pytest.mark.parametrize("line, words", [
    ('"contact.0.blet" = [0.1, 0.2]', ["unknown grid key 'contact.0.blet'", "contact.0.belt"]),
    ('"spring.1.k" = [0.5, -1.0]', ["grid.spring.1.k[1]", "spring.1.k"]),
    ('zeta = [0.1, 0.2]', ["unknown grid key 'zeta'"]),
])
def test_bad_grid_one_line_exit_2_nothing_written(files, line, words):
    bad = files / "bad.toml"
    bad.write_text(f'model = "models/two.toml"\nt_end = 50.0\n[grid]\n{line}\n')
    before = sorted(p.name for p in files.iterdir())
    code, _, err, _ = in_process("sweep", str(bad), "--out", str(files / "r.nc"))
    assert code == 2
    one_line(err, *words)
    assert sorted(p.name for p in files.iterdir()) == before


def test_bad_settings_and_model_path(files):
    bad = files / "bad.toml"
    bad.write_text('model = "models/none.toml"\n[grid]\n"spring.0.k" = [1.0, 2.0]\n')
    code, _, err, _ = in_process("sweep", str(bad), "--out", str(files / "r.nc"))
    assert code == 2
    one_line(err, "model", "none.toml", "is not a file")
    bad.write_text('model = "models/two.toml"\nfd = 0.1\n[grid]\n"spring.0.k" = [1.0, 2.0]\n')
    code, _, err, _ = in_process("sweep", str(bad), "--out", str(files / "r.nc"))
    assert code == 2
    one_line(err, "'fd' is not used by a model sweep")
    assert not (files / "r.nc").exists()


def test_summary_line_names_the_grid(files):
    code, stdout, err, _ = in_process("sweep", str(files / "s.toml"), "--out", str(files / "r.zarr"))
    assert code == 0, err
    assert stdout.startswith(f"4 points (contact.0.belt=2 x spring.2.k=2) -> {files / 'r.zarr'}: periodic "), stdout
