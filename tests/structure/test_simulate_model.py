"""``simulate --model FILE``: a one-dof model file gives the single mass's steady state and powers.

The single-mass command and the model file describe the same system by two
independent routes (its closed forms and analysis; the structure engine and
its section analysis), so their agreement is the check.
"""

from __future__ import annotations

import json
import math
import warnings
from contextlib import contextmanager
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
from PIL import Image

import frictionflow.cli.structure as cli_structure
from frictionflow.analysis.structure import analyze_structure
from frictionflow.solvers.structure import run_estimate, simulate_system
from frictionflow.structure_plot import energy_budget, mode_steps, plot_structure
from frictionflow.system import assemble, load_system

from ..cli.processes import cli, in_process, one_line

ONE_DOF = """
dof = ["x"]
mass = [1.0]
[[spring]]
on = {{ x = 1.0 }}
k = 1.0
[[damper]]
on = {{ x = 1.0 }}
c = {c}
[[contact]]
on = {{ x = 1.0 }}
belt = {vb}
friction = "coulomb"
fd = 0.02
fs = 0.04
stick_force = "{stick}"
[initial]
q = {{ x = 0.02 }}
v = {{ x = {vb} }}
"""

CASES = {"damped": (0.05, 0.01, "resultant"), "spring": (0.05, 0.01, "spring"), "fast_belt": (0.02, 0.02, "resultant")}


@pytest.mark.parametrize("case", sorted(CASES))
def test_one_dof_model_agrees_with_simulate(tmp_path, case):
    zeta, vb, stick = CASES[case]
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF.format(c=2 * zeta, vb=vb, stick=stick))
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "300", "--json")
    assert code == 0, err
    model = json.loads(out)
    code, out, err, _ = in_process("simulate", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--vb", str(vb),
                            "--zeta", str(zeta), "--stick-force", stick, "--x0", "0.02", "--v0", str(vb), "--t-end", "300",
                            "--json")
    assert code == 0, err
    single = json.loads(out)
    assert model["steady_state"]["kind"] == single["steady_state"]["kind"] == "periodic"
    assert model["steady_state"]["period"] == pytest.approx(single["steady_state"]["period"], rel=1e-9)
    assert model["steady_state"]["stick_fraction"][0] == pytest.approx(single["steady_state"]["stick_fraction"],
                                                                       rel=1e-8)
    av = single["averages"]
    contact, damper = model["elements"]["contact.0"], model["elements"]["damper.0"]
    assert contact["P_belt"] == pytest.approx(av["P_belt"], rel=1e-8)
    assert contact["P_heat"] == pytest.approx(av["P_heat"], rel=1e-8)
    assert -damper["P"] == pytest.approx(av["P_dv"], rel=1e-8)
    assert model["amplitude"]["X_max"]["x"] == pytest.approx(single["amplitude"]["X_max"], rel=1e-9)
    assert model["amplitude"]["X_min"]["x"] == pytest.approx(single["amplitude"]["X_min"], rel=1e-9, abs=1e-12)
    assert model["energy_residual"] < 1e-10


def test_model_refuses_single_mass_options(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF.format(c=0.1, vb=0.01, stick="resultant"))
    code, out, err, _ = in_process("simulate", "--model", str(path), "--fd", "0.3", "--json")
    assert code == 2 and out == ""
    one_line(err, "--fd", "--model")


def test_model_file_missing_is_one_line(tmp_path):
    code, out, err, _ = in_process("simulate", "--model", str(tmp_path / "none.toml"), "--json")
    assert code == 2 and out == ""
    one_line(err, "--model")


def _strict(text):
    """``text`` parsed as strict JSON: NaN or Infinity (which Python's json would read) fail."""
    def refuse(name):
        raise AssertionError(f"{name} in the JSON report")
    return json.loads(text, parse_constant=refuse)


