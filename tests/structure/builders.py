"""Assemblies built by hand for the structure engine's tests (the model layer is not needed to test it)."""

from __future__ import annotations

import numpy as np

from frictionflow.core.assembly import Assembly


def _rows(rows, n):
    return np.array(rows, dtype=float).reshape(len(rows), n)


def assembly(mass, springs=(), dampers=(), contacts=(), forces=(), q0=None, v0=None):
    """An Assembly from element lists: springs/dampers (e, value); contacts (e, belt, law row, normal or None);
    forces (e, amplitude, omega, phi)."""
    mass = np.array(mass, dtype=float)
    mass = np.diag(mass) if mass.ndim == 1 else mass
    n = len(mass)
    sd, sk = _rows([e for e, _ in springs], n), np.array([k for _, k in springs], dtype=float)
    dd, dc = _rows([e for e, _ in dampers], n), np.array([c for _, c in dampers], dtype=float)
    cd = _rows([c[0] for c in contacts], n)
    normal = np.array([c[3] if c[3] is not None else [1.0] + [0.0] * n for c in contacts], dtype=float).reshape(-1, n + 1)
    law = np.array([c[2] for c in contacts], dtype=float).reshape(len(contacts), -1)
    fd = _rows([f[0] for f in forces], n)
    return Assembly(
        mass=mass, stiffness=sd.T @ (sk[:, None] * sd), damping=dd.T @ (dc[:, None] * dd),
        contact_dir=cd, belt=np.array([c[1] for c in contacts], dtype=float), law=law, normal=normal,
        force_dir=fd, force_amp=np.array([f[1] for f in forces], dtype=float),
        force_omega=np.array([f[2] for f in forces], dtype=float), force_phi=np.array([f[3] for f in forces], dtype=float),
        spring_dir=sd, spring_k=sk, damper_dir=dd, damper_c=dc,
        q0=np.zeros(n) if q0 is None else np.array(q0, dtype=float),
        v0=np.zeros(n) if v0 is None else np.array(v0, dtype=float),
    )


def single_mass(zeta, vb, law, x0, v0, normal=None, force=None):
    """The belt oscillator X'' + 2 zeta X' + X = F_c (+ force) as a one-dof Assembly (``law``: the law object)."""
    forces = () if force is None else ([[1.0], *force],)
    return assembly([1.0], springs=[([1.0], 1.0)], dampers=[([1.0], 2.0 * zeta)],
                    contacts=[([1.0], vb, law.kernel_params(), normal)], forces=forces, q0=[x0], v0=[v0])


def uncoupled(count, zeta, vb, law, x0, v0):
    """``count`` identical belt oscillators side by side, with no coupling."""
    eye = np.eye(count)
    p = law.kernel_params()
    return assembly(np.ones(count), springs=[(e, 1.0) for e in eye], dampers=[(e, 2.0 * zeta) for e in eye],
                    contacts=[(e, vb, p, None) for e in eye], q0=np.full(count, x0), v0=np.full(count, v0))


def chain(n, law, belt, k_ground=1.0, k_couple=0.5, c=0.02, q0=None, v0=None, forces=()):
    """n unit masses: each on a ground spring and damper and a contact on the belt, neighbours coupled by springs."""
    eye = np.eye(n)
    springs = [(e, k_ground) for e in eye] + [(eye[i] - eye[i + 1], k_couple) for i in range(n - 1)]
    belts = np.broadcast_to(np.asarray(belt, dtype=float), (n,))
    p = law.kernel_params()
    return assembly(np.ones(n), springs=springs, dampers=[(e, c) for e in eye],
                    contacts=[(eye[i], belts[i], p, None) for i in range(n)], forces=forces, q0=q0, v0=v0)
