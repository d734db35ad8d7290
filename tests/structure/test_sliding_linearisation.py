"""Random structures sliding steadily: the exact engine's motion is the stability analysis's linearisation.

With Coulomb contacts whose normal loads follow q (N = P + n.q, the mode-coupling mechanism) every contact that
keeps slipping adds a linear force, so a run started near steady sliding is y* + expm(A t) d0 exactly while no
contact sticks: ``steady_sliding`` (its own assembly of K_eff and C_eff, the path of ``stability``) against
``run_assembly`` (the engine's combination of modes), with scipy's ``expm`` between them.  Random masses (full
or diagonal), angled contacts, up to three dof and three contacts.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from frictionflow import Coulomb
from frictionflow.analysis.stability import NoSteadySliding, steady_sliding
from frictionflow.solvers.structure import run_assembly

from .builders import assembly


def _random_structure(rng: np.random.Generator):
    n = int(rng.integers(1, 4))
    e = np.eye(n)
    if rng.random() < 0.3:
        a = rng.normal(size=(n, n))
        mass = a @ a.T + n * np.eye(n)
    else:
        mass = rng.uniform(0.5, 2.0, n)
    springs = [(e[i], rng.uniform(0.3, 3.0)) for i in range(n)]
    springs += [(e[i] - e[i + 1], rng.uniform(0.1, 1.0)) for i in range(n - 1)]
    dampers = [(e[i], rng.choice([0.0, rng.uniform(0.0, 0.2)])) for i in range(n)]
    contacts = []
    for j in range(int(rng.integers(1, n + 1))):
        direction = e[j] if rng.random() < 0.6 else rng.normal(size=n)
        fd = rng.uniform(0.2, 0.6)
        normal = [1.0, *(rng.uniform(-0.6, 0.6, n) * (rng.random() < 0.7))]
        belt = rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 2.0)
        contacts.append((direction, belt, Coulomb(fd, fd * rng.uniform(1.0, 1.5)).kernel_params(), normal))
    return assembly(mass, springs=springs, dampers=dampers, contacts=contacts)


@pytest.mark.parametrize("seed", range(12))
def test_a_run_near_steady_sliding_is_the_linearisation_s_flow(seed):
    rng = np.random.default_rng(seed)
    asm = _random_structure(rng)
    try:
        slide = steady_sliding(asm)
    except NoSteadySliding:  # K_eff singular or a load <= 0 there: nothing to compare
        pytest.skip("no steady sliding")
    n = len(asm.q0)
    y_star = np.concatenate((slide.q, np.zeros(n)))
    d0 = 1e-4 * rng.normal(size=2 * n)
    growth = float(np.max(slide.eigenvalues.real))
    t_end = min(60.0, 8.0 / max(abs(growth), 1e-3))
    motion = run_assembly(asm._replace(q0=y_star[:n] + d0[:n], v0=d0[n:]), t_end, dense_dt=t_end / 50)
    assert len(motion.switches) == 0 and motion.status == "ok"  # belts fast enough: every contact keeps slipping
    linear = np.stack([y_star + expm(slide.jacobian * t) @ d0 for t in motion.t], axis=1)
    scale = np.abs(y_star).max() + np.abs(d0).max()
    assert np.abs(motion.state - linear).max() <= 1e-13 * scale  # measured up to 8e-15 of it over 40 seeds
