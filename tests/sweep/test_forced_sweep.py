"""Sweeps over the external force's parameters: each forced point is judged on the stroboscopic section."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow.sweep import run_sweep

ZETA = 0.1


def test_linear_oscillator_sweep_in_fex_and_omega_matches_the_closed_form(tmp_path):
    fex, omega = [0.2, 0.5], [0.7, 1.3]
    spec = {"friction": "karnopp", "fd": 0.0, "fs": 0.0, "zeta": ZETA, "vb": 0.0, "x0": 0.0, "v0": 0.0,
            "solver": "rk4", "dt": 1e-2, "t_end": 300.0, "grid": {"fex": fex, "omega": omega}}
    with pytest.warns(UserWarning):  # a step coarse for a band no motion reaches
        ds = run_sweep(spec, tmp_path / "forced.zarr").load()
    assert ds["kind"].dims == ("fex", "omega")
    for i, f in enumerate(fex):
        for j, w in enumerate(omega):
            pt = ds.isel(fex=i, omega=j)
            a = f / math.hypot(1 - w * w, 2 * ZETA * w)
            assert int(pt["kind"]) == 0
            assert float(pt["period"]) == pytest.approx(2 * math.pi / w, rel=1e-12)
            assert float(pt["P_dv"]) == pytest.approx(ZETA * w * w * a * a, rel=1e-5)
            assert float(pt["TR_B"]) == pytest.approx(a * math.hypot(1, 2 * ZETA * w) / f, rel=1e-4)
            assert 0.5 * float(pt["X_max"] - pt["X_min"]) == pytest.approx(a, rel=1e-5)


def test_an_omega_axis_without_forcing_is_the_autonomous_system(tmp_path):
    base = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "vb": 0.01, "t_end": 300.0}
    forced_path = run_sweep({**base, "zeta": 0.05, "grid": {"omega": [0.5, 2.0]}}, tmp_path / "a.zarr").load()
    batched = run_sweep({**base, "grid": {"zeta": [0.05]}}, tmp_path / "b.zarr").load()
    for name in ("kind", "period", "P_dv", "TR_B"):
        values = forced_path[name].values
        assert np.all(values == values[0])  # Omega means nothing without F_ex
        assert values[0] == pytest.approx(float(batched[name].values[0]), rel=1e-9, nan_ok=True), name


def test_a_grid_touching_undamped_resonance_is_refused_before_any_work(tmp_path):
    spec = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "fex": 0.1, "t_end": 50.0,
            "grid": {"zeta": [0.0, 0.05], "omega": [0.5, 1.0]}}
    with pytest.raises(ValueError, match="undamped resonance"):
        run_sweep(spec, tmp_path / "r.zarr")
    assert not (tmp_path / "r.zarr").exists()
