"""``frictionflow orbit`` and ``frictionflow continue`` (the CLI module is cli/orbit.py)."""

from __future__ import annotations

import json
import math

import pytest

from frictionflow.cli import main

COULOMB = ["--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--vb", "0.01"]


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_orbit_json(capsys):
    code, out, err = run(capsys, "orbit", *COULOMB, "--zeta", "0", "--json", "--fd-check", "--t-end", "50")
    assert code == 0, err
    d = json.loads(out)  # exactly one JSON object
    assert {"period", "floquet_multipliers", "stable", "stick_fraction", "averages", "TR_B"} <= d.keys()
    assert d["period"] == pytest.approx(math.pi + 2 * math.atan(0.5) + 4.0, rel=1e-12)
    (m1, m2) = d["floquet_multipliers"]
    assert m1 == pytest.approx([1.0, 0.0], abs=1e-12) and m2 == pytest.approx([0.0, 0.0], abs=1e-12)
    assert d["stable"] is True and d["stick_fraction"] == pytest.approx(4.0 / d["period"], rel=1e-12)
    assert {"P_fin", "P_df", "P_dv", "R_c", "R_f"} <= d["averages"].keys()
    assert d["fd_deviation"] < 1e-6


def test_orbit_guess_reaches_an_unstable_orbit_and_plots(capsys, tmp_path):
    plot = tmp_path / "orbit.svg"
    code, out, err = run(capsys, "orbit", "--friction", "stribeck", "--zeta", "0.3", "--vb", "0.016",
                         "--x0", "0.031", "--v0", "0", "--guess", "--json", "--plot", str(plot))
    assert code == 0, err
    d = json.loads(out)
    assert d["stable"] is False and d["stability"] == "unstable" and d["has_stick"] is False
    assert d["floquet_multipliers"][0][0] > 1.5
    assert plot.exists() and plot.stat().st_size > 1000


def test_orbit_table(capsys):
    code, out, _ = run(capsys, "orbit", *COULOMB, "--zeta", "0.05", "--t-end", "50")
    assert code == 0 and "Floquet multiplier" in out and "TR_B" in out


def test_orbit_failures(capsys):
    # nothing periodic to find: a run-time failure (exit 1), one line
    code, _, err = run(capsys, "orbit", *COULOMB, "--zeta", "0.5", "--t-end", "100")
    assert code == 1 and err.startswith("error:") and err.count("\n") == 1
    for bad in (["--returns", "0"], ["--plot", "x.txt"], ["--tol", "-1"], ["--solver", "rk4"], ["--zeta", "-1"]):
        code, _, err = run(capsys, "orbit", *COULOMB, *bad)
        assert code == 2 and err.startswith("error:"), bad


def test_continue_json_and_plot(capsys, tmp_path):
    plot = tmp_path / "bif.png"
    code, out, err = run(capsys, "continue", "--param", "vb", "--from", "0.005", "--to", "0.025", "--friction", "stribeck",
                         "--delta", "1", "--viscous", "0.05", "--zeta", "0.1", "--points", "21", "--seeds", "hopf",
                         "--sweep", "3", "--t-end", "200", "--json", "--plot", str(plot))
    assert code == 0, err
    d = json.loads(out)
    assert isinstance(d["branches"], list) and all(isinstance(b, list) for b in d["branches"])
    need = {"value", "kind", "stability", "period", "amplitude", "P_fin", "P_df", "P_dv", "R_c", "R_f", "TR_B"}
    assert all(need <= p.keys() for b in d["branches"] for p in b)
    hopf = [b for b in d["bifurcations"] if b["type"] == "hopf"]
    assert hopf and hopf[0]["value"] == pytest.approx(0.01 * math.log(0.02 / (0.25 * 0.01)), rel=1e-12)
    kinds = {p["kind"] for b in d["branches"] for p in b}
    assert kinds == {"equilibrium", "periodic"}
    assert len(d["sweep"]) == 3
    assert plot.exists() and plot.stat().st_size > 1000


def test_continue_refuses_bad_input(capsys):
    for bad in (
        ["--param", "nope", "--from", "0", "--to", "1"],
        ["--param", "vb", "--from", "0.01", "--to", "0.01"],
        ["--param", "zeta", "--from", "-0.1", "--to", "0.1"],
        ["--param", "vb", "--from", "0.01", "--to", "0.02", "--seeds", "moon"],
        ["--param", "vb", "--from", "0.01", "--to", "0.02", "--plot", "out.gif"],
        ["--param", "vb", "--from", "0.01", "--to", "0.02", "--points", "1"],
    ):
        code, out, err = run(capsys, "continue", *COULOMB, *bad)
        assert code == 2 and err.startswith("error:") and out == "", bad


def test_continue_reports_monitor_extrema(capsys):
    code, out, err = run(capsys, "continue", "--friction", "cubic", "--fs", "0.04", "--k1", "0.3", "--k3", "10", "--zeta", "0.05",
                         "--param", "vb", "--from", "0.01", "--to", "0.3", "--seeds", "hopf", "--monitor", "R_c,TR_B", "--json")
    assert code == 0, err
    d = json.loads(out)
    (rc,) = [e for e in d["extrema"] if e["monitor"] == "R_c"]
    # the largest R_c of the branch's points, and the refined one at least as large
    pts = [p for b in d["branches"] for p in b if p["kind"] == "periodic" and p["R_c"] is not None]
    assert rc["kind"] == "max" and rc["monitor_value"] >= max(p["R_c"] for p in pts) - 1e-9
    (tr,) = [e for e in d["extrema"] if e["monitor"] == "TR_B"]
    graze = next(b for b in d["bifurcations"] if b["type"] == "grazing")
    assert tr["value"] == pytest.approx(graze["value"], abs=1e-12)


def test_continue_refuses_an_unknown_monitor(capsys):
    code, out, err = run(capsys, "continue", *COULOMB, "--param", "zeta", "--from", "0", "--to", "0.1", "--monitor", "nonsense")
    assert code == 2 and "--monitor" in err