def test_contact_lost_json_report():
    """A run ending in contact loss (Hoffmann's 2-dof flutter model, the example) reports it as strict JSON:
    what did not settle (the period, the stick fraction) is null, nothing is averaged, the energy balance up to
    the loss is given (closed to rounding), the exit code 0."""
    path = Path(__file__).parents[2] / "examples" / "models" / "hoffmann_2dof.toml"
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "200", "--json")
    assert code == 0, err
    report = _strict(out)
    assert report["status"] == "contact_lost" and report["steady_state"]["kind"] == "contact_lost"
    assert report["steady_state"]["period"] is None
    assert report["steady_state"]["stick_fraction"] == [None]
    assert report["elements"] == {} and report["amplitude"] == {}
    assert 0.0 <= report["energy_residual"] < 1e-12
    # which contact and when: there the load N = P - kH x2 (the file's preload and x2 row, read here) is 0 to
    # rounding, and positive on a grid before it
    system = load_system(path)
    motion = simulate_system(system, 200.0)
    t_lost = report["lost"]["t"]
    assert report["lost"]["contact"] == "contact.0" and 0.0 < t_lost < 200.0
    normal = system.contacts[0].normal
    row = np.array([dict(normal.on).get(d, 0.0) for d in system.dof])

    def load(times):
        return normal.preload + row @ motion.states(times)[:len(row)]  # states: (2n, len(times))

    assert abs(load([t_lost])[0]) < 1e-12
    assert np.all(load(np.linspace(0.0, t_lost, 2001)[:-1]) > 0.0)
    table = in_process("simulate", "--model", str(path), "--t-end", "200")[1]
    assert "contact.0 at t = " in table


def test_two_masses_budget_closes(tmp_path):
    """A chain of two masses, one contact each: the energy coming in equals what leaves, over the window."""
    path = tmp_path / "chain.toml"
    path.write_text("""
dof = ["x1", "x2"]
mass = [1.0, 1.5]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x1 = 1.0, x2 = -1.0 }
k = 0.6
[[damper]]
on = { x1 = 1.0 }
c = 0.05
[[damper]]
on = { x2 = 1.0 }
c = 0.04
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
fd = 0.03
fs = 0.05
""")
    result = analyze_structure(simulate_system(load_system(path), 400.0))
    assert result.energy_residual < 1e-10
    assert set(result.elements) == {"spring.0", "spring.1", "damper.0", "damper.1", "contact.0", "contact.1"}
    assert all(result.elements[d]["P"] <= 0.0 for d in ("damper.0", "damper.1"))  # dampers only take
    assert all(result.elements[c]["P_heat"] >= 0.0 for c in ("contact.0", "contact.1"))
    if result.steady_state.kind == "periodic":  # over whole periods the stored energy returns: in = out
        inputs, outputs = energy_budget(result.elements)
        inflow, outflow = sum(v for _, v in inputs), sum(v for _, v in outputs)
        assert math.isclose(inflow, outflow, rel_tol=1e-8)


def test_model_run_estimated_before_work(tmp_path):
    """A run whose switches alone would take hours is refused in one line, before any work."""
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF.format(c=0.1, vb=0.01, stick="resultant"))
    code, out, err, seconds = cli("simulate", "--model", str(path), "--t-end", "1e9", "--json")
    assert code == 2 and out == ""
    one_line(err, "switches", "--no-limit")


def test_model_figure_and_netcdf(tmp_path):
    """--plot draws the run at the asked dpi; --out writes the samples labelled by dof, contact and channel."""
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF.format(c=0.1, vb=0.01, stick="resultant"))
    png, nc = tmp_path / "run.png", tmp_path / "run.nc"
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "100", "--plot", str(png), "--dpi", "80",
                            "--out", str(nc))
    assert code == 0, err
    with Image.open(png) as im:
        assert im.size == (960, 600)
    ds = xr.open_dataset(nc)
    assert list(ds["dof"].values) == ["x"] and list(ds["contact"].values) == ["contact.0"]
    assert "contact.0.heat" in list(ds["channel"].values)
    assert float(ds["time"][-1]) == 100.0
    # a file gets the curve, not only the switches: at most 2 pi / 200 of the one mode's period between samples
    # (k = m = 1: omega 1), each sample the engine's exact state there
    gaps = np.diff(ds["time"].values)
    assert len(gaps) > 3000 and gaps.max() <= 2 * math.pi / 200 * (1 + 1e-12)
    motion = simulate_system(load_system(path), 100.0)
    picked = ds["time"].values[::97]
    assert np.allclose(ds["q"].sel(time=picked).values[:, 0], motion.states(picked)[0], rtol=0, atol=1e-12)


