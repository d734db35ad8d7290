"""Defects of ``basins`` found by QA: outcomes that were counted nowhere, a map that could not be drawn, one RK4
orbit split in three, store and output paths refused late (or not at all) or under the wrong name, a misleading
interruption message, a zero tolerance."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from frictionflow.basins import Tolerances, basins
from frictionflow.basins.labels import OUTCOMES, find_attractors, label_attractors, resolution
from frictionflow.cli import main
from frictionflow.solvers import RK4, Adaptive, Exact

#: a forced Coulomb oscillator whose every point is chaotic (QA's case)
CHAOS = ["basins", "--friction", "coulomb", "--fex", "0.5", "--omega", "1", "--zeta", "0.01", "--vb", "0.1", "--fd", "0.5",
         "--fs", "1.0", "--t-end", "1000"]
#: a cheap unforced Karnopp case (two points) for the path checks
CHEAP = ["basins", "--fd", "0.02", "--fs", "0.04", "--zeta", "0.05", "--vb", "0.01", "--t-end", "50",
         "--x0-range=-0.1:0.1:2", "--v0-range=-0.1:-0.1:1"]
_KINDS = ("periodic", "equilibrium", "not_settled", "diverged", "quasi_periodic", "chaotic")


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: "), err
    return err[0]


@pytest.fixture
def no_compute(monkeypatch):
    """Any chunk computed fails the test: what is refused must be refused before the sweep."""
    from frictionflow.sweep import runner

    def compute(*args):
        raise AssertionError("a chunk was computed")

    monkeypatch.setattr(runner, "compute_chunk", compute)


# -- 1. every point has exactly one outcome ----------------------------------------------------------

def _dataset(kinds: list[int]) -> xr.Dataset:
    """A finished sweep over a sample: one stick-slip orbit for the periodic points, NaN elsewhere."""
    n = len(kinds)
    kind = np.asarray(kinds, dtype=np.int8)
    per = kind == 0
    return xr.Dataset({"kind": ("sample", kind),
                       "period": ("sample", np.where(per, 6.29, np.nan)),
                       "X_min": ("sample", np.where(per, -0.1, np.nan)),
                       "X_max": ("sample", np.where(per, 0.14, np.nan)),
                       "stick_fraction": ("sample", np.where(per, 0.04, np.nan))}, coords={"sample": np.arange(n)})


def test_chaotic_and_quasi_periodic_points_are_outcomes_of_their_own():
    kinds = [0, 0, 0, 2, 3, 4, 4, 5, 5, 5]
    ds, found = label_attractors(_dataset(kinds), None, Tolerances())
    names = ds["outcome"].attrs["flag_meanings"].split()
    assert names == ["stick_slip_cycle", "not_settled", "diverged", "quasi_periodic", "chaotic"]
    assert ds["outcome"].values.tolist() == [0, -1, -2, -3, -4]
    count = dict(zip(names, ds["basin_count"].values.tolist()))
    assert count == {"stick_slip_cycle": 3, "not_settled": 1, "diverged": 1, "quasi_periodic": 2, "chaotic": 3}
    assert float(ds["basin_stability"].sum()) == pytest.approx(1.0, abs=1e-12)
    label = ds["label"].values
    assert (label[np.asarray(kinds) == 5] == -4).all() and (label[np.asarray(kinds) == 4] == -3).all()
    assert OUTCOMES[-3] == "quasi_periodic" and OUTCOMES[-4] == "chaotic"


def test_a_periodic_point_without_values_is_counted_as_not_settled():
    """Labelled not settled (it cannot be told apart) and counted there: the fractions still add up to 1."""
    ds = _dataset([0, 0, 1])
    ds["period"][1] = np.nan
    ds["X_min"][2] = np.nan  # an equilibrium without a position
    out, _ = label_attractors(ds, None, Tolerances())
    count = dict(zip(out["outcome"].attrs["flag_meanings"].split(), out["basin_count"].values.tolist()))
    assert count["not_settled"] == 2 and count["stick_slip_cycle"] == 1
    assert int(out["basin_count"].sum()) == 3


# -- 1 and 2 on the command line: QA's chaotic case, with the map -------------------------------------

def test_cli_chaotic_case_counts_every_point_and_draws_the_map(tmp_path, capsys):
    out, fig = tmp_path / "chaos.nc", tmp_path / "chaos.png"
    code = main([*CHAOS, "--x0-range=-1:1:2", "--v0-range=-1:-1:1", "--out", str(out), "--plot", str(fig), "--json"])
    assert code == 0, capsys.readouterr().err
    report = json.loads(capsys.readouterr().out)
    assert sum(o["count"] for o in report["outcomes"]) == 2
    assert sum(o["fraction"] for o in report["outcomes"]) == pytest.approx(1.0, abs=1e-12)
    with xr.open_dataset(out) as ds:
        kinds = ds["kind"].values.ravel()
        expected = {name: int(np.count_nonzero(kinds == i)) for i, name in enumerate(_KINDS)}
        labels = ds["label"].values.ravel()
    counts = {o["name"]: o["count"] for o in report["outcomes"]}
    for name in ("quasi_periodic", "chaotic"):
        assert counts[name] == expected[name]
    assert (labels < 0).all() == (expected["periodic"] + expected["equilibrium"] == 0)
    assert fig.read_bytes()[:4] == b"\x89PNG"


# -- 3. no tolerance finer than the solver resolves ------------------------------------------------

def test_the_resolution_follows_the_solver_and_its_settings():
    assert resolution(RK4()) == pytest.approx(1e-2)  # 10 dt
    assert resolution(RK4(dt=1e-4)) == pytest.approx(1e-3)
    assert resolution(Adaptive()) == pytest.approx(1e-7)  # 10 x its steady_rtol
    assert resolution(Exact()) == pytest.approx(1e-9)
    assert resolution(Adaptive(), rtol=1e-4) == pytest.approx(1e-3)  # the run's own rtol
    assert resolution(RK4(dt=1.0)) == 0.5  # capped


def test_rk4_finds_one_stick_slip_cycle_where_it_found_three():
    """QA's case: RK4's points of one cycle spread by ~3e-3 in period and amplitude; the default solver finds one."""
    b = basins(fd=0.02, fs=0.04, zeta=0.05, vb=0.01, t_end=300.0, solver="rk4", x0=(-0.1, 0.1, 3), v0=(-0.1, 0.1, 2))
    assert list(b.codes) == ["stick_slip_cycle"]
    assert b.tolerances.resolution == pytest.approx(1e-2) and b.dataset.attrs["label_tol_resolution"] == pytest.approx(1e-2)
    assert b.fractions["stick_slip_cycle"] == 1.0
    period = b.dataset["period"].values
    assert np.ptp(period) / np.median(period) > 1e-3  # what the default tolerance alone split


def test_at_rk4_resolution_distinct_orbits_stay_apart():
    """One orbit's points with RK4's spread (3e-3) stay one attractor; orbits 5 % apart, and a slip cycle beside a
    stick-slip cycle, stay separate."""
    rng = np.random.default_rng(3)
    n = 40
    base = np.array([8.0, 0.04, 0.49])  # period, amplitude, stick fraction (QA's orbit)
    rows = np.tile(base, (n, 1)) * (1 + 1.5e-3 * rng.uniform(-1, 1, (n, 3)))
    rows[20:30, :2] *= 1.05  # another stick-slip cycle, 5 % longer and wider
    rows[30:, 2] = 0.0  # a slip cycle
    q = {"kind": np.zeros(n), "period": rows[:, 0], "X_min": -rows[:, 1] / 2, "X_max": rows[:, 1] / 2, "stick_fraction": rows[:, 2]}
    tol = Tolerances(resolution=resolution(RK4()))
    found = find_attractors(q, tol)
    assert sorted(len(a.members) for a in found) == [10, 10, 20]
    assert sorted(a.name for a in found) == ["slip_cycle", "stick_slip_cycle", "stick_slip_cycle_2"]
    # two points of one RK4 orbit 3e-3 apart (QA's spread): the default tolerance alone splits them
    two = {k: v[:2].copy() for k, v in q.items()}
    two["period"][1] = two["period"][0] * (1 + 3e-3)
    assert len(find_attractors(two, Tolerances())) == 2 and len(find_attractors(two, tol)) == 1


def test_the_bistable_stribeck_case_keeps_both_attractors_at_the_default_solver_resolution():
    x_star = 0.02 + 0.02 * math.exp(-0.12 / 0.05)
    b = basins(friction="stribeck", fd=0.02, fs=0.04, vs=0.05, delta=1.0, zeta=0.03, vb=0.12, t_end=300.0,
               x0=(x_star - 0.3, x_star + 0.3), v0=(-0.3, 0.3), sample=60, seed=1)
    assert set(b.codes) == {"equilibrium", "stick_slip_cycle"}
    assert b.tolerances.resolution == pytest.approx(resolution(Adaptive()))


# -- 5. the store's problems name --store ----------------------------------------------------------

@pytest.mark.parametrize("make, store, words", [
    (lambda d: None, "nodir/s.zarr", "--store: directory 'nodir' does not exist"),
    (lambda d: (d / "afile").write_text(""), "afile/s.zarr", "--store: 'afile' is a file, not a directory"),
    (lambda d: ((d / "plain.zarr").mkdir(), (d / "plain.zarr" / "notes.txt").write_text("x")), "plain.zarr",
     "--store: 'plain.zarr' exists and is not a Zarr store"),
    (lambda d: None, "s.txt", "--store must end in .zarr"),
])
def test_store_problems_name_the_store_option(make, store, words, tmp_path, monkeypatch, capsys, no_compute):
    monkeypatch.chdir(tmp_path)
    make(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    assert main([*CHEAP, "--store", store]) == 2
    assert words in _one_line(capsys)
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_a_stale_store_names_the_store_option(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main([*CHEAP, "--store", "s.zarr"]) == 0
    capsys.readouterr()
    other = [a if a != "0.01" else "0.02" for a in CHEAP]  # another V_b: another sweep
    assert main([*other, "--store", "s.zarr"]) == 2
    assert _one_line(capsys).startswith("error: --store: 's.zarr' holds a different sweep")


# -- 6, 7, 8. outputs refused before anything is computed or written --------------------------------

def test_out_that_is_an_existing_directory_is_refused_before_the_sweep(tmp_path, monkeypatch, capsys, no_compute):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "d.nc").mkdir()
    assert main([*CHEAP, "--out", "d.nc"]) == 2
    assert "--out: 'd.nc' is a directory" in _one_line(capsys)
    assert [p.name for p in tmp_path.iterdir()] == ["d.nc"] and not any((tmp_path / "d.nc").iterdir())


def test_out_zarr_does_not_replace_a_directory_that_is_not_a_zarr_store(tmp_path, monkeypatch, capsys, no_compute):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out2.zarr").mkdir()
    (tmp_path / "out2.zarr" / "notes.txt").write_text("precious")
    assert main([*CHEAP, "--out", "out2.zarr"]) == 2
    assert "--out: 'out2.zarr' exists and is not a Zarr store" in _one_line(capsys)
    assert (tmp_path / "out2.zarr" / "notes.txt").read_text() == "precious"
    assert [p.name for p in tmp_path.iterdir()] == ["out2.zarr"]
    with pytest.raises(ValueError, match="out: .* exists and is not a Zarr store"):  # the API alike
        basins(fd=0.02, fs=0.04, zeta=0.05, vb=0.01, t_end=50.0, x0=(-0.1, 0.1, 2), v0=(-0.1, -0.1, 1), out=tmp_path / "out2.zarr")


def test_out_zarr_still_replaces_a_previous_output(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main([*CHEAP, "--out", "b.zarr", "--json"]) == 0
    assert main([*CHEAP, "--out", "b.zarr", "--json"]) == 0
    with xr.open_zarr(tmp_path / "b.zarr") as ds:
        assert int(ds["basin_count"].sum()) == 2


@pytest.mark.parametrize("store, out", [("same.zarr", "same.zarr"), ("./same.zarr", "same.zarr")])
def test_store_equal_to_out_is_refused(store, out, tmp_path, monkeypatch, capsys, no_compute):
    monkeypatch.chdir(tmp_path)
    assert main([*CHEAP, "--store", store, "--out", out]) == 2
    assert "--store must not be --out" in _one_line(capsys)
    assert not list(tmp_path.iterdir())


# -- 9. what an interruption keeps ------------------------------------------------------------------

def _interrupt(monkeypatch):
    from frictionflow.sweep import runner

    def compute(*args):
        raise KeyboardInterrupt

    monkeypatch.setattr(runner, "compute_chunk", compute)


def test_an_interrupted_run_without_out_says_nothing_was_kept(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _interrupt(monkeypatch)
    assert main(CHEAP) == 1
    line = _one_line(capsys)
    assert "nothing was kept" in line and "--out or --store" in line and "run the same command" not in line


def test_an_interrupted_run_with_out_says_its_store_resumes(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _interrupt(monkeypatch)
    assert main([*CHEAP, "--out", "b.nc"]) == 1
    line = _one_line(capsys)
    assert "'b.nc.sweep.zarr' keeps the chunks finished so far; run the same command to resume" in line
    assert (tmp_path / "b.nc.sweep.zarr").is_dir()


# -- 10. a tolerance in (0, 1) -----------------------------------------------------------------------

def test_a_zero_tolerance_is_refused(capsys, tmp_path, monkeypatch, no_compute):
    monkeypatch.chdir(tmp_path)
    assert main([*CHEAP, "--attractor-tol", "0"]) == 2
    assert "--attractor-tol must be a number in (0, 1), got 0.0" in _one_line(capsys)
    for field in ("period", "amplitude", "stick"):
        with pytest.raises(ValueError, match=rf"tolerance {field} must be a number in \(0, 1\)"):
            Tolerances(**{field: 0.0})
    assert Tolerances(floor=0.0).floor == 0.0  # an absolute floor may be 0


# -- the initial states' options named as options ---------------------------------------------------

@pytest.mark.parametrize("args, words", [
    (["--x0-range=1:0:3", "--v0-range=-0.1:0.1:2"], "--x0-range: low 1 > high 0"),
    (["--x0-range=-0.1:0.1:2", "--v0-range=0.1:0.1:3"], "--v0-range: low == high with 3 points"),
    (["--x0-range=-0.1:0.1", "--v0-range=-0.1:0.1", "--sample", "0"], "--sample must be an integer >= 1, got 0"),
    (["--x0-range=-0.1:0.1", "--v0-range=-0.1:0.1", "--sample", "3", "--seed", "-1"], "--seed must be an integer and in [0, 2^63)"),
])
def test_initial_state_problems_name_the_options(args, words, tmp_path, monkeypatch, capsys, no_compute):
    monkeypatch.chdir(tmp_path)
    base = [a for a in CHEAP if not a.startswith(("--x0-range", "--v0-range"))]
    assert main([*base, *args]) == 2
    assert words in _one_line(capsys)


def test_a_one_point_range_with_two_ends_is_refused_as_a_sweep_axis_is(capsys):
    # one point would keep low and drop high without a word (a sweep's axis refuses it alike)
    with pytest.raises(ValueError, match=r"v0: 1 point holds one value, but low -0.1 and high 0.1 differ"):
        basins(fd=0.02, fs=0.04, zeta=0.05, vb=0.01, t_end=50.0, x0=(-0.1, 0.1, 2), v0=(-0.1, 0.1, 1))
    assert main([*CHEAP[:-1], "--v0-range=-0.1:0.1:1"]) == 2
    assert "--v0-range: 1 point holds one value" in _one_line(capsys)
