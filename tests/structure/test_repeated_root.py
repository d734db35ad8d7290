"""A mode combination with a repeated root: refused by the exact engine, run by ``solver="auto"`` on the adaptive one.

A critically damped mode has a double root and one eigenvector: the exact engine's eigen-decomposition returned
two roots ~sqrt(EPS) apart and a basis of condition ~4e7, and the run went on ~1e-8 off.  A one-dof model at
zeta = 1 ended 1.1e-9 from its rest position (the single mass's own solver, which has a closed form for zeta =
1, to rounding), and its velocity at t = 30 came out +9.3e-10 where it is -1.97e-12.  Two equal undamped modes
coupled through a normal load (a Jordan block) were refused with a line blaming a spring's "rate 1 (alone)
beside its slowest rate 1".
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import xarray as xr
from scipy.optimize import brentq

import frictionflow as ff
from frictionflow.analysis.structure import analyze_structure
from frictionflow.orbits import find_structure_orbit
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import System

from ..cli.processes import in_process, one_line

REFUSED = "a combination of contact modes has a repeated root"


def _one_dof(c: float) -> System:
    """m = k = 1, damper c, a Coulomb contact (F_d 0.3, F_s 0.4) on a belt at 0.1, from x = 1 at rest."""
    return System.from_dict({"dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}],
                             "damper": [{"on": {"x": 1.0}, "c": c}],
                             "contact": [{"on": {"x": 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.3, "fs": 0.4}],
                             "initial": {"q": {"x": 1.0}}}, source=None)


def _single_mass(zeta: float) -> ff.Trajectory:
    return ff.simulate(ff.BeltOscillator(zeta=zeta, vb=0.1), ff.Coulomb(fd=0.3, fs=0.4), t_end=40.0, x0=1.0, v0=0.0)


TIMES = (1.0, 5.0, 10.0, 20.0, 30.0)


def test_a_critically_damped_mode_is_refused_by_the_exact_engine_and_run_by_auto():
    system = _one_dof(2.0)
    with pytest.raises(ValueError, match=f"solver=exact: {REFUSED} .*; use solver=adaptive"):
        simulate_system(system, 40.0)
    with pytest.warns(UserWarning, match="solver=auto ran the model with solver=adaptive"):
        motion = simulate_system(system, 40.0, solver="auto")
    assert motion.solver == "adaptive"
    reference = _single_mass(1.0)  # the single mass's exact solver: zeta = 1 in closed form
    for t in TIMES:
        assert np.allclose(motion.at(t), reference.at(t), rtol=0.0, atol=1e-9), t


def test_a_mode_near_critical_damping_stays_on_the_exact_engine_and_agrees_with_the_single_mass():
    """zeta = 1 + 1e-6 and 1 - 1e-6: two roots 2.8e-3 apart, a basis of condition ~700 -- the exact engine's."""
    for zeta in (1.0 + 1e-6, 1.0 - 1e-6):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            motion = simulate_system(_one_dof(2.0 * zeta), 40.0, solver="auto")
        assert motion.solver == "exact"
        reference = _single_mass(zeta)
        for t in TIMES:
            assert np.allclose(motion.at(t), reference.at(t), rtol=0.0, atol=1e-12), (zeta, t)


#: x1 on a belt, its normal load 1 - 2 x2; x2 undamped at the same natural frequency, forced at it (resonance)
JORDAN = {"dof": ["x1", "x2"], "mass": [1.0, 1.0],
          "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x2": 1.0}, "k": 1.0}],
          "contact": [{"on": {"x1": 1.0}, "belt": 0.5, "friction": "coulomb", "fd": 0.3, "fs": 0.4,
                       "normal": {"preload": 1.0, "x2": -2.0}}],
          "force": [{"on": {"x2": 1.0}, "amplitude": 0.2, "omega": 1.0}]}


