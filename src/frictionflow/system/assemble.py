"""A :class:`~frictionflow.system.System` assembled into the arrays the engines read (``core.assembly.Assembly``)."""

from __future__ import annotations

import numpy as np

from .. import _validate as check
from ..core import layout
from ..core.assembly import Assembly, natural_frequencies
from .elements import vector
from .model import System

#: the forcing slots of a law row: the structure's forces are elements of their own, not a contact's
FORCING_SLOTS = (layout.FEX, layout.OMEGA, layout.PHI)


def assemble(system: System) -> Assembly:
    """M, K = sum k e e^T, C = sum c e e^T and the per-element arrays of ``system``.

    Parameters
    ----------
    system:
        The validated model.

    Returns
    -------
    Assembly
        Every array float64 and C-contiguous; a kind with no element has shape (0, n) or (0,).
        A contact's law row is its law's :meth:`~frictionflow.FrictionLaw.kernel_params`
        with the forcing slots 0; its normal row is [preload, n_1, ..., n_n] ([1, 0, ..., 0] without
        a normal load).
    """
    check.instance("system", system, System, "a System (frictionflow.system.load_system(path) or System(...))")
    dof, n = system.dof, system.n
    spring_dir = _rows([s.on for s in system.springs], dof)
    spring_k = np.array([s.k for s in system.springs], dtype=np.float64)
    damper_dir = _rows([d.on for d in system.dampers], dof)
    damper_c = np.array([d.c for d in system.dampers], dtype=np.float64)
    law = np.zeros((len(system.contacts), layout.N_PARAMS))
    normal = np.zeros((len(system.contacts), n + 1))
    for j, contact in enumerate(system.contacts):
        law[j] = contact.law.kernel_params()
        law[j, list(FORCING_SLOTS)] = 0.0
        if contact.normal is None:
            normal[j, 0] = 1.0
        else:
            normal[j, 0] = contact.normal.preload
            normal[j, 1:] = vector(contact.normal.on, dof)
    return Assembly(
        mass=np.ascontiguousarray(system.mass_matrix),
        stiffness=np.ascontiguousarray((spring_dir.T * spring_k) @ spring_dir),
        damping=np.ascontiguousarray((damper_dir.T * damper_c) @ damper_dir),
        contact_dir=_rows([c.on for c in system.contacts], dof),
        belt=np.array([c.belt for c in system.contacts], dtype=np.float64),
        law=law, normal=normal,
        force_dir=_rows([f.on for f in system.forces], dof),
        force_amp=np.array([f.amplitude for f in system.forces], dtype=np.float64),
        force_omega=np.array([f.omega for f in system.forces], dtype=np.float64),
        force_phi=np.array([f.phi for f in system.forces], dtype=np.float64),
        spring_dir=spring_dir, spring_k=spring_k, damper_dir=damper_dir, damper_c=damper_c,
        q0=np.ascontiguousarray(system.q0), v0=np.ascontiguousarray(system.v0),
    )


def _rows(directions: list, dof: tuple[str, ...]) -> np.ndarray:
    """The directions as the rows of a (len(directions), n) array."""
    out = np.zeros((len(directions), len(dof)))
    for i, on in enumerate(directions):
        out[i] = vector(on, dof)
    return out


def fastest_rate(assembly: Assembly) -> float:
    """The structure's fastest rate: its fastest natural frequency or forcing frequency; without either (no
    springs, no force), its fastest own rate (a damper over a mass); without that (masses on belts alone), 0:
    the structure has no time scale of its own."""
    a = assembly
    omega = max(float(natural_frequencies(a).max(initial=0.0)), float(np.max(np.abs(a.force_omega), initial=0.0)))
    if omega > 0.0:
        return omega
    rates = np.abs(np.linalg.eigvals(np.linalg.solve(np.asarray(a.mass, dtype=float),
                                                     np.asarray(a.damping, dtype=float))))
    return float(rates.max(initial=0.0))


def state_scales(assembly: Assembly, t_end: float) -> tuple[float, float, float, float]:
    """(time, position, velocity, work): the sizes the structure's motion is measured in, from its elements alone.

    Time is 1 / :func:`fastest_rate` (``t_end`` without one); a force F is the largest static friction level
    at the start or force amplitude; velocity the largest of the belt speeds, |q'(0)|, |q(0)| / time and the
    speed F gives the lightest mode over that time; position the largest of |q(0)| and velocity x time; work
    the largest of the heaviest mode's kinetic energy at that velocity and F x position.  Each scales with
    the model's units as its quantity does, so a tolerance in these sizes means the same in any units (an
    absolute 1e-13 on lengths in metres of a nanometre motion was a relative 1e-4)."""
    a = assembly
    rate = fastest_rate(a)
    time = 1.0 / rate if rate > 0.0 else float(t_end)
    normal = np.abs(a.normal[:, 0] + a.normal[:, 1:] @ a.q0)
    force = max(float(np.max(a.law[:, layout.FS] * normal, initial=0.0)), float(np.max(np.abs(a.force_amp), initial=0.0)))
    heavy = np.linalg.eigvalsh(np.asarray(a.mass, dtype=float))
    q0, v0 = float(np.max(np.abs(a.q0), initial=0.0)), float(np.max(np.abs(a.v0), initial=0.0))
    velocity = max(float(np.max(np.abs(a.belt), initial=0.0)), v0, q0 / time, force * time / heavy[0], 1e-300)
    position = max(q0, velocity * time)
    return time, position, velocity, max(heavy[-1] * velocity * velocity, force * position)


def free_directions(assembly: Assembly, undamped: bool = False) -> np.ndarray:
    """(n, r) orthonormal columns: the directions d along which no spring (K d = 0) and no contact's normal
    load (n_j . d = 0) depends on the position -- and with ``undamped``, no damper acts either (C d = 0).

    A structure may repeat its motion shifted along the first (the belt carrying it along); along the second
    its motion is polynomial in time (x'' constant while the contacts slip), which no sum of exponentials
    describes."""
    n = len(assembly.q0)
    parts = [np.asarray(assembly.stiffness, dtype=float), np.asarray(assembly.normal, dtype=float)[:, 1:]]
    if undamped:
        parts.append(np.asarray(assembly.damping, dtype=float))
    # each part over its own size: stiffnesses and dampings are in different units, and one rank over both
    # took the springs beside a damper of 1e12 for rounding (a sprung structure "free along q1")
    parts = [p / np.abs(p).max() for p in parts if p.size and np.abs(p).max() > 0.0]
    if not parts:
        return np.eye(n)
    _, sv, vt = np.linalg.svd(np.vstack(parts).reshape(-1, n))
    rank = int(np.sum(sv > 1e-12 * max(float(sv.max(initial=0.0)), 1e-300)))
    return vt[rank:].T
