"""``frictionflow forced-orbit`` and ``forced-continue``: JSON output, figures, and bad input (exit 2, one line)."""

from __future__ import annotations

import json

import pytest

import frictionflow.cli.forced_orbit  # noqa: F401  (registers the commands until cli/__init__ imports it)
from frictionflow.cli import main

SUB3 = ["--zeta", "0.05", "--vb", "0.1", "--fex", "0.5", "--omega", "1.0", "--friction", "coulomb", "--fd", "0.5",
        "--fs", "1.0"]


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
    args = ["forced-continue", *SUB3, "--m", "3", "--parameter", "omega", "--from", "1.25", "--to", "1.35",
            "--switch-pd", "--sweep", "5", "--json", "--plot", str(path)]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    first, doubled = out["branches"]
    assert [e["type"] for e in first["events"]] == ["period_doubling"]
    assert doubled["m"] == 6
    assert len(out["brute_force"]["values"]) == 5
    assert path.stat().st_size > 1000


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