def test_equal_modes_coupled_through_a_normal_load_are_said_to_have_a_repeated_root(tmp_path):
    """x1 slipping feels -F_d (1 - 2 x2): K_eff = [[1, -0.6], [0, 1]], a Jordan block.  x2 = 0.1 t sin t (the
    resonance from rest), so the load 1 - 0.2 t sin t first reaches zero where t sin t = 5."""
    system = System.from_dict(JORDAN, source=None)
    with pytest.raises(ValueError, match=f"solver=exact: {REFUSED}"):
        simulate_system(system, 20.0)
    with pytest.warns(UserWarning, match="solver=auto ran the model with solver=adaptive"):
        motion = simulate_system(system, 20.0, solver="auto")
    contact, t_lost = motion.lost
    assert contact == "contact.0"
    assert t_lost == pytest.approx(brentq(lambda t: t * math.sin(t) - 5.0, 6.5, 7.5, xtol=1e-14), abs=1e-9)
    path = tmp_path / "jordan.toml"
    path.write_text('dof = ["x1", "x2"]\nmass = [1.0, 1.0]\n[[spring]]\non = { x1 = 1.0 }\nk = 1.0\n[[spring]]\n'
                    'on = { x2 = 1.0 }\nk = 1.0\n[[contact]]\non = { x1 = 1.0 }\nbelt = 0.5\nfriction = "coulomb"\n'
                    'fd = 0.3\nfs = 0.4\nnormal = { preload = 1.0, x2 = -2.0 }\n[[force]]\non = { x2 = 1.0 }\n'
                    'amplitude = 0.2\nomega = 1.0\n')
    code, out, err, _ = in_process("simulate", "--model", str(path), "--solver", "exact", "--json")
    assert code == 2 and out == ""
    one_line(err, REFUSED, "use solver=adaptive")
    code, out, err, _ = in_process("simulate", "--model", str(path), "--t-end", "20", "--json")
    assert code == 0 and '"contact_lost"' in out and err.startswith("warning: solver=auto ran the model with")


def test_an_orbit_through_a_repeated_root_is_refused_in_orbit_terms():
    with pytest.raises(ValueError, match=f"orbits follow the exact engine's phases: {REFUSED}.*simulate runs it "
                                         "with solver=adaptive"):
        find_structure_orbit(_one_dof(2.0), t_transient=20.0)


def test_a_sweep_point_at_critical_damping_is_the_simulate_run(tmp_path):
    """A model sweep's point runs as ``simulate --model`` there (auto): across c = 2 a sweep stopped at that
    point (the exact engine's refusal); it now takes the adaptive run, the same numbers as simulate's."""
    model = tmp_path / "one.toml"
    model.write_text('dof = ["x"]\nmass = [1.0]\n[[spring]]\non = { x = 1.0 }\nk = 1.0\n[[damper]]\non = { x = 1.0 }\n'
                     'c = 1.0\n[[contact]]\non = { x = 1.0 }\nbelt = 0.1\nfriction = "coulomb"\nfd = 0.3\nfs = 0.4\n'
                     '[initial]\nq = { x = 1.0 }\n')
    config = tmp_path / "sweep.toml"
    config.write_text(f'model = "{model}"\nt_end = 12.0\n[grid]\n"damper.0.c" = [1.5, 2.0]\n')
    code, _, err, _ = in_process("sweep", str(config), "--out", str(tmp_path / "s.zarr"))
    assert code == 0, err
    ds = xr.open_zarr(tmp_path / "s.zarr")
    point = ds.sel({"damper.0.c": 2.0})
    with pytest.warns(UserWarning, match="solver=auto"):
        motion = simulate_system(_one_dof(2.0), 12.0, solver="auto")
    run = analyze_structure(motion)
    assert float(point["X_max"].sel(dof="x")) == run.amplitude["X_max"]["x"]
    assert float(point["X_min"].sel(dof="x")) == run.amplitude["X_min"]["x"]
    assert float(point["energy_residual"]) == run.energy_residual
    # each point says which solver ran it (the dataset's attribute gave the base model's, exact, for both)
    meanings = ds["solver"].attrs["flag_meanings"].split()
    ran = [meanings[int(code)] for code in ds["solver"].values]
    assert ran == ["exact", "adaptive"] and ds.attrs["solver"] == "exact"


def test_equal_roots_of_independent_modes_beside_a_stiff_damper_stay_on_the_exact_engine():
    """x2 and x3 are equal undamped oscillators (the same roots +-i, independent modes) beside a damper of 1e8 on
    x1 (roots -1e-8 and -1e8): equal roots, not a repeated root.  x3 and x1's creep are the closed forms'."""
    system = System.from_dict({
        "dof": ["x1", "x2", "x3"], "mass": [1.0, 1.0, 1.0],
        "spring": [{"on": {d: 1.0}, "k": 1.0} for d in ("x1", "x2", "x3")],
        "damper": [{"on": {"x1": 1.0}, "c": 1e8}],
        "contact": [{"on": {"x2": 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.2, "fs": 0.3}],
        "initial": {"q": {"x1": 0.2, "x2": 0.5, "x3": 0.3}}}, source=None)
    exact = simulate_system(system, 20.0)
    assert exact.solver == "exact" and len(exact.switches) > 4
    x3 = 0.3 * np.cos(20.0)  # x3 is a free undamped oscillator
    assert exact.at(20.0)[2] == pytest.approx(x3, abs=1e-12)
    assert exact.at(20.0)[0] == pytest.approx(0.2 * math.exp(-20.0 / 1e8), rel=1e-6)  # x1 creeps at k / c