def test_mode_steps_hold_each_mode_until_the_next_sample():
    """The figure's mode curve at any time of the window is the mode of the last sample at or before it (found
    here by a scan), from the window's start to its end, with or without a switch inside."""
    system = load_system(Path(__file__).parents[2] / "examples" / "models" / "two_mass_chain.toml")
    motion = simulate_system(system, 60.0)
    t, modes = np.asarray(motion.t), np.asarray(motion.modes)
    for span in ((0.3, 6.0), (2.0, 9.0), (20.0, 60.0), (0.0, 60.0)):
        times, steps = mode_steps(motion, span)
        assert times[0] == span[0] and times[-1] == span[1] and np.all(np.diff(times) >= 0)
        for s in np.linspace(span[0], span[1], 157)[:-1]:
            last = max(i for i in range(len(t)) if t[i] <= s)
            shown = steps[:, np.searchsorted(times, s, side="right") - 1]  # where="post": the value from its time on
            assert np.array_equal(shown, modes[:, last]), (span, s)


def test_a_lost_contact_run_reports_the_end_time_asked_for():
    """The run stops at the loss (``lost.t``); ``params.t_end`` is what was asked for: the default 300 without
    --t-end (it was the loss time), the option's value with it."""
    path = Path(__file__).parents[2] / "examples" / "models" / "hoffmann_2dof.toml"
    for extra, asked in (((), 300.0), (("--t-end", "250"), 250.0)):
        code, out, err, _ = in_process("simulate", "--model", str(path), *extra, "--json")
        report = _strict(out)
        assert code == 0 and report["params"]["t_end"] == asked, err
        assert report["lost"]["t"] < asked and report["steady_state"]["window"][1] == report["lost"]["t"]


def test_the_figure_of_a_lost_contact_run_warns_of_nothing_and_says_nothing_is_averaged():
    """Its energy-budget panel has no bars (nothing is averaged over a transient): no legend of nothing (matplotlib
    warned "No artists with labels found" on stderr), a note instead."""
    path = Path(__file__).parents[2] / "examples" / "models" / "hoffmann_2dof.toml"
    result = analyze_structure(simulate_system(load_system(path), 200.0))
    assert result.steady_state.kind == "contact_lost"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fig = plot_structure(result)
    assert not caught, [str(w.message) for w in caught]
    budget = fig.axes[3]
    assert budget.get_legend() is None and [t.get_text() for t in budget.texts] == ["nothing averaged (contact lost)"]


def test_model_netcdf_carries_what_the_json_says(tmp_path):
    """The file's energy residual was the whole run's under the JSON's name for the window's (3.65e-14 against
    2.43e-13), with no provenance and no long names: the file now names both and records the run's settings."""
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF.format(c=0.1, vb=0.01, stick="resultant"))
    nc = tmp_path / "run.nc"
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "100", "--out", str(nc), "--json")
    assert code == 0, err
    report = json.loads(out)
    with xr.open_dataset(nc) as ds:
        assert ds.attrs["window_energy_residual"] == report["energy_residual"]
        assert ds.attrs["steady_state"] == report["steady_state"]["kind"] and ds.attrs["t_end"] == 100.0
        assert ds.attrs["model_file"] == str(path) and ds.attrs["solver"] == "exact"
        assert ds.attrs["energy_residual"] < 1e-12 and "whole run" in ds.attrs["energy_residual_span"]
        assert all(ds[k].attrs.get("long_name") for k in ("q", "v", "force", "mode", "work"))


