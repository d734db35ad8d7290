"""Basins of attraction: a bistable Stribeck oscillator, labels over chunks, basin stability, CLI, datasets.

The bistable case (issue 11): Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1)
at zeta = 0.03, V_b = 0.12.  Its sliding equilibrium X* = F(V_b) =
0.02 + 0.02 exp(-2.4) is stable (2 zeta + F'(V_b) = 0.06 - 0.4 exp(-2.4) > 0),
an unstable pure-slip cycle (X* + 0.108 on the section X' = 0) surrounds it,
and outside that lies the basin of a stable stick-slip cycle.  In the plane
(X, X') the unstable cycle is the boundary between the two basins, so the
expected label of a point follows from geometry alone: inside the cycle (found
here by Newton shooting, an algorithm independent of the sweep's
classification) the equilibrium, outside the stick-slip cycle.
"""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from frictionflow import BeltOscillator, Stribeck, analyze, simulate
from frictionflow.basins import Tolerances, basins
from frictionflow.orbits import find_orbit
from frictionflow.basins.study import SweepOptions
from frictionflow.basins.labels import find_attractors
from frictionflow.cli import main
from frictionflow.sweep import parse_sweep, run_sweep, verify_sweep

LAW = {"friction": "stribeck", "fd": 0.02, "fs": 0.04, "vs": 0.05, "delta": 1.0}
SETTINGS = {**LAW, "zeta": 0.03, "vb": 0.12, "t_end": 300.0}
X_STAR = 0.02 + 0.02 * math.exp(-0.12 / 0.05)  # F(V_b) of the Stribeck law with delta = 1
HALF = 0.3  # the box of initial states: X* +- HALF, X' in +- HALF
BOX = {"x0": (X_STAR - HALF, X_STAR + HALF), "v0": (-HALF, HALF)}


@pytest.fixture(scope="module")
def unstable_cycle():
    """The unstable slip cycle around X*, as a closed polygon in (X - X*, X'), by Newton shooting."""
    orbit = find_orbit(BeltOscillator(zeta=0.03, vb=0.12), Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0),
                       x0=X_STAR + 0.108, v0=0.0, transient=0.0)
    assert orbit.stability == "unstable" and orbit.stick_fraction == 0.0
    assert orbit.state[0] - X_STAR == pytest.approx(0.108, abs=1e-3)  # the amplitude about X*
    traj = orbit.trajectory()
    return np.column_stack([traj.x - X_STAR, traj.v])


@pytest.fixture(scope="module")
def big():
    return basins(SETTINGS, **BOX, sample=1200, seed=1, chunk_size=256)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    d = tmp_path_factory.mktemp("small")
    return basins(SETTINGS, **BOX, sample=150, seed=2, out=d / "b.nc", plot=d / "b.png")


def _radius(result) -> np.ndarray:
    ds = result.dataset
    return np.hypot(ds["x0"].values - X_STAR, ds["v0"].values)


def _labels(result, name: str) -> np.ndarray:
    return result.dataset["label"].values == result.codes[name]


# -- the bistable case --------------------------------------------------------------------------

def test_both_attractors_are_found_and_described(big, unstable_cycle):
    assert set(big.codes) == {"equilibrium", "stick_slip_cycle"}
    assert big.codes == {"equilibrium": 0, "stick_slip_cycle": 1}  # ordered by amplitude
    eq, ss = {o["name"]: o for o in big.outcomes()}["equilibrium"], {o["name"]: o for o in big.outcomes()}["stick_slip_cycle"]
    assert eq["x_mid"] == pytest.approx(X_STAR, abs=1e-7) and eq["amplitude"] == 0.0 and eq["period"] is None
    # the stick-slip cycle sticks (at X' = V_b) and encloses the unstable cycle
    assert ss["stick_fraction"] > 0.01
    assert ss["amplitude"] > 0.5 * np.ptp(unstable_cycle[:, 0])
    per = _labels(big, "stick_slip_cycle")
    assert np.allclose(big.dataset["V_max"].values[per], 0.12, rtol=1e-6)


def test_basins_add_up_to_the_whole_sample(big):
    ds = big.dataset
    assert int(ds["basin_count"].sum()) == 1200 == ds.sizes["sample"]
    assert float(ds["basin_stability"].sum()) == pytest.approx(1.0, abs=1e-12)
    assert set(np.unique(ds["label"].values)) <= set(ds["label"].attrs["flag_values"])
    for j, code in enumerate(ds["outcome"].values):
        n = int(np.count_nonzero(ds["label"].values == code))
        p = n / 1200
        assert int(ds["basin_count"][j]) == n
        assert float(ds["basin_stability_stderr"][j]) == pytest.approx(math.sqrt(p * (1 - p) / 1200), rel=1e-12)


