"""``frictionflow forced-orbit`` and ``forced-continue``: JSON output, figures, and bad input (exit 2, one line)."""

from __future__ import annotations

import importlib
import json

import pytest

import frictionflow.cli.forced_orbit  # noqa: F401  (registers the commands until cli/__init__ imports it)
from frictionflow.cli import main

SUB3 = ["--zeta", "0.05", "--vb", "0.1", "--fex", "0.5", "--omega", "1.0", "--friction", "coulomb", "--fd", "0.5",
        "--fs", "1.0"]
#: the same system continued in omega (which the branch sets: no --omega)
SUB3_IN_OMEGA = [a for i, a in enumerate(SUB3) if "--omega" not in SUB3[i - 1:i + 1]]


def test_forced_orbit_json_matches_the_api(capsys):
    from frictionflow import BeltOscillator, Coulomb
    from frictionflow.orbits.forced import find_forced_orbit

    assert main(["forced-orbit", *SUB3, "--m", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # the CLI starts where every command does, at (F_d, V_b), and runs 200 forcing periods first
    o = find_forced_orbit(BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.0), Coulomb(0.5, 1.0), m=3, x0=0.5, v0=0.1,
                          transient_periods=200)
    assert out["m"] == 3 and out["stability"] == "stable"
    assert out["state"]["X"] == pytest.approx(o.state[0], abs=1e-12)
    assert out["multipliers"][1] == [0.0, 0.0]
    a = out["averages"]
    assert a["P_ex"] == pytest.approx(a["P_dv"] + a["P_df"] - a["P_fin"], rel=1e-8)


def test_forced_orbit_plot(tmp_path, capsys):
    path = tmp_path / "orbit.png"
    assert main(["forced-orbit", *SUB3, "--m", "3", "--plot", str(path)]) == 0
    assert path.stat().st_size > 1000
    assert "ForcedOrbit" in capsys.readouterr().out


def test_forced_continue_json_and_plot(tmp_path, capsys):
    path = tmp_path / "branch.svg"
    args = ["forced-continue", *SUB3_IN_OMEGA, "--m", "3", "--parameter", "omega", "--from", "1.25", "--to", "1.35",
            "--switch-pd", "--sweep", "5", "--json", "--plot", str(path)]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    first, doubled = out["branches"]
    assert [e["type"] for e in first["events"]] == ["period_doubling"]
    assert doubled["m"] == 6
    assert len(out["brute_force"]["values"]) == 5
    assert path.stat().st_size > 1000


def test_forced_continue_in_fex_runs_from_the_command_line(capsys):
    """``--vary fex=FROM:TO`` is the only way to give F_ex to forced-continue (a --fex beside it is refused), so the
    model is built at FROM; it was built at F_ex = 0 and refused as unforced, and no command line could run.
    Both ends of the branch are the orbits forced-orbit's API finds at those amplitudes."""
    from frictionflow import BeltOscillator, Coulomb
    from frictionflow.orbits.forced import find_forced_orbit

    system = ["--friction", "coulomb", "--zeta", "0.03", "--vb", "0.05", "--fd", "0.02", "--fs", "0.04", "--omega", "0.9"]
    assert main(["forced-continue", *system, "--vary", "fex=0.02:0.03", "--json"]) == 0
    branch = json.loads(capsys.readouterr().out)["branches"][0]
    assert branch["parameter"] == "fex" and branch["end"] == "interval end"
    for point, fex in ((branch["points"][0], 0.02), (branch["points"][-1], 0.03)):
        assert point["lambda"] == pytest.approx(fex, abs=1e-14)
        o = find_forced_orbit(BeltOscillator(zeta=0.03, vb=0.05, fex=fex, omega=0.9), Coulomb(0.02, 0.04), m=1,
                              x0=point["X"], v0=point["V"])
        assert (point["X"], point["V"]) == pytest.approx(tuple(o.state[:2]), abs=1e-10)
        assert point["amplitude"] == pytest.approx(o.amplitude, rel=1e-10)


@pytest.mark.parametrize("args, name", [
    (["forced-continue", *SUB3, "--parameter", "zeta", "--from", "0.1", "--to", "0.2"], "--vary"),
    (["forced-continue", *SUB3, "--from", "-1", "--to", "0.2"], "--vary FROM"),
    (["forced-continue", *SUB3, "--from", "1", "--to", "1"], "--vary"),
    (["forced-orbit", *SUB3, "--m", "0"], "m"),
    (["forced-orbit", "--zeta", "0.05", "--vb", "0.1", "--friction", "coulomb"], "fex"),
    (["forced-orbit", *SUB3[:-6], "--friction", "karnopp"], "friction"),
])
def test_bad_input_exits_2_naming_the_parameter(args, name, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("error:") and name in err


@pytest.mark.parametrize("given", ["option", "config"])
@pytest.mark.parametrize("parameter, interval", [("omega", "1.25:1.35"), ("fex", "0.4:0.5")])
def test_forced_continue_refuses_a_value_of_the_parameter_it_varies(tmp_path, capsys, monkeypatch, given, parameter,
                                                                    interval):
    """The branch sets the varied parameter from FROM to TO: a value given besides --vary (an option or a config's
    key) would be ignored without a word, so it is refused in one line naming both, before any work."""
    monkeypatch.setattr("frictionflow.cli.forced_orbit.find_forced_orbit",
                        lambda *a, **k: pytest.fail("computed despite the conflict"))
    system = [a for i, a in enumerate(SUB3) if f"--{parameter}" not in SUB3[i - 1:i + 1]]
    value = {"omega": "0.7", "fex": "0.3"}[parameter]
    if given == "option":
        extra = [f"--{parameter}", value]
        words = [f"--{parameter} {value} conflicts with --vary {parameter}=FROM:TO", "give one of them"]
    else:
        (tmp_path / "c.toml").write_text(f"{parameter} = {value}\n")
        extra = ["--config", str(tmp_path / "c.toml")]
        words = [f"--config: {parameter} = {value} conflicts with --vary {parameter}=FROM:TO", "remove it from"]
    assert main(["forced-continue", *system, *extra, "--vary", f"{parameter}={interval}", "--json"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1 and lines[0].startswith("error: "), captured.err
    assert all(w in lines[0] for w in words), lines[0]


@pytest.mark.parametrize("given", ["option", "config"])
@pytest.mark.parametrize("command, flag, args", [
    ("continue", "--vary", ["--friction", "stribeck", "--vb", "0.016", "--vary", "zeta=0.2:0.4"]),
    ("map", "--y", ["--friction", "stribeck", "--x", "vb=0.01:0.03", "--y", "zeta=0.0:0.5"]),
    ("map", "--x", ["--friction", "stribeck", "--x", "zeta=0.0:0.5", "--y", "vb=0.01:0.03"]),
    ("map", "--y", ["--friction", "coulomb", "--x", "omega=0.5:1.5", "--y", "fex=0.01:0.1"]),
])
def test_continue_and_map_refuse_a_value_of_a_parameter_they_vary(tmp_path, capsys, monkeypatch, given, command, flag,
                                                                  args):
    """As forced-continue: ``continue --vary zeta=... --zeta 0.3`` and ``map --y zeta=... --zeta 0.5`` echoed the
    fixed value in their params while the branch or the chart set it (the result was the run without it)."""
    for name in ("continuation", "stability_map", "forced_map"):
        for module in ("orbit", "map"):
            if hasattr(cli_module(module), name):
                monkeypatch.setattr(cli_module(module), name, lambda *a, **k: pytest.fail("computed despite the conflict"))
    varied = args[args.index(flag) + 1].split("=")[0]
    value = "0.3"
    if given == "option":
        extra, words = [f"--{varied}", value], [f"--{varied} {value} conflicts with {flag} {varied}=FROM:TO"]
    else:
        (tmp_path / "c.toml").write_text(f"{varied} = {value}\n")
        extra, words = ["--config", str(tmp_path / "c.toml")], [f"--config: {varied} = {value} conflicts with {flag}"]
    assert main([command, *args, *extra, "--json"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1 and lines[0].startswith("error: "), captured.err
    assert all(w in lines[0] for w in words), lines[0]


def cli_module(name: str):
    return importlib.import_module(f"frictionflow.cli.{name}")
