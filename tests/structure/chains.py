"""Hand-built :class:`~frictionflow.core.assembly.Assembly` records for the reference's tests and the benchmark.

Built from the element lists with numpy (K = sum k e e^T, C = sum c e e^T), not
by the model layer, so that the reference and the engine's tests do not rest
on the code under test.
"""

from __future__ import annotations

from typing import NamedTuple, Sequence

import numpy as np

from frictionflow import Coulomb
from frictionflow.core.assembly import Assembly


class Elements(NamedTuple):
    """A structure's elements: directions (one per row) and their constants."""

    mass: np.ndarray
    springs: tuple  # (directions (s, n), k (s,))
    dampers: tuple  # (directions (d, n), c (d,))
    contacts: tuple  # (directions (k, n), belt (k,), laws: sequence of Coulomb, normal (k, n + 1) or None)
    forces: tuple | None = None  # (directions (m, n), amplitude, omega, phi)
    q0: Sequence[float] | None = None
    v0: Sequence[float] | None = None


def build(el: Elements) -> Assembly:
    """The record of ``el``, every array float64."""
    mass = np.atleast_2d(np.asarray(el.mass, dtype=float))
    n = mass.shape[0]
    sd, sk = (np.asarray(a, dtype=float).reshape(-1, n) if i == 0 else np.asarray(a, dtype=float)
              for i, a in enumerate(el.springs))
    dd, dc = (np.asarray(a, dtype=float).reshape(-1, n) if i == 0 else np.asarray(a, dtype=float)
              for i, a in enumerate(el.dampers))
    cd, belt, laws, normal = el.contacts
    cd = np.asarray(cd, dtype=float).reshape(-1, n)
    normal = (np.hstack((np.ones((len(cd), 1)), np.zeros((len(cd), n)))) if normal is None
              else np.asarray(normal, dtype=float))
    law = np.array([lw.kernel_params() for lw in laws]).reshape(-1, len(Coulomb().kernel_params()))
    if el.forces is None:
        forces = (np.zeros((0, n)), np.zeros(0), np.zeros(0), np.zeros(0))
    else:
        forces = (np.asarray(el.forces[0], dtype=float).reshape(-1, n),
                  *(np.asarray(a, dtype=float) for a in el.forces[1:]))
    q0 = np.zeros(n) if el.q0 is None else np.asarray(el.q0, dtype=float)
    v0 = np.zeros(n) if el.v0 is None else np.asarray(el.v0, dtype=float)
    return Assembly(mass, (sd.T * sk) @ sd, (dd.T * dc) @ dd, cd, np.asarray(belt, dtype=float), law, normal,
                    *forces, sd, sk, dd, dc, q0, v0)


def single_mass(zeta: float, vb: float, law: Coulomb, x0: float, v0: float,
                forcing: tuple | None = None) -> Assembly:
    """X'' + 2 zeta X' + X = F_c (+ F_ex cos(Omega t + phi), ``forcing`` = (F_ex, Omega, phi))."""
    forces = None if forcing is None else ([[1.0]], [forcing[0]], [forcing[1]], [forcing[2]])
    return build(Elements([[1.0]], ([[1.0]], [1.0]), ([[1.0]], [2.0 * zeta]), ([[1.0]], [vb], [law], None),
                          forces, [x0], [v0]))


def chain(n: int, belt: Sequence[float], laws: Sequence[Coulomb], *, k_ground: float = 1.0, k_between: float = 0.5,
          c: float = 0.04, q0: Sequence[float] | None = None, v0: Sequence[float] | None = None) -> Assembly:
    """n unit masses in a line: each on a spring and a damper to the ground, springs between neighbours,
    one contact per mass on its own belt."""
    e = np.eye(n)
    springs = np.array([*e, *(e[i] - e[i + 1] for i in range(n - 1))]).reshape(-1, n)
    k = np.array([k_ground] * n + [k_between] * (n - 1))
    return build(Elements(np.eye(n), (springs, k), (e, np.full(n, c)), (e, belt, laws, None), None, q0, v0))
