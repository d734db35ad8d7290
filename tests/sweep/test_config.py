"""Sweep configs: every bad key or value is refused up front, with the key named."""

import numpy as np
import pytest

from frictionflow.cli import main
from frictionflow.sweep import parse_sweep
from frictionflow.sweep.config import chunk_shape
from frictionflow.sweep.compute import _friction_rows
from frictionflow.core import layout

BASE = {"friction": "coulomb", "fs": 0.04, "grid": {"zeta": [0.0, 0.05]}}


def test_axes_numbers_lists_and_ranges():
    cfg = parse_sweep({
        "friction": "karnopp",
        "grid": {
            "zeta": {"start": 0.0, "stop": 0.1, "num": 5},
            "vb": {"start": 1e-3, "stop": 1e-1, "num": 3, "scale": "log"},
            "fd": [0.01, 0.02],
            "vd": 2e-3,
        },
    })
    assert cfg.dims == ("zeta", "vb", "fd") and cfg.shape == (5, 3, 2) and cfg.size == 30
    assert np.allclose(cfg.axes["vb"], [1e-3, 1e-2, 1e-1])
    assert cfg.fixed == {"vd": 2e-3} and cfg.run.vd == 2e-3


@pytest.mark.parametrize(
    "change, key",
    [
        ({"bogus": 1}, "bogus"),
        ({"grid": {"zeta": [0.0], "speed": [1.0]}}, "speed"),
        ({"grid": {"zeta": []}}, "grid.zeta"),
        ({"grid": {"zeta": {"start": 0, "stop": 1}}}, "num"),
        ({"grid": {"zeta": {"start": 0, "stop": 1, "num": 0}}}, "grid.zeta.num"),
        ({"grid": {"zeta": {"start": 0, "stop": 1, "num": 3, "scale": "log"}}}, "grid.zeta"),
        ({"grid": {"zeta": {"start": 0, "stop": 1, "num": 3, "step": 1}}}, "step"),
        ({"grid": {"zeta": [-0.1, 0.1]}}, "grid.zeta"),
        ({"grid": {"zeta": [0.1, "a"]}}, "grid.zeta[1]"),
        ({"grid": {"fd": [0.01, 0.05]}}, "grid.fd"),  # F_s = 0.04 < 0.05
        ({"grid": {"vb": [0.01, float("nan")]}}, "grid.vb[1]"),
        ({"zeta": 0.1, "grid": {"zeta": [0.0, 0.1]}}, "zeta"),
        ({"grid": {}}, "[grid]"),
        ({"grid": {"zeta": 0.1}}, "[grid]"),
        ({"window": "1:2"}, "window"),
        ({"solver": "euler"}, "solver"),
    ],
)
def test_bad_configs_name_the_key(change, key):
    cfg = {**BASE, **change}
    with pytest.raises(ValueError) as e:
        parse_sweep(cfg)
    assert key in str(e.value)


