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


# -- the batched forced points (exact solver) against simulate + analyze, point by point ----------

def _reference(settings: dict, point: dict) -> dict:
    """simulate + analyze of one point of a sweep, as a user would run it."""
    from frictionflow import BeltOscillator, analyze, simulate
    from frictionflow.friction.registry import law_class
    from frictionflow.solvers.exact import Exact

    values = {**settings, **point}
    law = law_class(values["friction"])(values["fd"], values["fs"], stick_force=values.get("stick_force", "resultant"))
    model = BeltOscillator(zeta=values["zeta"], vb=values["vb"], fex=values["fex"], omega=values["omega"],
                           phi=values.get("phi", 0.0))
    traj = simulate(model, law, Exact(), t_end=values["t_end"], x0=law.fd, v0=model.vb)
    return analyze(traj).quantities()


def _grid_agrees(settings: dict, grid: dict) -> list[dict]:
    """Each point of the forced sweep chunk against its reference: every swept quantity; returns the references."""
    from frictionflow.sweep.compute import VARIABLES, compute_chunk

    axes = list(grid)
    shape = tuple(len(grid[a]) for a in axes)
    out = compute_chunk({"settings": settings, "grid": grid}, (0,) * len(shape), shape)
    refs = []
    for index in np.ndindex(*shape):
        point = {a: grid[a][i] for a, i in zip(axes, index)}
        want = _reference(settings, point)
        refs.append(want)
        for i, (name, _, _) in enumerate(VARIABLES):
            got, ref = float(out[(i, *index)]), want[name]
            if math.isnan(ref):
                assert math.isnan(got), (point, name, got)
            elif name == "kind":
                assert got == ref, (point, got, ref)
            else:
                assert got == pytest.approx(ref, rel=1e-9, abs=1e-15 if name == "energy_residual" else 0.0), (point, name)
    return refs


def test_batched_forced_points_agree_with_simulate_and_analyze():
    """Stick-slip and pure slip, harmonic and subharmonic responses, undamped (zeta = 0, Omega != 1), unforced points
    of the same sweep, and sections that do not repeat (decided by the Lyapunov exponent): each the reference's."""
    from frictionflow.quantities import KINDS

    coulomb = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "vb": 0.01, "t_end": 300.0, "phi": 0.3}
    refs = _grid_agrees(coulomb, {"omega": [0.7, 1.4, 2.3], "zeta": [0.0, 0.01, 0.05], "fex": [0.0, 0.02, 0.05]})
    # pure slip (the belt outruns every motion) and a chaotic point (lyapunov_exponents' doctest)
    refs += _grid_agrees({**coulomb, "vb": 0.3, "zeta": 0.1}, {"omega": [0.8, 1.2], "fex": [0.05]})
    refs += _grid_agrees({"friction": "coulomb", "fd": 0.5, "fs": 1.0, "vb": 0.1, "zeta": 0.01, "t_end": 300.0},
                         {"omega": [1.0], "fex": [0.5]})
    kinds = {KINDS[int(r["kind"])] for r in refs}
    assert {"periodic", "not_settled", "chaotic"} <= kinds, kinds
    periodic = [r for r in refs if KINDS[int(r["kind"])] == "periodic"]
    assert any(r["stick_fraction"] > 0 for r in periodic) and any(r["stick_fraction"] == 0 for r in periodic)
    multiples = {round(r["period"] * w / (2 * math.pi)) for r in periodic for w in [0.7, 1.4, 2.3, 0.8, 1.2]
                 if abs(r["period"] * w / (2 * math.pi) - round(r["period"] * w / (2 * math.pi))) < 1e-9}
    assert max(multiples) > 1  # a subharmonic among them


def test_batched_forced_points_with_the_band_law_agree():
    """Karnopp's band (no tangent kernel): a section that does not repeat is not settled, as analyze says."""
    karnopp = {"friction": "karnopp", "fd": 0.02, "fs": 0.04, "vb": 0.01, "t_end": 300.0}
    _grid_agrees(karnopp, {"omega": [0.7, 1.4], "zeta": [0.0, 0.05], "fex": [0.05]})
