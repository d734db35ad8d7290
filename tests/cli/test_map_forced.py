"""``frictionflow map`` for the forced system (--x/--y among omega, fex): JSON, dataset, chart; bad input refused."""

from __future__ import annotations

import json

import pytest

import frictionflow.cli.map  # noqa: F401  (registers the command wherever cli/__init__ does not yet)
from frictionflow import BeltOscillator, Coulomb
from frictionflow.cli import main
from frictionflow.orbits.forced import continue_forced, find_forced_orbit

COULOMB = ["--friction", "coulomb", "--fd", "0.5", "--fs", "1.0", "--zeta", "0.05", "--vb", "0.1"]
PLANE = ["--x", "omega", "--x-from", "1.8", "--x-to", "1.6", "--y", "fex", "--y-from", "0.5", "--y-to", "0.45"]


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_forced_map_writes_json_dataset_and_chart(capsys, tmp_path):
    import xarray as xr

    plot, data = tmp_path / "chart.png", tmp_path / "chart.nc"
    code, out, err = run(capsys, "map", *COULOMB, *PLANE, "--y-points", "1", "--m", "2", "--sweep", "3x2",
                         "--t-end", "60", "--heat", "TR_B", "--json", "--plot", str(plot), "--dataset", str(data))
    assert code == 0, err
    d = json.loads(out)
    assert d["continued_in"] == "omega" and d["heat"] == "TR_B"
    (pd,) = [c for c in d["curves"] if c["kind"] == "period_doubling"]
    assert pd["m"] == 2 and len(pd["points"]) == 1
    # the same point from the API: the period-2 orbit continued from Omega = 1.8 down
    model = BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.8)
    o = find_forced_orbit(model, Coulomb(0.5, 1.0), 2)
    (ev,) = continue_forced(model, Coulomb(0.5, 1.0), "omega", 1.8, 1.6, m=2, orbit=o).events_of("period_doubling")
    assert pd["points"][0]["x"] == pytest.approx(ev.lam, abs=1e-9) and pd["points"][0]["y"] == 0.5
    assert plot.stat().st_size > 0
    ds = xr.open_dataset(data)
    assert float(ds["period_doubling_m2_omega"].values[0, 0]) == pytest.approx(ev.lam, abs=1e-9)
    assert ds["sweep_TR_B"].shape == (3, 2)


@pytest.mark.parametrize("args, message", [
    (["--x", "omega", "--y", "zeta"], "--y"),
    (["--x", "fex", "--y", "fex"], "--y"),
    (["--x", "omega", "--y", "fex", "--curves", "hopf"], "--curves"),
    (["--x", "omega", "--y", "fex", "--m", "0"], "--m"),
    (["--x", "omega", "--y", "fex", "--y-points", "0"], "--y fex: N must be >= 1"),
    (["--x", "omega", "--y", "fex", "--x-to", "-1"], "--x: omega must be finite and > 0"),
    (["--x", "omega", "--y", "fex", "--friction", "karnopp"], "--friction"),
])
def test_forced_map_refuses_bad_input(capsys, args, message):
    base = ["--x-from", "1.8", "--x-to", "1.6", "--y-from", "0.4", "--y-to", "0.5"]
    given = dict(zip(base[::2], base[1::2]))
    for flag, value in zip(args[::2], args[1::2]):
        given[flag] = value
    code, out, err = run(capsys, "map", *COULOMB, *[t for kv in given.items() for t in kv])
    assert code == 2 and message in err
    assert len(err.strip().splitlines()) == 1
