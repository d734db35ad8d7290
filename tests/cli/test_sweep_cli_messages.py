"""``frictionflow sweep``'s one-line refusals name its options (not the API's arguments), give advice the command
takes, and an interrupted sweep speaks of a store only when there is one."""

from __future__ import annotations

import pytest

from frictionflow.cli import sweep as sweep_cli

from .processes import in_process, one_line

TOML = 'friction = "coulomb"\nfd = 0.02\nfs = 0.04\nt_end = 50.0\n[grid]\nvb = [0.01, 0.02]\n'


@pytest.fixture
def config(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(TOML)
    return path


def test_an_interrupted_sweep_speaks_of_a_store_only_when_there_is_one(monkeypatch, tmp_path, config):
    def stop(*args, **kwargs):  # Ctrl-C during the start-up (a model sweep's probe run): nothing written yet
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep_cli, "run_sweep", stop)
    out = tmp_path / "r.nc"
    code, stdout, err, _ = in_process("sweep", str(config), "--out", str(out))
    assert code == 1 and stdout == ""
    line = one_line(err, f"interrupted (Ctrl-C or SIGTERM) before anything was written to {out}")
    assert "keeps" not in line and "resume" not in line
    (tmp_path / "r.nc.partial.zarr").mkdir()  # a .nc is written in its journal until the end
    code, _, err, _ = in_process("sweep", str(config), "--out", str(out))
    assert code == 1
    one_line(err, f"interrupted: {out} keeps the chunks finished so far; run the same command to resume")


def test_a_bad_chunk_size_names_the_option(tmp_path, config):
    code, out, err, _ = in_process("sweep", str(config), "--out", str(tmp_path / "r.zarr"), "--chunk-size", "0")
    assert code == 2 and out == ""
    one_line(err, "--chunk-size must be an integer and in [1, 1e+07], got 0")
    assert not (tmp_path / "r.zarr").exists()


@pytest.mark.parametrize("repair", [[], ["--repair"]])
def test_verify_names_its_option(config, repair):
    code, out, err, _ = in_process("sweep", "--verify", str(config), *repair)
    assert code == 2 and out == ""
    one_line(err, f"--verify must end in .zarr or .nc, got {str(config)!r}")


def test_verify_of_what_is_not_a_sweep_gives_advice_verify_takes(tmp_path):
    empty = tmp_path / "notsweep.zarr"
    empty.mkdir()
    code, out, err, _ = in_process("sweep", "--verify", str(empty))
    assert code == 2 and out == ""
    line = one_line(err, f"--verify: {str(empty)!r} exists and is not a Zarr store; nothing to verify: give the .zarr "
                         "or .nc a sweep wrote")
    assert "--restart" not in line
    code, _, err, _ = in_process("sweep", "--verify", str(tmp_path / "missing.nc"))
    assert code == 2
    one_line(err, f"--verify: {str(tmp_path / 'missing.nc')!r} does not exist")
