"""``frictionflow map`` (cli/map.py): JSON, the xarray dataset and the chart; bad input refused before any work."""

from __future__ import annotations

import json
import math

import pytest

import frictionflow.cli.map  # noqa: F401  (registers the command wherever cli/__init__ does not yet)
from frictionflow.cli import main

STRIBECK = ["--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.01"]


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_map_writes_json_dataset_and_chart(capsys, tmp_path):
    import xarray as xr

    plot, data = tmp_path / "chart.png", tmp_path / "chart.nc"
    code, out, err = run(capsys, "map", *STRIBECK, "--x", "vb", "--x-from", "0.008", "--x-to", "0.02", "--x-points", "5",
                         "--y", "zeta", "--y-from", "0", "--y-to", "1", "--curves", "hopf,grazing", "--sweep", "4x3",
                         "--t-end", "100", "--heat", "TR_B", "--json", "--plot", str(plot), "--dataset", str(data))
    assert code == 0, err
    d = json.loads(out)
    kinds = {c["kind"]: c["points"] for c in d["curves"]}
    assert set(kinds) == {"hopf", "grazing"} and d["heat"] == "TR_B"
    for p in kinds["hopf"]:  # 2 zeta + F'(V_b) = 0 with F' derived by hand
        s = p["x"]
        assert p["y"] == pytest.approx(0.02 * s / 0.01**2 * math.exp(-((s / 0.01) ** 2)), rel=1e-12)
    assert [c["kind"] for c in d["codim2"]] == ["bautin"]
    assert plot.stat().st_size > 0
    ds = xr.open_dataset(data)
    assert "hopf_zeta" in ds and "sweep_TR_B" in ds and ds["sweep_TR_B"].shape == (4, 3)


@pytest.mark.parametrize("args, message", [
    (["--curves", "hopf,nonsense"], "--curves"),
    (["--sweep", "4by3"], "--overlay"),
    (["--plot", "chart.txt"], "--plot"),
    (["--x-points", "1"], "--x N"),
])
def test_map_refuses_bad_input(capsys, tmp_path, args, message):
    args = [a if not a.endswith(".txt") else str(tmp_path / a) for a in args]
    code, out, err = run(capsys, "map", *STRIBECK, "--x-from", "0.008", "--x-to", "0.02", "--y-from", "0", "--y-to", "1", *args)
    assert code == 2 and message in err