def test_cli_refuses_a_bad_config_with_exit_2(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text('friction = "coulomb"\n[grid]\nzeta = []\n')
    out = tmp_path / "out.zarr"
    assert main(["sweep", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "grid.zeta" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_chunks_fill_the_last_axes_first():
    assert chunk_shape((10, 20, 30), 600) == (1, 20, 30)
    assert chunk_shape((10, 20, 30), 100) == (1, 3, 30)
    assert chunk_shape((4,), 100) == (4,)


def test_sizes_and_steps_are_checked_up_front(tmp_path):
    from frictionflow.solvers.base import CoarseStepWarning

    base = {"friction": "coulomb", "fs": 0.04, "grid": {"zeta": [0.1, 0.2]}}
    with pytest.raises(ValueError, match=r"t_end=1e\+09 with solver=exact.*max_memory=4 GiB"):
        parse_sweep({**base, "t_end": 1e9})
    with pytest.raises(ValueError, match=r"grid.zeta\[1\]: zeta must be"):
        parse_sweep({"grid": {"zeta": [0.1, True]}})
    with pytest.raises(ValueError, match=r"grid.zeta.num must be an integer"):
        parse_sweep({"grid": {"zeta": {"start": 0.0, "stop": 1.0, "num": "3"}}})
    with pytest.raises(ValueError, match=r"the grid has 2e\+10 points"):
        parse_sweep({"grid": {"zeta": {"start": 0.0, "stop": 0.1, "num": 100_000},
                              "vb": {"start": 0.01, "stop": 0.1, "num": 100_000}, "fd": [0.01, 0.02]}})
    with pytest.warns(CoarseStepWarning, match=r"grid.vb = 0.1: dt=0.5 lets X' jump across the stick band"):
        parse_sweep({"solver": "rk4", "dt": 0.5, "t_end": 50.0, "grid": {"vb": [0.01, 0.1]}})


def test_a_huge_grid_is_never_materialised(tmp_path):
    # issue 10: a 1e5 x 1e5 grid took 3.2 GB before any chunk was written; now memory is O(chunk)
    import tracemalloc

    from frictionflow.sweep.config import chunk_shape
    from frictionflow.sweep.store import SweepStore

    tracemalloc.start()
    cfg = parse_sweep({"friction": "coulomb", "fs": 0.04, "t_end": 10.0,
                       "grid": {"zeta": {"start": 0.0, "stop": 0.1, "num": 100_000},
                                "vb": {"start": 0.001, "stop": 0.1, "num": 100_000}}})
    store = SweepStore(tmp_path / "r.zarr", cfg, chunk_shape(cfg.shape, 4096))
    first = next(iter(store.todo()))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert cfg.size == 10**10 and first == (0, 0)
    assert peak < 64 * 2**20, f"{peak / 2**20:.0f} MiB"


def test_values_beyond_the_model_range_are_refused_in_grids():
    with pytest.raises(ValueError, match=r"grid.vb\[0\]: vb must be finite and in \[-1000, 1000\], got 1e\+300"):
        parse_sweep({"grid": {"vb": [1e300, 0.01]}})


@pytest.mark.parametrize("entry, message", [
    ("abc", 'grid.vb must be a number, a list, a {start, stop, num, scale} table or "FROM:TO:N", got \'abc\''),
    ("0.01:0.02", "grid.vb must be FROM:TO:N, got '0.01:0.02'"),  # a range meant: its own syntax
])
def test_a_grid_entry_text_names_the_forms_it_may_take(entry, message):
    with pytest.raises(ValueError) as err:
        parse_sweep({"friction": "coulomb", "fd": 0.02, "grid": {"vb": entry}})
    assert str(err.value) == message


def test_a_default_that_follows_an_axis_is_not_recorded_as_fixed():
    """Stribeck's F_s defaults to 2 F_d: over an fd axis it differs per point (fd = 0.01 runs with fs = 0.02, as
    simulate --fd 0.01 does), so no ``fixed_fs`` (it said 0.04, the base point's)."""
    over_fd = parse_sweep({"friction": "stribeck", "t_end": 100.0, "grid": {"fd": [0.02, 0.01], "zeta": [0.1]}})
    attrs = over_fd.attributes()
    assert "fixed_fs" not in attrs and attrs["fixed_vs"] == 0.01
    _, law, _ = over_fd.run.build()
    rows = _friction_rows(over_fd, law, over_fd.point_params((np.array([0, 1]), np.array([0, 0]))))
    assert rows[:, layout.FS].tolist() == [0.04, 0.02]  # what the points ran with
    fixed_fd = parse_sweep({"friction": "stribeck", "fd": 0.02, "t_end": 100.0, "grid": {"zeta": [0.1, 0.2]}})
    assert fixed_fd.attributes()["fixed_fs"] == 0.04
    given = parse_sweep({"friction": "stribeck", "fs": 0.05, "t_end": 100.0, "grid": {"fd": [0.02, 0.01]}})
    assert given.attributes()["fixed_fs"] == 0.05


@pytest.mark.parametrize("axis", ["0.1:0.2:1", {"start": 0.1, "stop": 0.2, "num": 1}], ids=["text", "table"])
def test_a_one_value_range_with_two_ends_is_refused(axis):
    # linspace(0.1, 0.2, 1) is [0.1]: the stop would be dropped without a word
    with pytest.raises(ValueError, match=r"grid.vb: num = 1 holds one value, but start 0.1 and stop 0.2 differ"):
        parse_sweep({"grid": {"vb": axis}})
    assert parse_sweep({"grid": {"vb": {"start": 0.1, "stop": 0.1, "num": 1}}}).axes["vb"].tolist() == [0.1]


def test_an_axis_holds_the_decimals_its_range_implies_as_stability_s_scan_does():
    # "0.6:0.7:3": linspace gives 0.6499999999999999
    assert parse_sweep({"grid": {"vb": "0.6:0.7:3"}}).axes["vb"].tolist() == [0.6, 0.65, 0.7]
    assert parse_sweep({"grid": {"vb": {"start": 0.6, "stop": 0.7, "num": 3}}}).axes["vb"].tolist() == [0.6, 0.65, 0.7]
