"""Harmonic forces: the forced single mass's exact solver, uncoupled forced masses, a coupled forced 2-mass chain
against the independent phase integrator, and forcing at a natural frequency (resonance)."""

from __future__ import annotations

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly

from .builders import assembly, chain, single_mass
from .reference import check_phases

FORCED = [  # (zeta, vb, fd, fs, fex, omega, phi)
    (0.05, 0.01, 0.02, 0.04, 0.03, 0.8, 0.3),
    (0.0, 0.05, 0.02, 0.04, 0.01, 1.3, 0.0),
]


def single_forced(zeta, vb, fd, fs, fex, omega, phi, t_end):
    law = ff.Coulomb(fd=fd, fs=fs)
    traj = ff.simulate(ff.BeltOscillator(zeta=zeta, vb=vb, fex=fex, omega=omega, phi=phi), law, x0=fd, v0=vb,
                       t_end=t_end)
    return law, traj


@pytest.mark.parametrize("case", FORCED)
def test_forced_one_dof_equals_the_forced_single_mass(case):
    zeta, vb, fd, fs, fex, omega, phi = case
    law, traj = single_forced(*case, t_end=150.0)
    motion = run_assembly(single_mass(zeta, vb, law, fd, vb, force=(fex, omega, phi)), 150.0)
    ev = traj.events["t"]
    assert len(ev) > 4 and len(motion.switches) == len(ev)
    np.testing.assert_allclose(motion.switches, ev, rtol=1e-12, atol=1e-13)
    scale = np.abs(traj.state).max()
    np.testing.assert_allclose(motion.state[:, -1], traj.state[:, -1], rtol=0, atol=1e-12 * scale)
    size = np.abs(traj.work[-1]).sum()
    ch = motion.channels.index("force.0")
    assert motion.work[ch, -1] == pytest.approx(traj.work[-1, 4], abs=1e-12 * size)
    assert motion.energy_residual < 1e-13


def test_two_uncoupled_forced_masses_each_equal_their_single_mass():
    law = ff.Coulomb(fd=0.02, fs=0.04)
    (z, vb, fd, fs, fex, om, phi), (z2, vb2, _, _, fex2, om2, phi2) = FORCED[0], (0.05, 0.01, 0, 0, 0.02, 1.1, 1.0)
    eye = np.eye(2)
    p = law.kernel_params()
    asm = assembly([1.0, 1.0], springs=[(e, 1.0) for e in eye], dampers=[(e, 2 * z) for e in eye],
                   contacts=[(e, vb, p, None) for e in eye], forces=[(eye[0], fex, om, phi), (eye[1], fex2, om2, phi2)],
                   q0=[fd, fd], v0=[vb, vb])
    motion = run_assembly(asm, 100.0)
    for j, (a, w, ph) in enumerate([(fex, om, phi), (fex2, om2, phi2)]):
        _, traj = single_forced(z, vb, fd, fs, a, w, ph, 100.0)
        np.testing.assert_allclose(motion.switches[motion.switch_contact == j], traj.events["t"], rtol=1e-12,
                                   atol=1e-13)
        np.testing.assert_allclose(motion.state[[j, 2 + j], -1], traj.state[:, -1], rtol=0,
                                   atol=1e-12 * np.abs(traj.state).max())


def test_a_forced_coupled_chain_against_the_independent_integrator():
    law = ff.Coulomb(fd=0.3, fs=0.4)
    asm = chain(2, law, belt=[0.1, 0.05], q0=[0.2, -0.1], forces=[([0.0, 1.0], 0.25, 0.9, 0.4)])
    motion = run_assembly(asm, 60.0)
    assert len(motion.switches) >= 6 and any((0 in m) and np.any(m != 0) for m in motion.modes.T)
    assert check_phases(motion, atol=1e-9) < 1.0
    assert motion.energy_residual < 1e-13


def test_forcing_at_the_natural_frequency_grows_linearly():
    """Undamped, always slipping: x = F_d + (x0 - F_d) cos t + (A / 2) t sin t (resonance, no cosine denominator)."""
    fd, amp = 0.02, 0.01
    law = ff.Coulomb(fd=fd, fs=0.04)
    motion = run_assembly(single_mass(0.0, 10.0, law, 0.5, 0.0, force=(amp, 1.0, 0.0)), 30.0, dense_dt=0.7)
    t = motion.t
    x = fd + (0.5 - fd) * np.cos(t) + 0.5 * amp * t * np.sin(t)
    np.testing.assert_allclose(motion.state[0], x, rtol=0, atol=1e-13)
    assert motion.energy_residual < 1e-13