def test_basins_follow_the_unstable_cycle(big, unstable_cycle):
    """Inside the unstable cycle: the equilibrium; outside: the stick-slip cycle (away from the boundary)."""
    from matplotlib.path import Path

    r = _radius(big)
    rmin, rmax = np.hypot(*unstable_cycle.T).min(), np.hypot(*unstable_cycle.T).max()
    inside, outside = r < 0.85 * rmin, r > 1.2 * rmax
    assert inside.sum() > 40 and outside.sum() > 800
    assert _labels(big, "equilibrium")[inside].all()
    assert not _labels(big, "equilibrium")[outside].any()
    assert _labels(big, "stick_slip_cycle")[outside].all()
    # every equilibrium point lies inside the cycle, every stick-slip point outside (a margin for the slowest ones)
    pts = np.column_stack([big.dataset["x0"].values - X_STAR, big.dataset["v0"].values])
    grown, shrunk = Path(1.02 * unstable_cycle), Path(0.98 * unstable_cycle)
    assert grown.contains_points(pts[_labels(big, "equilibrium")]).all()
    assert not shrunk.contains_points(pts[_labels(big, "stick_slip_cycle")]).any()


def test_basin_stability_is_the_area_inside_the_unstable_cycle(big, unstable_cycle):
    x, v = unstable_cycle.T
    area = 0.5 * abs(np.sum(x * np.roll(v, -1) - np.roll(x, -1) * v))  # shoelace
    expected = area / (2 * HALF) ** 2  # uniform initial states in the box
    p, se = big.fractions["equilibrium"], big.stderr["equilibrium"]
    assert abs(p - expected) < 3 * se, (p, se, expected)


def test_fractions_converge_with_sample_size(big, small):
    """Two independent samples (N = 150, 1200) agree within their errors, which shrink as 1/sqrt(N)."""
    for name in ("equilibrium", "stick_slip_cycle"):
        p1, s1 = small.fractions[name], small.stderr[name]
        p2, s2 = big.fractions[name], big.stderr[name]
        assert abs(p1 - p2) < 3 * math.hypot(s1, s2), (name, p1, p2)
        if min(p1, p2) > 0:
            ratio = s1 / s2 / math.sqrt(1200 / 150)
            assert 0.6 < ratio < 1.6, ratio


def test_batched_kernel_and_single_run_agree_on_a_stick_slip_point(tmp_path):
    x0, v0 = 0.3046575593987602, -0.1603191612333502  # drawn by the seed-1 sample of an earlier box
    single = analyze(simulate(BeltOscillator(zeta=0.03, vb=0.12), Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0),
                              x0=x0, v0=v0, t_end=300.0)).steady_state
    ds = run_sweep({**SETTINGS, "grid": {"x0": [x0], "v0": [v0]}}, tmp_path / "one.zarr").load()
    assert single.kind == "periodic"
    assert int(ds["kind"].values.ravel()[0]) == 0


# -- consistency ---------------------------------------------------------------------------------

def test_labels_are_the_same_whatever_the_chunks():
    grid = dict(x0=(X_STAR - 0.2, X_STAR + 0.2, 12), v0=(-0.2, 0.2, 12))
    one = basins(SETTINGS, **grid, chunk_size=144)
    many = basins(SETTINGS, **grid, chunk_size=7)
    assert one.codes == many.codes
    np.testing.assert_array_equal(one.dataset["label"].values, many.dataset["label"].values)
    for var in ("kind", "period", "X_max", "stick_fraction", "basin_stability"):
        np.testing.assert_array_equal(one.dataset[var].values, many.dataset[var].values)
    assert set(one.codes) == {"equilibrium", "stick_slip_cycle"}


