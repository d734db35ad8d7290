"""Sweeps over a model file's entries: the single-mass sweep on one dof, each point's own run, resume, refusals."""

from __future__ import annotations

import json
import math
import time

import numpy as np
import pytest
import xarray as xr

import frictionflow as ff
from frictionflow.analysis.structure import STRUCTURE_KINDS, analyze_structure, evaluations
from frictionflow.solvers.structure import simulate_system
from frictionflow.sweep import repair_sweep, run_sweep, verify_sweep
from frictionflow.sweep import model as model_module, runner
from frictionflow.sweep.model import load_model_sweep, parse_model_sweep
from frictionflow.system import System, assemble, load_system

from ..cli.processes import in_process

ZETA, FD, FS, T_END = 0.1, 0.02, 0.04, 200.0
#: two stick-slip cycles and two sliding equilibria (from X = 0 at rest)
BELTS = [0.005, 0.01, 0.03, 0.06]

TWO = """
dof = ["x1", "x2"]
mass = [1.0, 1.0]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x2 = 1.0 }
k = 1.0
[[spring]]
on = { x1 = 1.0, x2 = -1.0 }
k = 0.3
[[damper]]
on = { x1 = 1.0 }
c = 0.2
[[damper]]
on = { x2 = 1.0 }
c = 0.2
[[contact]]
on = { x1 = 1.0 }
belt = 0.01
friction = "coulomb"
fd = 0.02
fs = 0.04
[[contact]]
on = { x2 = 1.0 }
belt = 0.01
friction = "coulomb"
fd = 0.02
fs = 0.04
"""

SWEEP = """
model = "two.toml"
t_end = 150.0
[grid]
"contact.0.belt" = [0.005, 0.01]
"spring.2.k" = "0.3:0.6:2"
"""


@pytest.fixture(scope="module")
def one_dof_pair(tmp_path_factory):
    """The single-mass sweep and the one-dof model sweep over the same belt speeds, start state and t_end."""
    tmp = tmp_path_factory.mktemp("pair")
    single = run_sweep({"friction": "coulomb", "fd": FD, "fs": FS, "t_end": T_END, "zeta": ZETA, "x0": 0.0, "v0": 0.0,
                        "grid": {"vb": BELTS}}, tmp / "single.nc").load()
    system = System.single_mass(ff.BeltOscillator(ZETA, 0.01), ff.Coulomb(FD, FS), x0=0.0, v0=0.0)
    cfg = parse_model_sweep({"t_end": T_END, "grid": {"contact.0.belt": BELTS}}, system)
    return single, run_sweep(cfg, tmp / "model.zarr", chunk_size=3).load()


def test_one_dof_sweep_equals_the_single_mass_sweep(one_dof_pair):
    single, model = one_dof_pair
    kinds = [STRUCTURE_KINDS[k] for k in model["kind"].values]
    assert kinds == ["periodic", "periodic", "equilibrium", "equilibrium"]
    assert [ff.quantities.KINDS[k] for k in single["kind"].values] == kinds
    np.testing.assert_allclose(model["period"].values, single["period"].values, rtol=1e-8)  # NaN where not periodic
    c = {"contact": "contact.0"}
    pairs = [(model["P_belt"].sel(c), single["P_belt"]), (model["P_heat"].sel(c), single["P_heat"]),
             (-model["P"].sel(element="damper.0"), single["P_dv"]),
             (model["stick_fraction"].sel(c), single["stick_fraction"]),
             (model["X_max"].sel(dof="x"), single["X_max"]), (model["X_min"].sel(dof="x"), single["X_min"])]
    for mine, theirs in pairs:
        np.testing.assert_allclose(mine.values, theirs.values, rtol=1e-8, atol=1e-8 * float(np.max(np.abs(theirs))))
    # the spring stores and returns energy: no net power over whole periods or at rest
    np.testing.assert_allclose(model["P"].sel(element="spring.0").values, 0.0, atol=1e-12)