def test_model_json_names_its_solver_and_settings_as_the_single_mass_does(tmp_path):
    """docs/citation.md: "the JSON output records both [solver and sticking force] under ``solver`` and
    ``params``": the single mass's report had ``solver``, the model's had none.  It gives the solver's name, its
    settings (the adaptive one's by keyword, defaults included) and the sample step the run used (None: the
    switches only; the file's step with --out), the same numbers the NetCDF's samples are spaced by."""
    path = tmp_path / "one.toml"
    path.write_text(ONE_DOF.format(c=0.1, vb=0.01, stick="resultant"))
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "50", "--json")
    assert code == 0, err
    assert json.loads(out)["solver"] == {"name": "exact", "dense_dt": None}
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "50", "--solver", "adaptive",
                                   "--ode-rtol", "1e-8", "--json")
    assert code == 0, err
    solver = json.loads(out)["solver"]
    assert solver["name"] == "adaptive" and solver["rtol"] == 1e-8 and solver["dense_dt"] is None
    assert solver["atol"] > 0 and solver["max_steps"] >= 1  # the defaults the run used, not only what was given
    # a setting out of its range is refused under the option's own name (it was the solver's keyword, rtol)
    code, out, err, _ = in_process("simulate", "--model", str(path), "--solver", "adaptive", "--ode-rtol", "1")
    assert code == 2 and out == "" and err.startswith("error: ode_rtol must be finite and in [1e-14, 0.01]"), err
    nc = tmp_path / "run.nc"
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "50", "--out", str(nc), "--json")
    assert code == 0, err
    step = json.loads(out)["solver"]["dense_dt"]
    with xr.open_dataset(nc) as ds:
        gaps = np.diff(ds["time"].values)
    assert step > 0 and gaps.max() == pytest.approx(step, rel=1e-12)  # no two samples further apart than the step


def test_the_help_gives_the_defaults_a_model_run_takes(capsys):
    """``simulate --help`` gave only the single-mass solvers' --rtol defaults (1e-6 to 1e-10) and --dense-dt range
    ([1e-9, 1000]); beside --model the steady-state tolerance is 1e-6 and the step any time > 0 in the model's
    units.  The run without --rtol is the run with --rtol 1e-6."""
    code, out, err, _ = in_process("simulate", "--help")
    assert code == 0, err
    text = " ".join(out.split())
    assert "[rk4 1e-6, adaptive 1e-8, exact 1e-10]. With --model: 1e-06 unless given." in text
    assert "With --model: any step > 0 in the model's units of time." in text
    path = Path(__file__).resolve().parents[2] / "examples" / "models" / "stick_slip_chain.toml"
    runs = [in_process("simulate", "--model", str(path), "--t-end", "100", "--json", *extra)
            for extra in ((), ("--rtol", "1e-6"), ("--rtol", "0.1"))]
    assert all(run[0] == 0 for run in runs), runs
    default, given, other = (json.loads(run[1]) for run in runs)
    assert default == given and default["steady_state"] != other["steady_state"]


def test_a_long_model_run_shows_a_bar_on_a_terminal(monkeypatch):
    """A structure run of half a minute was silent on a terminal (the single mass's long runs show a bar with the
    time so far): the bar shows for a run estimated above ``PROGRESS_AFTER`` seconds, on a terminal only, and the
    run's report is the same with it."""
    shown = []

    @contextmanager
    def recorder(description, total, enabled=True, **kwargs):
        shown.append((description, enabled))
        yield lambda n: None

    path = Path(__file__).resolve().parents[2] / "examples" / "models" / "stick_slip_chain.toml"
    wall = run_estimate(assemble(load_system(path)), 100.0).wall
    plain = in_process("simulate", "--model", str(path), "--t-end", "100", "--json")
    monkeypatch.setattr(cli_structure, "progress_bar", recorder)
    for terminal in (False, True):
        monkeypatch.setattr(cli_structure, "sys", SimpleNamespace(stderr=SimpleNamespace(isatty=lambda: terminal)))
        for after in (2 * wall, wall / 2):
            monkeypatch.setattr(cli_structure, "PROGRESS_AFTER", after)
            assert in_process("simulate", "--model", str(path), "--t-end", "100", "--json")[:3] == plain[:3]
    assert shown == [("exact run", False)] * 3 + [("exact run", True)]
