"""The record a linear structure with friction contacts reaches the compiled kernels as.

A structure with n generalised coordinates q, k friction contacts, m harmonic
forces, s springs and d dampers obeys

    M q'' + C q' + K q = sum_j e_j F_j + sum_i g_i A_i cos(Omega_i t + phi_i)

where contact j rubs along e_j on a belt moving at b_j: its relative velocity
is V_r,j = b_j - e_j . q' and, while slipping, F_j = N_j(q) law_j(V_r,j) with
the normal load N_j = P_j + n_j . q.  Without a normal-load description
N_j = 1 and the law's levels are forces.  The single belt oscillator is
n = k = s = d = 1 with M = 1, K = 1, C = 2 zeta and e = 1.

==================  ==========================================================
``mass``            (n, n) M, symmetric positive definite
``stiffness``       (n, n) K = sum_s k_s e_s e_s^T
``damping``         (n, n) C = sum_d c_d e_d e_d^T
``contact_dir``     (k, n) the contacts' directions e_j, one per row
``belt``            (k,) the belt speeds b_j
``law``             (k, N_PARAMS) each contact's law row in the layout of
                    :mod:`.layout` (its forcing slots are 0: the forces
                    below act on the structure, not on a contact)
``normal``          (k, n + 1) column 0 the preload P_j, columns 1..n the
                    coefficients n_j (no normal load given: 1, 0, ..., 0)
``force_dir``       (m, n) the forces' directions g_i
``force_amp``       (m,) A_i; ``force_omega`` (m,) Omega_i;
                    ``force_phi`` (m,) phi_i
``spring_dir``      (s, n) and ``spring_k`` (s,): the springs
``damper_dir``      (d, n) and ``damper_c`` (d,): the dampers
``q0``, ``v0``      (n,) the initial state
==================  ==========================================================

Every array is float64 and C-contiguous; a kind with no element has shape
(0, n) or (0,).  The per-element arrays are kept beside the assembled
matrices so that each element's power can be computed on its own.  This
module imports nothing of the package: the model layer
(:mod:`frictionflow.system`) builds the record, the engines read it.
"""

from __future__ import annotations

from collections import namedtuple

import numpy as np

Assembly = namedtuple(
    "Assembly",
    "mass stiffness damping contact_dir belt law normal force_dir force_amp force_omega force_phi "
    "spring_dir spring_k damper_dir damper_c q0 v0",
)


def natural_frequencies(assembly) -> np.ndarray:
    """The undamped natural frequencies sqrt(eig(M^-1 K)) of ``assembly``, ascending (0 for a rigid mode).

    The scale the engines and analyses take their time steps, grids and
    estimates from (the contacts and the dampers left out).
    """
    k_over_m = np.abs(np.linalg.eigvals(np.linalg.solve(assembly.mass, assembly.stiffness)))
    return np.sort(np.sqrt(k_over_m))