def test_sweep_options_as_a_record_or_as_keywords(tmp_path):
    """A SweepOptions, or its fields as keywords (they win): the same sweep, kept in the store named."""
    grid = dict(x0=(X_STAR - 0.2, X_STAR + 0.2, 3), v0=(-0.2, 0.2, 3))
    store = tmp_path / "kept.zarr"
    by_record = basins(SETTINGS, **grid, sweep_options=SweepOptions(store=store, chunk_size=4))
    assert store.is_dir()  # given: kept
    by_keywords = basins(SETTINGS, **grid, sweep_options=SweepOptions(chunk_size=2), chunk_size=4, store=store, restart=True)
    np.testing.assert_array_equal(by_record.dataset["label"].values, by_keywords.dataset["label"].values)
    assert by_record.fractions == by_keywords.fractions
    with pytest.raises(TypeError, match="sweep_options must be a SweepOptions"):
        basins(SETTINGS, **grid, sweep_options={"chunk_size": 4})
    with pytest.raises(ValueError, match="unknown key 'chunksize'"):
        basins(SETTINGS, **grid, chunksize=4)  # a keyword neither a setting nor a sweep option: refused by name


def test_a_study_against_vb_labels_each_value_and_shares_codes(small, tmp_path):
    """At V_b = 0.06 the equilibrium is unstable (2 zeta + F'(V_b) = 0.06 - 0.4 exp(-1.2) < 0): nothing can reach it."""
    assert 0.06 - 0.4 * math.exp(-1.2) < 0
    settings = {k: v for k, v in SETTINGS.items() if k != "vb"}
    study = basins(settings, **BOX, sample=150, seed=2, vary={"vb": [0.06, 0.12]}, plot=tmp_path / "curves.svg")
    ds = study.dataset
    assert ds["basin_stability"].dims == ("vb", "outcome") and ds["label"].dims == ("vb", "sample")
    np.testing.assert_allclose(ds["basin_stability"].sum("outcome"), 1.0)
    assert study.fractions["equilibrium"][0] == 0.0
    # the value 0.12 of the study is the fixed-V_b run of the same sample, label for label
    np.testing.assert_array_equal(ds["label"].sel(vb=0.12).values, small.dataset["label"].values)
    assert study.codes == small.codes
    assert (tmp_path / "curves.svg").read_text().lstrip().startswith("<?xml")
    report = study.to_dict()
    assert report["vary"] == "vb" and [r["vb"] for r in report["results"]] == [0.06, 0.12]


def test_clusters_tell_orbits_apart_within_the_tolerances():
    """Synthetic steady states: noise of 1e-7 stays one orbit; 1 % in period or amplitude is another."""
    rng = np.random.default_rng(0)
    n = 60
    base = np.array([6.3, 0.24, 0.04])  # period, amplitude, stick fraction
    rows = np.tile(base, (n, 1)) * (1 + 1e-7 * rng.standard_normal((n, 3)))
    rows[20:40, 0] *= 1.01  # another period
    rows[40:50, 1] *= 0.99  # another amplitude
    rows[50:, 2] = 0.0  # no sticking: a slip cycle
    q = {"kind": np.zeros(n), "period": rows[:, 0], "X_min": -rows[:, 1] / 2, "X_max": rows[:, 1] / 2, "stick_fraction": rows[:, 2]}
    found = find_attractors(q, Tolerances())
    sizes = sorted(len(a.members) for a in found)
    assert sizes == [10, 10, 20, 20]
    assert sorted(a.name for a in found) == ["slip_cycle", "stick_slip_cycle", "stick_slip_cycle_2", "stick_slip_cycle_3"]
    # the same points in another order: the same attractors
    perm = rng.permutation(n)
    again = find_attractors({k: v[perm] for k, v in q.items()}, Tolerances())
    assert sorted(sorted(perm[a.members].tolist()) for a in again) == sorted(sorted(a.members.tolist()) for a in found)
    # a looser tolerance merges what differs by 1 %
    assert len(find_attractors(q, Tolerances(period=0.05, amplitude=0.05))) == 2


# -- outputs -------------------------------------------------------------------------------------