def test_dataset_layout(one_dof_pair):
    _, model = one_dof_pair
    assert model["kind"].dims == ("contact.0.belt",)
    assert model["kind"].attrs["flag_meanings"].split() == list(STRUCTURE_KINDS)
    assert model["P"].dims == ("contact.0.belt", "element")
    assert list(model["element"].values) == ["spring.0", "damper.0"]
    assert model["P_belt"].dims == model["stick_fraction"].dims == ("contact.0.belt", "contact")
    assert model["X_max"].dims == ("contact.0.belt", "dof")
    np.testing.assert_array_equal(model["contact.0.belt"].values, BELTS)
    assert float(model["energy_residual"].max()) < 1e-9


def point_values(system: System, t_end: float) -> dict:
    """One point, run and analysed directly."""
    a = analyze_structure(simulate_system(system, t_end))
    ss = a.steady_state
    return {"kind": STRUCTURE_KINDS.index(ss.kind), "period": ss.period, "stick_fraction": list(ss.stick_fraction),
            "P": [a.elements[e]["P"] for e in (*system.spring_names, *system.damper_names)],
            "P_belt": [a.elements[c]["P_belt"] for c in system.contact_names],
            "P_heat": [a.elements[c]["P_heat"] for c in system.contact_names],
            "X_max": [a.amplitude["X_max"][d] for d in system.dof], "X_min": [a.amplitude["X_min"][d] for d in system.dof],
            "energy_residual": a.energy_residual}


