"""The belt's work (``dbelt``) of a law with internal state survives resampling: :meth:`Trajectory.dense`,
:meth:`Trajectory.sample`, the dataset and the command line's NetCDF file.

The references are derived here, independently of the resampling: at the
run's own samples the belt's work is the running sum of the increments the
solver recorded; between them it follows from the momentum balance of the
mass, X'' = F_c - X - 2 zeta X' on a belt at constant speed V_b, so that
int F_c V_b dtau = V_b (Delta X' + 2 zeta Delta X + int X dtau), with int X
a fine Simpson sum of the motion (no friction force in it).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import simpson

from frictionflow import BeltOscillator, RateState, simulate
from frictionflow.cli import main
from frictionflow.friction import LuGre

#: the QA report's run (rate-and-state, sparse samples: dense() adds points) and a LuGre stick-slip run
#: (the contact stores energy that comes and goes)
RUNS = {
    "rate_state": (BeltOscillator(0.0, 0.01), RateState(), 30.0),
    "lugre_stick_slip": (BeltOscillator(0.0, 0.05), LuGre(fd=0.2, fs=0.4, sigma0=1e3, sigma1=30.0), 40.0),
}


@pytest.fixture(scope="module", params=sorted(RUNS))
def run(request):
    model, law, t_end = RUNS[request.param]
    return simulate(model, law, t_end=t_end)


#: points per period of dense(): enough to add points between the stick-slip run's samples too
DENSE = 256


def _resampled(run, how):
    # sample() from an offset start: its points fall between the solver's samples, except by chance
    return run.dense(DENSE) if how == "dense" else run.sample(0.07, start=0.013)


def _belt_work_from_motion(run, t0, t1):
    """int F_c V_b over (t0, t1) from the motion alone (the momentum balance; see the module's docstring)."""
    tau = np.linspace(t0, t1, 20001)
    x, v = run.at(tau)
    return run.vb * (v[-1] - v[0] + 2.0 * run.zeta * (x[-1] - x[0]) + simpson(x, x=tau))


@pytest.mark.parametrize("how", ["dense", "sample"])
def test_resampled_runs_balance_the_interface(run, how):
    out = _resampled(run, how)
    assert out.dbelt is not None and out.dbelt.shape == out.t.shape
    scale = run.interface_balance().belt
    for i1 in (len(out.t) // 3, len(out.t) // 2 + 1, -1):  # windows ending on added points and on samples
        bal = out.interface_balance(0, i1)
        assert abs(bal.residual) < 1e-9 * scale, (i1, bal)


def test_dense_keeps_the_recorded_belt_work_at_the_samples(run):
    out = run.dense(DENSE)
    assert out.recorded is not None and not out.recorded.all()  # points were added between the samples
    np.testing.assert_allclose(np.cumsum(out.dbelt)[out.recorded], np.cumsum(run.dbelt), rtol=1e-12, atol=1e-15)


def test_sampled_belt_work_follows_the_motion(run):
    out = _resampled(run, "sample")
    w_belt = np.cumsum(out.dbelt)
    for i in (len(out.t) // 4, len(out.t) // 2, len(out.t) - 1):
        expected = _belt_work_from_motion(run, out.t[0], out.t[i])
        assert w_belt[i] == pytest.approx(expected, rel=1e-6, abs=1e-9 * abs(w_belt[-1]))


def test_the_dense_dataset_has_the_belt_work(run):
    ds = run.to_xarray(points_per_period=DENSE)
    samples = ds.where(ds["is_sample"], drop=True)
    np.testing.assert_allclose(samples["W_belt"].values, np.cumsum(run.dbelt), rtol=1e-12, atol=1e-15)


def test_the_command_lines_netcdf_file_has_the_belt_work(tmp_path, capsys):
    nc, csv = tmp_path / "r.nc", tmp_path / "r.csv"
    for out in (nc, csv):
        assert main(["simulate", "--friction", "rate_state", "--t-end", "30", "--out", str(out)]) == 0
    capsys.readouterr()
    with xr.open_dataset(nc) as ds:
        ds = ds.load()
    rows = np.genfromtxt(csv, delimiter=",", names=True)
    samples = ds.where(ds["is_sample"], drop=True)
    np.testing.assert_allclose(samples["tau"].values, rows["tau"], rtol=0, atol=0)
    np.testing.assert_allclose(samples["W_belt"].values, rows["W_belt"], rtol=1e-12, atol=1e-15)
    assert ds["W_belt"].attrs["long_name"].startswith("cumulative work of the belt")
