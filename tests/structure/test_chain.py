"""A 3-mass chain with stick of some contacts while others slip: the phases against an independent integrator,
the energy balance per element, the exact evaluation between samples."""

from __future__ import annotations

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly

from .builders import chain
from .reference import check_phases

NODES, WEIGHTS = np.polynomial.legendre.leggauss(12)


@pytest.fixture(scope="module")
def motion():
    law = ff.Coulomb(fd=0.3, fs=0.4)
    asm = chain(3, law, belt=[0.1, 0.15, 0.05], q0=[0.3, 0.0, -0.2], v0=[0.0, 0.1, 0.0])
    return run_assembly(asm, 60.0)


def test_some_contacts_stick_while_others_slip(motion):
    mixed = [(0 in m) and np.any(m != 0) for m in motion.modes.T]
    assert sum(mixed) >= 3
    assert len(motion.switches) >= 10 and motion.status == "ok"


def test_phases_against_an_independent_integrator(motion):
    assert check_phases(motion, atol=1e-9) < 1.0


def test_energy_balance_closes_to_rounding(motion):
    assert motion.energy_residual < 1e-13


def _quadrature(motion, power):
    """int power(t, q, v) dt over the run: 12-point Gauss-Legendre on 16 pieces of each sample interval."""
    n, total = motion.n, 0.0
    for t0, t1 in zip(motion.t[:-1], motion.t[1:]):
        edges = np.linspace(t0, t1, 17)
        for a, b in zip(edges[:-1], edges[1:]):
            for x, w in zip(NODES, WEIGHTS):
                t = 0.5 * (a + b) + 0.5 * (b - a) * x
                y = motion.at(t)
                total += 0.5 * (b - a) * w * power(t, y[:n], y[n:])
    return total


def test_each_element_work_against_its_own_integral(motion):
    asm, n = motion.assembly, motion.n
    ch = {c: i for i, c in enumerate(motion.channels)}
    size = np.abs(motion.work[:, -1]).sum()
    q0, q1 = motion.state[:n, 0], motion.state[:n, -1]
    for s, (e, k) in enumerate(zip(asm.spring_dir, asm.spring_k)):  # a spring's work: -Delta k (e.q)^2 / 2
        assert motion.work[ch[f"spring.{s}"], -1] == pytest.approx(-0.5 * k * ((e @ q1) ** 2 - (e @ q0) ** 2),
                                                                    abs=1e-13 * size)
    e, c = asm.damper_dir[1], asm.damper_c[1]
    w = _quadrature(motion, lambda t, q, v: -c * (e @ v) ** 2)
    assert motion.work[ch["damper.1"], -1] == pytest.approx(w, abs=1e-12 * size)


def test_motion_at_a_sample_is_the_sample_and_between_continuous(motion):
    i = len(motion.t) // 2
    np.testing.assert_array_equal(motion.at(motion.t[i]), motion.state[:, i])
    t = motion.t[i + 1]
    np.testing.assert_allclose(motion.at(t - 1e-9)[:motion.n], motion.state[:motion.n, i + 1], atol=1e-8)
    ds = motion.to_xarray()
    assert list(ds["q"].dims) == ["time", "dof"] and list(ds.channel.values) == list(motion.channels)
    p = motion.element_power(10.0, 50.0)
    assert set(p) == {*(f"spring.{s}" for s in range(5)), *(f"damper.{d}" for d in range(3)),
                      *(f"contact.{j}" for j in range(3))}