def test_dataset_and_figure_outputs(small, tmp_path):
    back = xr.open_dataset(small.files["out"])
    np.testing.assert_array_equal(back["label"].values, small.dataset["label"].values)
    assert back["label"].attrs["flag_meanings"].split() == small.names
    assert back.attrs["basins_kind"] == "sample" and back.attrs["label_tol_period"] == 1e-3
    assert {"x0", "v0"} <= set(back.coords) and "kind" in back and "stick_fraction" in back
    assert not list(Path(small.files["out"]).parent.glob("*.sweep.zarr"))  # the sweep store went once the output was written
    assert open(small.files["plot"], "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    # the same as Zarr: consolidated, opened without a warning
    z = tmp_path / "b.zarr"
    basins(SETTINGS, x0=(X_STAR - 0.2, X_STAR + 0.2, 4), v0=(-0.2, 0.2, 4), out=z)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with xr.open_zarr(z) as ds:
            assert ds["label"].dims == ("x0", "v0") and int(ds["basin_count"].sum()) == 16
    assert not (tmp_path / "b.zarr.sweep.zarr").exists()


def test_an_interrupted_run_resumes_from_its_store(tmp_path, monkeypatch):
    """Killed mid-sweep: the store beside the output keeps the finished chunks; the same call finishes the rest."""
    from frictionflow.sweep import runner

    grid = dict(x0=(X_STAR - 0.2, X_STAR + 0.2, 4), v0=(-0.2, 0.2, 4))
    out = tmp_path / "b.nc"
    real, calls = runner.compute_chunk, []

    def compute(*args):
        if len(calls) == 2:
            raise KeyboardInterrupt
        calls.append(args)
        return real(*args)

    monkeypatch.setattr(runner, "compute_chunk", compute)
    with pytest.raises(KeyboardInterrupt):
        basins(SETTINGS, **grid, out=out, chunk_size=4)
    assert (tmp_path / "b.nc.sweep.zarr").is_dir() and not out.exists()
    monkeypatch.setattr(runner, "compute_chunk", lambda *a: (calls.append(a), real(*a))[1])
    resumed = basins(SETTINGS, **grid, out=out, chunk_size=4)
    assert len(calls) == 4  # 2 chunks before the interruption, the other 2 after
    assert not (tmp_path / "b.nc.sweep.zarr").exists() and out.exists()
    fresh = basins(SETTINGS, **grid, chunk_size=16)
    np.testing.assert_array_equal(resumed.dataset["label"].values, fresh.dataset["label"].values)


def test_sweep_zarr_stores_are_consolidated(tmp_path):
    out = tmp_path / "s.zarr"
    cfg = {**LAW, "zeta": 0.03, "t_end": 50.0, "grid": {"vb": [0.1, 0.12], "sample": {"num": 8, "seed": 3, "x0": [-0.1, 0.1], "v0": [-0.1, 0.1]}}}
    run_sweep(cfg, out, chunk_size=4).close()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with xr.open_zarr(out) as ds:
            np.testing.assert_array_equal(ds["x0"].values, parse_sweep(cfg).sample["x0"])
            assert ds["kind"].dims == ("vb", "sample")
    run_sweep(cfg, out, chunk_size=4).close()  # resumed when complete: still intact and consolidated
    assert verify_sweep(out).intact


def test_the_sample_is_reproducible_and_checked():
    spec = {"num": 5, "seed": 7, "v0": [-1.0, 1.0], "x0": [0.0, 2.0]}
    a = parse_sweep({**LAW, "grid": {"sample": spec}}).sample
    b = parse_sweep({**LAW, "grid": {"sample": dict(reversed(list(spec.items())))}}).sample
    np.testing.assert_array_equal(a["x0"], b["x0"])
    assert (0 <= a["x0"]).all() and (a["x0"] < 2).all() and (-1 <= a["v0"]).all() and (a["v0"] < 1).all()
    for bad, key in [({"num": 0, "x0": [0, 1]}, "grid.sample.num"), ({"num": 3, "x0": [1, 0]}, "grid.sample.x0"),
                     ({"num": 3, "seed": -1, "x0": [0, 1]}, "grid.sample.seed"), ({"num": 3, "zeta": [0, 1]}, "'zeta'"),
                     ({"num": 3}, "grid.sample"), ({"num": 3, "x0": 1.0}, "grid.sample.x0")]:
        with pytest.raises(ValueError, match=key):
            parse_sweep({**LAW, "grid": {"sample": bad}})
    with pytest.raises(ValueError, match="'x0' is both sampled"):
        parse_sweep({**LAW, "grid": {"sample": {"num": 3, "x0": [0, 1]}, "x0": [0.1, 0.2]}})


# -- the command line ----------------------------------------------------------------------------

CLI = ["basins", "--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.05", "--delta", "1", "--zeta", "0.03",
       "--t-end", "300"]


def test_cli_json_figure_and_dataset(tmp_path, capsys):
    out, fig = tmp_path / "b.nc", tmp_path / "b.png"
    code = main([*CLI, "--vb", "0.12", "--x0=-0.28:0.32:6", "--v0=-0.3:0.3:6", "--out", str(out), "--plot", str(fig), "--json"])
    assert code == 0
    report = json.loads(capsys.readouterr().out)
    names = [o["name"] for o in report["outcomes"]]
    assert names == ["equilibrium", "stick_slip_cycle", "not_settled", "diverged", "quasi_periodic", "chaotic"]
    assert sum(o["count"] for o in report["outcomes"]) == 36 and report["design"]["kind"] == "grid"
    assert report["labels"] == {"0": "equilibrium", "1": "stick_slip_cycle", "-1": "not_settled", "-2": "diverged",
                                "-3": "quasi_periodic", "-4": "chaotic"}
    assert out.exists() and fig.read_bytes()[:4] == b"\x89PNG"
    with xr.open_dataset(out) as ds:
        assert ds["label"].shape == (6, 6)


def test_cli_vary_prints_a_table(capsys):
    assert main([*CLI, "--x0=-0.28:0.32", "--v0=-0.3:0.3", "--sample", "20", "--vary", "vb=0.06,0.12"]) == 0
    text = capsys.readouterr().out
    assert "basin stability" in text and "0.06" in text and "stick_slip_cycle" in text


@pytest.mark.parametrize("args, words", [
    (["--vb", "0.12", "--x0-range", "abc", "--v0-range=-0.3:0.3:5"], "--x0-range must be FROM:TO:N"),
    (["--vb", "0.12", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--sample", "10"], "--x0-range (with --sample, N is --sample's) must be FROM:TO"),
    (["--vb", "0.12", "--x0-range=0.3:-0.3:5", "--v0-range=-0.3:0.3:5"], "--x0-range: low 0.3 > high -0.3"),
    (["--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--vary", "x0=0.1,0.2"], "'x0' cannot be varied"),
    (["--vb", "0.1", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--vary", "vb=0.1,0.2"], "vb is also given"),
    (["--vb", "0.12", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--out", "b.csv"], "--out must end in"),
    (["--vb", "0.12", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--plot", "b.gif"], "--plot must end in"),
    (["--vb", "0.12", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--attractor-tol", "2"],
     "--attractor-tol must be a number in (0, 1), got 2.0"),  # the option, not Tolerances' field (period)
    (["--vb", "0.12", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--chunk-size", "0"],
     "--chunk-size must be an integer and in [1, 1e+07], got 0"),  # the option, not the API's chunk_size
    (["--vb", "0.12", "--x0-range=-0.3:0.3:5", "--v0-range=-0.3:0.3:5", "--zeta", "-1"], "zeta must be"),
])
def test_cli_bad_input_exits_2_with_one_line(args, words, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main([*CLI, *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and words in err[0], err
    assert not list(tmp_path.iterdir())  # nothing written


def test_an_attractor_s_amplitude_is_its_orbit_s(big):
    """One meaning of amplitude: the basin's stick-slip cycle has the amplitude (X_max - X_min) / 2 that shooting
    reports for the orbit through one of its points (it was peak-to-peak here, half the range in orbit/continue)."""
    ss = {o["name"]: o for o in big.outcomes()}["stick_slip_cycle"]
    i = int(np.nonzero(_labels(big, "stick_slip_cycle"))[0][0])
    ds = big.dataset
    orbit = find_orbit(BeltOscillator(zeta=0.03, vb=0.12), Stribeck(fd=0.02, fs=0.04, vs=0.05, delta=1.0),
                       x0=float(ds["x0"].values[i]), v0=float(ds["v0"].values[i]), transient=300.0)
    assert orbit.stick_fraction > 0.01
    assert ss["amplitude"] == pytest.approx(orbit.amplitude, rel=1e-6)


def test_points_that_did_not_settle_are_said_to_leave_the_fractions_lower_bounds():
    """At t_end = 20 the slow spirals into X* have not settled: their basin is unknown, and the run says so with the
    count; at the module's t_end every point settles and nothing is said (QA: a forced torus's points split 61/39
    between quasi_periodic and not_settled, read as two basins)."""
    grid = dict(x0=(X_STAR - 0.2, X_STAR + 0.2, 3), v0=(-0.2, 0.2, 3))
    with pytest.warns(UserWarning, match=r"^(\d) of 9 runs did not settle by t_end = 20 ") as seen:
        short = basins({**SETTINGS, "t_end": 20.0}, **grid)
    n = int(np.count_nonzero(short.dataset["label"].values == -1))
    assert n > 0 and str(seen[0].message).startswith(f"{n} of 9 ")
    assert short.fractions["not_settled"] == pytest.approx(n / 9, abs=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        settled = basins(SETTINGS, **grid)
    assert settled.fractions["not_settled"] == 0.0
