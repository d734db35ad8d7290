"""``frictionflow simulate``: JSON keys, outputs, config files and bad input."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from frictionflow.cli import main

FAST = ["--t-end", "40", "--dt", "2e-3"]


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_has_the_documented_keys(capsys):
    code, out, err = run(capsys, "simulate", "--fd", "0.02", "--vb", "0.01", "--zeta", "0", "--json", *FAST)
    assert code == 0
    d = json.loads(out)  # exactly one JSON object on stdout
    assert {"params", "solver", "steady_state", "averages", "TR_B", "amplitude", "energy_residual"} <= d.keys()
    assert {"zeta", "vb", "fd", "fs", "vd"} <= d["params"].keys()
    assert {"kind", "period", "window", "stability", "stick_fraction"} <= d["steady_state"].keys()
    assert d["solver"]["name"] == "exact" and isinstance(d["events"], int)
    assert {"P_dv", "P_df", "P_fin", "R_c", "R_f", "P_belt", "P_heat"} <= d["averages"].keys()
    assert {"X_min", "X_max", "V_min", "V_max"} <= d["amplitude"].keys()
    assert d["steady_state"]["kind"] == "periodic"
    assert d["steady_state"]["period"] == pytest.approx(2 * np.pi, rel=1e-6)


def test_period_is_null_unless_periodic(capsys):
    # the paper's method sees a decaying spiral, slipping inside the certified disc about X* ...
    code, out, _ = run(capsys, "simulate", "--zeta", "0.01", "--solver", "rk4", "--json", *FAST)
    d = json.loads(out)
    assert d["steady_state"]["kind"] == "equilibrium"
    assert d["steady_state"]["period"] is None
    assert d["steady_state"]["decay_rate"] == pytest.approx(0.01, rel=1e-12)
    # ... a Stribeck spiral started outside its (smaller) certified disc is not settled yet, decaying
    code, out, _ = run(capsys, "simulate", "--friction", "stribeck", "--fs", "0.04", "--vs", "0.05", "--delta", "1",
                       "--vb", "0.12", "--zeta", "0.03", "--x0", "0.1168", "--v0", "0", "--json", "--t-end", "60")
    d = json.loads(out)
    assert d["steady_state"]["kind"] == "not_settled" and d["steady_state"]["period"] is None
    assert d["steady_state"]["decay_rate"] > 0
    # ... the exact solver (the default) knows the spiral never reaches the band again
    code, out, _ = run(capsys, "simulate", "--zeta", "0.01", "--json", *FAST)
    d = json.loads(out)
    assert d["steady_state"]["kind"] == "equilibrium" and d["steady_state"]["period"] is None
    assert d["steady_state"]["stability"] == "stable"
    assert d["steady_state"]["decay_rate"] == pytest.approx(0.01, rel=1e-12)
    assert d["averages"]["P_fin"] == 0.0 and d["TR_B"] == 1.0


def test_defaults_are_the_papers(capsys):
    code, out, _ = run(capsys, "simulate", "--json", *FAST)
    d = json.loads(out)
    assert d["params"]["vd"] == 1e-3 and d["params"]["fs"] == d["params"]["fd"]


def test_window_option_fixes_the_window(capsys):
    code, out, _ = run(capsys, "simulate", "--json", "--window", "10:30", *FAST)
    d = json.loads(out)
    assert d["steady_state"]["window"] == [10.0, 30.0]
    assert d["steady_state"]["manual_window"] is True


def test_config_file_equals_options(tmp_path, capsys):
    cfg = tmp_path / "run.toml"
    cfg.write_text('fd = 0.04\nvb = 0.01\nzeta = 0.0\nt_end = 40.0\ndt = 2e-3\nstick_force = "spring"\n')
    _, a, _ = run(capsys, "simulate", "--config", str(cfg), "--json")
    _, b, _ = run(capsys, "simulate", "--fd", "0.04", "--stick-force", "spring", "--json", *FAST)
    assert json.loads(a) == json.loads(b)
    # the command line overrides the file
    _, c, _ = run(capsys, "simulate", "--config", str(cfg), "--fd", "0.02", "--json")
    assert json.loads(c)["params"]["fd"] == 0.02


def test_dimensional_input_is_converted_and_reported(capsys):
    # m=1, k=4 -> omega0 = 2; c = 0.08 -> zeta = 0.02; v_b = 0.02 -> V_b = 0.01; f_d = 0.08 -> F_d = 0.02
    code, out, err = run(capsys, "simulate", "--dimensional", "m=1,c=0.08,k=4,v_b=0.02,f_d=0.08", "--json", *FAST)
    assert code == 0, err
    d = json.loads(out)
    assert d["params"]["zeta"] == pytest.approx(0.02)
    assert d["params"]["vb"] == pytest.approx(0.01)
    assert d["params"]["fd"] == pytest.approx(0.02)
    assert d["dimensional"]["omega0"] == pytest.approx(2.0)


@pytest.mark.parametrize("ext", [".csv", ".nc"])
def test_out_writes_the_trajectory(tmp_path, capsys, ext):
    path = tmp_path / f"traj{ext}"
    code, _, err = run(capsys, "simulate", "--solver", "rk4", "--out", str(path), "--record-every", "10", *FAST)
    assert code == 0, err
    if ext == ".nc":
        ds = xr.open_dataset(path)
        assert {"X", "V", "F_c", "mode", "W_dv", "W_fin", "W_fout", "W_heat"} <= set(ds.data_vars)
        assert ds["X"].attrs["long_name"].startswith("displacement")
        tau = ds["tau"].values
        ds.close()
    else:
        data = np.genfromtxt(path, delimiter=",", names=True)
        assert data.dtype.names[:4] == ("tau", "X", "V", "F_c")
        tau = data["tau"]
    # every 10th step, and (RK4 thinned) the steps around each section crossing and extreme
    steps = np.rint(tau / (40.0 / 20_000)).astype(int)
    assert set(range(0, 20_001, 10)) <= set(steps.tolist()) and len(tau) < 2 * (20_000 // 10 + 1)


def test_exact_out_is_sampled_densely(tmp_path, capsys):
    path = tmp_path / "traj.nc"
    code, _, err = run(capsys, "simulate", "--out", str(path), "--t-end", "40")
    assert code == 0, err
    with xr.open_dataset(path) as ds:
        assert ds.attrs["solver_name"] == "exact"
        assert np.max(np.diff(ds["tau"].values)) <= 2 * np.pi / 200 + 1e-12


@pytest.mark.parametrize("ext", [".png", ".pdf", ".svg"])
def test_plot_writes_a_figure(tmp_path, capsys, ext):
    path = tmp_path / f"fig{ext}"
    code, _, err = run(capsys, "simulate", "--plot", str(path), *FAST)
    assert code == 0, err
    assert path.stat().st_size > 1000


BAD = [
    (["--zeta", "-0.1"], "zeta"),
    (["--zeta", "nan"], "zeta"),
    (["--zeta", "inf"], "zeta"),
    (["--fd", "-0.02"], "fd"),
    (["--fd", "nan"], "fd"),
    (["--vd", "0"], "vd"),
    (["--vd", "-1e-3"], "vd"),
    (["--fd", "0.04", "--fs", "0.02"], "fs"),
    (["--dt", "0"], "dt"),
    (["--dt", "-1e-3"], "dt"),
    (["--t-end", "0"], "t_end"),
    (["--t-end", "-5"], "t_end"),
    (["--bogus", "1"], "--bogus"),
    (["--solver", "euler"], "solver"),
    (["--friction", "stribeck", "--solver", "exact"], "solver=exact"),
    (["--friction", "stribeck", "--vs", "0"], "vs"),
    (["--friction", "tanh"], "friction"),
    (["--stick-force", "both"], "stick_force"),
    (["--window", "30:10"], "window"),
    (["--fd", "abc"], "--fd"),
    (["--dimensional", "m=1,c=0.1"], "dimensional"),
    (["--out", "traj.txt"], "out"),
    (["--plot", "fig.jpg"], "plot"),
]


@pytest.mark.parametrize("args, name", BAD)
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys, monkeypatch, args, name):
    monkeypatch.chdir(tmp_path)
    # the bad option comes last so that it is the one in force
    code, out, err = run(capsys, "simulate", *FAST, "--out", "t.csv", "--plot", "f.png", *args)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and name in lines[0], err
    assert "Traceback" not in err and out == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "text, name",
    [
        ("fd = 0.02\nzeta = \n", "not valid TOML"),
        ("fd = 0.02\nbogus_key = 1\n", "bogus_key"),
        ('zeta = "abc"\n', "zeta"),
        ("zeta = -1.0\n", "zeta"),
        ("[dimensional]\nm = 1.0\n", "dimensional"),
    ],
)
def test_malformed_config(tmp_path, capsys, text, name):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text)
    code, out, err = run(capsys, "simulate", "--config", str(cfg))
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and name in err
    assert out == ""


def test_missing_config(tmp_path, capsys):
    code, _, err = run(capsys, "simulate", "--config", str(tmp_path / "none.toml"))
    assert code == 2 and "not found" in err


def test_coarse_step_warns_on_stderr(capsys):
    code, out, err = run(capsys, "simulate", "--solver", "rk4", "--vb", "0.1", "--dt", "0.05", "--t-end", "20", "--json")
    assert code == 0
    assert err.startswith("warning: dt=0.05") and "use dt <=" in err
    json.loads(out)


def test_console_script_exit_code_and_no_traceback():
    proc = subprocess.run(
        [sys.executable, "-m", "frictionflow", "simulate", "--zeta", "-1"], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 2
    assert proc.stderr.strip() == "error: zeta must be finite and in [0, 1000], got -1.0"
