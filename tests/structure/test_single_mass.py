"""One dof and N uncoupled masses against the single-mass exact solver (an independent closed-form engine)."""

from __future__ import annotations

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly
from tests.golden.cases import SIMULATE

from .builders import single_mass, uncoupled

CASES = [name for name in SIMULATE if name.startswith("coulomb_exact")]


def parse(args):
    """(model, law, x0, v0, t_end, dense_dt) of a golden command line."""
    opts = dict(zip(args[::2], args[1::2]))
    fd = float(opts["--fd"])
    law = ff.Coulomb(fd=fd, fs=float(opts.get("--fs", fd)), stick_force=opts.get("--stick-force", "resultant"))
    model = ff.BeltOscillator(zeta=float(opts["--zeta"]), vb=float(opts["--vb"]))
    x0, v0 = float(opts.get("--x0", fd)), float(opts.get("--v0", model.vb))
    dense = float(opts["--dense-dt"]) if "--dense-dt" in opts else None
    return model, law, x0, v0, float(opts["--t-end"]), dense


def single(name):
    model, law, x0, v0, t_end, dense = parse(SIMULATE[name])
    traj = ff.simulate(model, law, x0=x0, v0=v0, t_end=t_end)
    return model, law, x0, v0, t_end, dense, traj


def single_works(traj, idx):
    """(damper work, net friction work, heat) of the single mass at samples ``idx``, the structure's signs."""
    w = traj.work[idx]
    return -w[:, 0], w[:, 1] - w[:, 2], w[:, 3]


@pytest.mark.parametrize("name", CASES)
def test_one_dof_equals_the_single_mass(name):
    model, law, x0, v0, t_end, dense, traj = single(name)
    motion = run_assembly(single_mass(model.zeta, model.vb, law, x0, v0), t_end, dense_dt=dense)
    ev = traj.events["t"]
    assert len(motion.switches) == len(ev)
    np.testing.assert_allclose(motion.switches, ev, rtol=1e-12, atol=1e-13)
    idx = np.searchsorted(traj.t, ev)
    assert np.array_equal(traj.t[idx], ev)
    mine = np.searchsorted(motion.t, motion.switches)
    scale = np.abs(traj.state).max()
    np.testing.assert_allclose(motion.state[:, mine], traj.state[:, idx], rtol=0, atol=1e-12 * scale)
    np.testing.assert_array_equal(motion.modes[0, mine], np.sign(traj.modes[0, idx]))
    # works at every switch and at the end: damper, friction on the mass (belt input - heat), heat
    idx, mine = np.append(idx, len(traj.t) - 1), np.append(mine, len(motion.t) - 1)
    damper, friction, heat = single_works(traj, idx)
    size = np.abs(traj.work[-1]).sum()
    ch = {c: i for i, c in enumerate(motion.channels)}
    np.testing.assert_allclose(motion.work[ch["damper.0"], mine], damper, rtol=0, atol=1e-12 * size)
    net = motion.work[ch["contact.0.belt"], mine] - motion.work[ch["contact.0.heat"], mine]
    np.testing.assert_allclose(net, friction, rtol=0, atol=1e-12 * size)
    np.testing.assert_allclose(motion.work[ch["contact.0.heat"], mine], heat, rtol=0, atol=1e-12 * size)


@pytest.mark.parametrize("name", ["coulomb_exact", "coulomb_exact_spring", "coulomb_exact_undamped"])
def test_average_powers_over_a_window_equal_the_single_mass(name):
    """element_power between two arbitrary times (not samples) against the single mass's works there."""
    model, law, x0, v0, t_end, _, traj = single(name)
    motion = run_assembly(single_mass(model.zeta, model.vb, law, x0, v0), t_end)
    t0, t1 = 0.37 * t_end, 0.91 * t_end
    dense = traj.sample(1.0, start=t0, stop=t1)
    w = dense.work[-1] - dense.work[0]
    p = motion.element_power(t0, t1)
    size = np.abs(w).sum() / (t1 - t0)
    assert p["damper.0"]["P"] == pytest.approx(-w[0] / (t1 - t0), abs=1e-12 * size)
    assert p["contact.0"]["P_heat"] == pytest.approx(w[3] / (t1 - t0), abs=1e-12 * size)
    assert p["contact.0"]["P_belt"] - p["contact.0"]["P_heat"] == pytest.approx((w[1] - w[2]) / (t1 - t0),
                                                                               abs=1e-12 * size)
    x, v = traj.at(0.5 * (t0 + t1))
    np.testing.assert_allclose(motion.at(0.5 * (t0 + t1)), [x, v], rtol=0, atol=1e-12 * np.abs(traj.state).max())


@pytest.mark.parametrize("name", ["coulomb_exact", "coulomb_exact_x0v0"])
def test_uncoupled_identical_masses_each_equal_the_single_mass(name):
    model, law, x0, v0, t_end, _, traj = single(name)
    count = 3
    motion = run_assembly(uncoupled(count, model.zeta, model.vb, law, x0, v0), t_end)
    ev = traj.events["t"]
    for j in range(count):
        mine = motion.switches[motion.switch_contact == j]
        assert len(mine) == len(ev)
        np.testing.assert_allclose(mine, ev, rtol=1e-12, atol=1e-13)
    end = motion.state[:, -1]
    scale = np.abs(traj.state).max()
    np.testing.assert_allclose(end[:count], traj.x[-1], atol=1e-12 * scale, rtol=0)
    np.testing.assert_allclose(end[count:], traj.v[-1], atol=1e-12 * scale, rtol=0)
    size = np.abs(traj.work[-1]).sum()
    heat = motion.work[[motion.channels.index(f"contact.{j}.heat") for j in range(count)], -1]
    np.testing.assert_allclose(heat, traj.work[-1, 3], rtol=0, atol=1e-12 * size)
