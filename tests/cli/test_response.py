"""``frictionflow response``: outputs and bad input."""

from __future__ import annotations

import json

import pytest
import xarray as xr

from frictionflow.cli import main
from frictionflow.quantities import KINDS

BASE = ["response", "--fex", "0.3", "--zeta", "0.1", "--vb", "0", "--friction", "karnopp", "--fd", "0.05",
        "--solver", "rk4", "--dt", "5e-3", "--periods", "20"]


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_dataset_and_figure(capsys, tmp_path):
    code, out, _ = run(capsys, *BASE, "--omega", "0.8:1.2:3", "--json", "--out", str(tmp_path / "r.nc"),
                       "--plot", str(tmp_path / "r.png"))
    assert code == 0
    d = json.loads(out)
    assert d["omega"] == pytest.approx([0.8, 1.0, 1.2])
    assert set(d) == {"params", "omega", "kinds", "up", "down"}
    assert d["kinds"] == list(KINDS) and d["kinds"][d["up"]["kind"][0]] == "periodic"  # the codes' legend
    assert len(d["up"]["amplitude"]) == 3 and "P_ex" in d["down"]
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        assert ds.sizes == {"direction": 2, "omega": 3}
        assert ds["amplitude"].values.tolist() == [d["up"]["amplitude"], d["down"]["amplitude"]]
    assert (tmp_path / "r.png").stat().st_size > 0


@pytest.mark.parametrize("args, message", [
    (["--omega", "1:2"], "--vary omega must be FROM:TO:N"),
    (["--omega", "2:1:5"], "omega must be increasing"),
    (["--omega", "0.5:1:3", "--direction", "left"], "--direction"),
    (["--omega", "0.5:1:3", "--out", "r.txt"], "--out"),
])
def test_bad_input_exits_2_and_writes_nothing(capsys, tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, *BASE, *args)
    assert code == 2 and message in err and out == ""
    assert list(tmp_path.iterdir()) == []


def test_unforced_is_refused(capsys):
    code, _, err = run(capsys, "response", "--omega", "0.5:1:3", "--solver", "rk4")
    assert code == 2 and "fex must be > 0" in err


def test_an_end_out_of_range_is_named_as_typed(capsys):
    """omega=0.5:2000:5 was refused for the grid point 1000.25, a value the user never typed."""
    code, out, err = run(capsys, "response", "--fex", "0.1", "--vary", "omega=0.5:2000:5", "--json")
    assert code == 2 and out == "" and err.strip() == "error: --vary TO: omega must be finite and in (0, 1000], got 2000.0"


@pytest.mark.parametrize("periods", ["7", "100000000"])
def test_periods_out_of_range_is_named_before_the_estimate(capsys, tmp_path, periods):
    """--periods 1e8 was answered by the time estimate (a refusal about time, not about the option)."""
    code, out, err = run(capsys, "response", "--fex", "0.1", "--vary", "omega=0.5:1.5:1000", "--periods", periods,
                         "--out", str(tmp_path / "r.nc"))
    assert code == 2 and out == ""
    assert err.strip() == f"error: --periods must be an integer in [8, 1000000], got {periods}"
    assert list(tmp_path.iterdir()) == []


def test_periods_range_is_in_the_help(capsys):
    code, out, _ = run(capsys, "response", "--help")
    assert code == 0 and "in [8," in " ".join(out.split())
