"""run_sweep, repair_sweep and verify_sweep refuse an argument of the wrong type or range in one line naming it,
before anything is created (not an AttributeError from deep inside, nor a truthy string taken for True)."""

from __future__ import annotations

import re

import pytest

from frictionflow.sweep import repair_sweep, run_sweep, verify_sweep

GOOD = {"friction": "coulomb", "fs": 0.04, "t_end": 50.0, "grid": {"vb": [0.01, 0.02]}}
PATH = "a path (str or os.PathLike) ending in .zarr or .nc"
CONFIG = "a SweepConfig, a mapping as in a sweep's TOML file, or a path to one"


@pytest.mark.parametrize("kwargs, error, message", [
    ({"client": object()}, TypeError, "client must be a dask.distributed Client or None, got object"),
    ({"restart": "yes"}, TypeError, "restart must be True or False, got str"),
    ({"restart": 1}, TypeError, "restart must be True or False, got int"),
    ({"progress": "no"}, TypeError, "progress must be True or False, got str"),
    ({"scheduler": 5}, TypeError, "scheduler must be a Dask scheduler's address (str) or None, got int"),
    ({"lock_stale_after": -1}, ValueError, "lock_stale_after must be a number of seconds > 0, got -1"),
    ({"lock_stale_after": "600"}, ValueError, "lock_stale_after must be a number of seconds > 0, got '600'"),
    ({"scheduler_timeout": True}, ValueError, "scheduler_timeout must be a number of seconds > 0, got True"),
])
def test_a_bad_keyword_argument_is_named_before_anything_is_created(tmp_path, kwargs, error, message):
    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        run_sweep(GOOD, tmp_path / "a.nc", **kwargs)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("config, out, error, message", [
    (5, "a.nc", TypeError, f"config must be {CONFIG}, got int"),
    (None, "a.nc", TypeError, f"config must be {CONFIG}, got NoneType"),
    (GOOD, 5, TypeError, f"out must be {PATH}, got int"),
    (GOOD, None, TypeError, f"out must be {PATH}, got NoneType"),
])
def test_a_bad_config_or_output_is_named(tmp_path, monkeypatch, config, out, error, message):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(error, match=f"^{re.escape(message)}$"):
        run_sweep(config, out)
    assert list(tmp_path.iterdir()) == []


def test_restart_as_a_truthy_string_keeps_an_existing_output(tmp_path):
    out = tmp_path / "a.zarr"
    run_sweep(GOOD, out).close()
    before = sorted(p.relative_to(out) for p in out.rglob("*"))
    with pytest.raises(TypeError, match="^restart must be True or False"):
        run_sweep({**GOOD, "t_end": 60.0}, out, restart="no")  # a truthy string: it discarded the output
    assert sorted(p.relative_to(out) for p in out.rglob("*")) == before


def test_verify_and_repair_name_their_path_argument(tmp_path):
    with pytest.raises(TypeError, match=f"^path must be {re.escape(PATH)}, got int$"):
        verify_sweep(3)
    with pytest.raises(ValueError, match="^path must end in .zarr or .nc, got 's.toml'$"):
        verify_sweep("s.toml")
    with pytest.raises(TypeError, match=f"^out must be {re.escape(PATH)}, got int$"):
        repair_sweep(3)
    with pytest.raises(ValueError, match="^lock_stale_after must be a number of seconds > 0, got 0$"):
        repair_sweep(tmp_path / "a.zarr", lock_stale_after=0)