@pytest.fixture(scope="module")
def two_dof(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("two")
    (tmp / "two.toml").write_text(TWO)
    (tmp / "sweep.toml").write_text(SWEEP)
    return tmp


def assert_same(a: xr.Dataset, b: xr.Dataset) -> None:
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


def test_each_point_equals_its_own_run_on_every_path(two_dof):
    base = load_system(two_dof / "two.toml")
    zarr_one = run_sweep(two_dof / "sweep.toml", two_dof / "a.zarr", chunk_size=1).load()
    nc_three = run_sweep(two_dof / "sweep.toml", two_dof / "b.nc", chunk_size=3).load()
    assert_same(zarr_one, nc_three)
    for vb in (0.005, 0.01):
        for k in (0.3, 0.6):
            want = point_values(base.with_entry("contact.0.belt", vb).with_entry("spring.2.k", k), 150.0)
            got = zarr_one.sel({"contact.0.belt": vb, "spring.2.k": k})
            for name, value in want.items():
                np.testing.assert_array_equal(got[name].values, value, err_msg=f"{name} at {vb}, {k}")
    assert set(STRUCTURE_KINDS[k] for k in zarr_one["kind"].values.ravel()) <= {"periodic", "not_settled"}


def test_a_stribeck_model_sweeps_on_simulate_s_solver(tmp_path):
    """A law only the adaptive solver runs (Stribeck's): the sweep runs it as ``simulate --model`` does (it refused
    it with the exact solver's message), each point the command's own report at that point."""
    model = TWO.replace('friction = "coulomb"', 'friction = "stribeck"\nvs = 0.005')
    (tmp_path / "two.toml").write_text(model)
    (tmp_path / "s.toml").write_text('model = "two.toml"\nt_end = 60.0\n[grid]\n"contact.0.belt" = [0.005, 0.03]\n')
    ds = run_sweep(tmp_path / "s.toml", tmp_path / "r.nc", chunk_size=1).load()
    assert ds.attrs["solver"] == "adaptive"
    for vb in (0.005, 0.03):
        (tmp_path / "p.toml").write_text(model.replace("belt = 0.01", f"belt = {vb}", 1))
        code, out, err, _ = in_process("simulate", "--model", str(tmp_path / "p.toml"), "--t-end", "60", "--json")
        assert code == 0, err
        report, got = json.loads(out), ds.sel({"contact.0.belt": vb})
        assert STRUCTURE_KINDS[int(got["kind"])] == report["steady_state"]["kind"]
        for j, c in enumerate(("contact.0", "contact.1")):
            assert float(got["P_belt"][j]) == report["elements"][c]["P_belt"]
            assert float(got["P_heat"][j]) == report["elements"][c]["P_heat"]
        assert [float(x) for x in got["X_max"]] == list(report["amplitude"]["X_max"].values())
        assert float(got["energy_residual"]) == report["energy_residual"]


def test_dask_path_agrees(two_dof):
    distributed = pytest.importorskip("distributed")
    local = run_sweep(two_dof / "sweep.toml", two_dof / "local.zarr", chunk_size=2).load()
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        dask = run_sweep(two_dof / "sweep.toml", two_dof / "dask.zarr", chunk_size=2, client=client).load()
    assert_same(local, dask)


def test_resume_after_an_interruption_gives_identical_arrays(two_dof, monkeypatch):
    whole = run_sweep(two_dof / "sweep.toml", two_dof / "whole.zarr", chunk_size=1).load()
    calls = []
    real = runner.compute_model_chunk

    def interrupted(source, chunk, chunks):
        calls.append(chunk)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(source, chunk, chunks)

    monkeypatch.setattr(runner, "compute_model_chunk", interrupted)
    out = two_dof / "resumed.nc"
    with pytest.raises(KeyboardInterrupt):
        run_sweep(two_dof / "sweep.toml", out, chunk_size=1)
    found = verify_sweep(out)
    assert found.intact and found.done == 2 and found.n_chunks == 4
    calls.clear()
    resumed = run_sweep(two_dof / "sweep.toml", out, chunk_size=1).load()
    assert len(calls) == 2  # only the chunks not committed
    assert_same(whole, resumed)
    assert verify_sweep(out).intact


def test_a_moved_sweep_file_is_the_same_sweep(two_dof, tmp_path):
    """The fingerprint is the model's content and the grid, not the files' paths."""
    a = load_model_sweep(two_dof / "sweep.toml")
    (tmp_path / "m").mkdir()
    (tmp_path / "m" / "two.toml").write_text(TWO)
    (tmp_path / "s.toml").write_text(SWEEP.replace('"two.toml"', '"m/two.toml"'))
    assert load_model_sweep(tmp_path / "s.toml").fingerprint() == a.fingerprint()
    (tmp_path / "m" / "two.toml").write_text(TWO.replace("k = 0.3", "k = 0.4"))
    assert load_model_sweep(tmp_path / "s.toml").fingerprint() != a.fingerprint()


@pytest.mark.parametrize("grid, words", [
    ({"contact.0.blet": [0.1, 0.2]}, ["unknown grid key 'contact.0.blet'", "contact.0.belt"]),
    ({"spring.7.k": [0.1, 0.2]}, ["unknown grid key 'spring.7.k'"]),
    ({"spring.0.k": [1.0, -2.0]}, ["grid.spring.0.k[1]", "spring.0.k"]),
    ({"contact.0.fd": "0.01:0.05:3"}, ["grid.contact.0.fd.stop"]),  # fd above fs = 0.04: the law's own check
    ({"contact.0.belt": [0.1, True]}, ["grid.contact.0.belt[1]"]),
])
def test_bad_grids_refused_in_one_line_with_nothing_written(two_dof, tmp_path, grid, words):
    lines = "\n".join(f'"{k}" = {v!r}'.replace("True", "true").replace("'", '"') for k, v in grid.items())
    refused_grid(two_dof, tmp_path, lines, words)


def refused_grid(two_dof, tmp_path, grid: str, words: list[str]) -> None:
    """A sweep of the two-dof model over ``grid`` (TOML lines) is refused in one line holding ``words``, nothing
    written."""
    sweep = tmp_path / "bad.toml"
    sweep.write_text(f'model = "{two_dof / "two.toml"}"\nt_end = 50.0\n[grid]\n{grid}\n')
    with pytest.raises(ValueError) as e:
        run_sweep(sweep, tmp_path / "r.zarr")
    message = str(e.value)
    assert "\n" not in message
    for w in words:
        assert w in message, message
    assert list(tmp_path.iterdir()) == [sweep]


def test_entries_that_bound_each_other_are_swept_together(two_dof, tmp_path):
    """F_d up to 0.05 and F_s from 0.06: every point is a valid contact though F_d = 0.05 exceeds the file's
    F_s = 0.04 (each value was once checked against the file alone, and a point set F_d before F_s); each point
    is its own run with both entries set."""
    sweep = tmp_path / "s.toml"
    sweep.write_text(f'model = "{two_dof / "two.toml"}"\nt_end = 60.0\n[grid]\n'
                     '"contact.0.fd" = [0.02, 0.05]\n"contact.0.fs" = [0.06, 0.08]\n"contact.1.fs" = 0.07\n'
                     '"contact.1.fd" = 0.06\n')
    ds = run_sweep(sweep, tmp_path / "r.nc").load()
    base = load_system(two_dof / "two.toml").with_entries({"contact.1.fs": 0.07, "contact.1.fd": 0.06})
    assert base.entry("contact.1.fd") == 0.06
    for fd in (0.02, 0.05):
        for fs in (0.06, 0.08):
            want = point_values(base.with_entries({"contact.0.fd": fd, "contact.0.fs": fs}), 60.0)
            got = ds.sel({"contact.0.fd": fd, "contact.0.fs": fs})
            for name, value in want.items():
                np.testing.assert_array_equal(got[name].values, value, err_msg=f"{name} at {fd}, {fs}")


@pytest.mark.parametrize("grid, words", [
    # the corner (F_d 0.07, F_s 0.06) is no contact: named as a whole point
    ('"contact.0.fd" = [0.02, 0.07]\n"contact.0.fs" = [0.06, 0.08]', ["grid point (contact.0.fd = 0.07, contact.0.fs = 0.06)",
                                                                     "fs must be >= fd"]),
    # F_d 0.09 is above every F_s of the grid: the value itself is named
    ('"contact.0.fd" = [0.02, 0.09]\n"contact.0.fs" = [0.06, 0.08]', ["grid.contact.0.fd[1] = 0.09"]),
    # fixed entries are set together; the model's message names the one at fault
    ('"contact.0.belt" = [0.01, 0.02]\n"spring.0.k" = -1.0', ["fixed entries (spring.0.k = -1)",
                                                              "spring.0.k must be >= 0"]),
    ('"contact.0.belt" = [0.01, 0.02]\n"contact.0.fd" = 0.05\n"contact.0.fs" = 0.045',
     ["fixed entries (contact.0.fd = 0.05, contact.0.fs = 0.045)", "fs must be >= fd"]),
    # contact.1 along (1, 0), contact.0's direction, at the grid's middle point only: the engines cannot hold both
    # stuck; it ran the other points first, then stopped with exit 2 and left a partial store (QA)
    ('"contact.1.on.x1" = 1.0\n"contact.1.on.x2" = [1.0, 0.0, -1.0]',
     ["grid point (contact.1.on.x2 = 0)", "its direction is a multiple of contact.0's"]),
])
def test_grids_whose_entries_do_not_fit_together_are_refused_in_one_line(two_dof, tmp_path, grid, words):
    refused_grid(two_dof, tmp_path, grid, words)


def test_a_range_table_with_a_wrong_key_is_named_as_the_single_mass_sweep_names_it(two_dof, tmp_path):
    """``{ from = ..., to = ..., n = ... }`` under an entry: the entry's range key is wrong, not the entry (TOML's
    nested tables once made it "unknown grid key 'contact.0.belt.from': not an entry of the model")."""
    sweep = tmp_path / "bad.toml"
    sweep.write_text(f'model = "{two_dof / "two.toml"}"\nt_end = 50.0\n[grid]\n'
                     '"contact.0.belt" = {{ from = 0.02, to = 0.2, n = 8 }}\n'.replace("{{", "{").replace("}}", "}"))
    with pytest.raises(ValueError, match=r"^.*bad.toml: grid.contact.0.belt: unknown key 'from'; allowed: num, scale, "
                                         r"start, stop$"):
        run_sweep(sweep, tmp_path / "r.zarr")
    assert list(tmp_path.iterdir()) == [sweep]


def test_dotted_keys_unquoted_are_the_same_grid(two_dof, tmp_path):
    """TOML reads ``contact.0.belt = ...`` (unquoted) as nested tables: joined back into the address."""
    (tmp_path / "s.toml").write_text(SWEEP.replace('"contact.0.belt"', "contact.0.belt").replace('"spring.2.k"', "spring.2.k")
                                     .replace('"two.toml"', f'"{two_dof / "two.toml"}"'))
    cfg = load_model_sweep(tmp_path / "s.toml")
    assert cfg.dims == ("contact.0.belt", "spring.2.k")
    assert cfg.fingerprint() == load_model_sweep(two_dof / "sweep.toml").fingerprint()


def test_fixed_entries_apply_to_every_point(two_dof):
    system = load_system(two_dof / "two.toml")
    cfg = parse_model_sweep({"t_end": 10.0, "grid": {"damper.1.c": 0.5, "spring.2.k": [0.1, 0.2]}}, system)
    assert cfg.fixed == {"damper.1.c": 0.5} and cfg.dims == ("spring.2.k",)
    assert cfg.point_system((1,)).entry("damper.1.c") == 0.5 and cfg.point_system((1,)).entry("spring.2.k") == 0.2
    assert not math.isnan(cfg.size)


def test_damage_is_found_and_repaired(two_dof, monkeypatch):
    """A model sweep's store is checked like the single mass's: a damaged chunk found, its metadata rebuilt from
    the settings it records (no config file), only the bad chunk computed again."""
    out = two_dof / "damaged.zarr"
    whole = run_sweep(two_dof / "sweep.toml", out, chunk_size=1).load()
    (out / "P_heat" / "c" / "1" / "0" / "0").write_bytes(b"")  # a truncated chunk file of a variable over `contact`
    found = verify_sweep(out)
    assert not found.intact and [b.chunk for b in found.bad] == [(1, 0)]
    (out / "zarr.json").write_text("")  # the root's metadata emptied
    repaired = repair_sweep(out)
    assert repaired.rebuilt == ["root"] and repaired.done == 3
    calls = []
    real = runner.compute_model_chunk
    monkeypatch.setattr(runner, "compute_model_chunk", lambda *a: calls.append(a[1]) or real(*a))
    again = run_sweep(two_dof / "sweep.toml", out, chunk_size=1).load()
    assert calls == [(1, 0)]
    assert_same(whole, again)
    assert verify_sweep(out).intact


def test_estimate_before_any_work(two_dof, tmp_path):
    """The cost is estimated (a probe run scaled to t_end) and held to the limits before anything is written."""
    from frictionflow.estimate import Limits, limited

    cfg = load_model_sweep(two_dof / "sweep.toml")
    est = runner.sweep_estimate(cfg, tmp_path / "r.zarr")
    assert est.work == 4 and est.seconds > 0
    # per point: kind, solver, period, energy_residual; stick_fraction, P_belt, P_heat, t_lost over 2 contacts; P over 5
    # elements; X_max, X_min over 2 dof
    assert est.outputs == (("out", str(tmp_path / "r.zarr"), 4 * 8.0 * (4 + 4 * 2 + 5 + 2 * 2)),)
    with limited(Limits(seconds=1e-9)), pytest.raises(ValueError) as e:
        run_sweep(cfg, tmp_path / "r.zarr")
    assert "\n" not in str(e.value)
    assert list(tmp_path.iterdir()) == []


def _burning(real, seconds: float, which) -> tuple[list, object]:
    """``real`` (the analysis) with ``seconds`` of CPU burnt first in the calls ``which(call number)`` picks."""
    calls = []

    def burn(motion, **kwargs):
        if which(len(calls)):
            end = time.process_time() + seconds
            while time.process_time() < end:
                pass
        calls.append(motion.t[-1])
        return real(motion, **kwargs)

    return calls, burn


def test_the_estimate_leaves_out_a_first_use_compile(two_dof, monkeypatch):
    """The probe runs twice and the cheaper run counts: a process's first run loads its kernels or compiles them
    (stood in for here by a second of CPU in its analysis), which the points will not."""
    cfg = load_model_sweep(two_dof / "sweep.toml")
    calls, burn = _burning(model_module.analyze_structure, 1.0, lambda k: k == 0)
    monkeypatch.setattr(model_module, "analyze_structure", burn)
    est = model_module.model_sweep_estimate(cfg)
    assert calls == [model_module.probe_length(assemble(cfg.point_system((0, 0))), cfg.t_end)] * 2
    assert est.seconds / est.work < 1.0  # the burnt second is not in it


def test_the_estimate_counts_the_probe_s_analysis_once(two_dof, monkeypatch):
    """The probe's analysis is counted once per point, not scaled to t_end with its run: where the probe has
    not settled it is mostly the largest Lyapunov exponent, a fixed number of blocks whatever t_end (QA: 600
    points of the stick-slip chain to t_end 1000, 50 s of work, were estimated at 2.8 h and refused).  Stood
    in for by 0.3 s of CPU in every probe's analysis, at t_end 20 times the probe's: the estimate holds it
    once.  The part of the analysis that does grow with t_end (its grids, its crossings) is counted at t_end's
    size: twice the run, twice those evaluations."""
    probe = model_module.probe_length(assemble(load_model_sweep(two_dof / "sweep.toml").point_system((0, 0))), 1e9)
    (two_dof / "long.toml").write_text(SWEEP.replace("t_end = 150.0", f"t_end = {20.0 * probe!r}"))
    cfg = load_model_sweep(two_dof / "long.toml")
    assert model_module.probe_length(assemble(cfg.point_system((0, 0))), cfg.t_end) == pytest.approx(probe)
    _, burn = _burning(model_module.analyze_structure, 0.3, lambda k: True)
    monkeypatch.setattr(model_module, "analyze_structure", burn)
    per_point = model_module.model_sweep_estimate(cfg).seconds / cfg.size
    assert 0.3 <= per_point < 0.3 * 2.0
    motion = simulate_system(cfg.point_system((0,) * len(cfg.axes)), probe)
    one, two = evaluations(motion, 1000.0), evaluations(motion, 2000.0)
    assert 1.9 < two[0] / one[0] < 2.1 and 1.9 < two[1] / one[1] < 2.1


def test_a_lost_contact_is_its_own_kind(tmp_path):
    """N = 1 - c x reaches zero for the larger c: that point is ``contact_lost``, with nothing averaged but the
    energy balance of the run up to the loss checked, the same number as the direct run's."""
    system = System.from_dict({
        "dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}], "damper": [{"on": {"x": 1.0}, "c": 0.1}],
        "contact": [{"on": {"x": 1.0}, "belt": 0.5, "friction": "coulomb", "fd": 0.3, "fs": 0.4,
                     "normal": {"preload": 1.0, "x": -5.0}}]})
    ds = run_sweep(parse_model_sweep({"t_end": 50.0, "grid": {"contact.0.normal.x": [-5.0, -0.5]}}, system),
                   tmp_path / "r.nc").load()
    lost = ds.isel({"contact.0.normal.x": 0})
    assert STRUCTURE_KINDS[int(lost["kind"])] == "contact_lost"
    motion = simulate_system(system, 50.0)
    assert motion.status == "contact_lost"  # (the engine's own report, independent of the sweep)
    for name in ("period", "stick_fraction", "P", "P_belt", "P_heat", "X_max", "X_min"):
        assert np.all(np.isnan(lost[name].values)), name
    assert motion.lost[1] > 1.0 and motion.energy_residual < 1e-12  # the run's balance at every sample up to the loss
    direct = analyze_structure(simulate_system(system.with_entry("contact.0.normal.x", -5.0), 50.0))
    assert direct.steady_state.kind == "contact_lost" and direct.steady_state.window[1] == motion.lost[1]
    assert float(lost["energy_residual"]) == direct.energy_residual < 1e-12
    assert lost["t_lost"].sel(contact="contact.0").item() == motion.lost[1]  # where simulate --model says it stopped
    kept = ds.isel({"contact.0.normal.x": 1})
    assert np.isnan(kept["t_lost"].values).all()
    want = point_values(system.with_entry("contact.0.normal.x", -0.5), 50.0)
    assert int(kept["kind"]) == want["kind"] and STRUCTURE_KINDS[want["kind"]] != "contact_lost"
    np.testing.assert_array_equal(kept["P_heat"].values, want["P_heat"])
