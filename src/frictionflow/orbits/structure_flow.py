"""A structure's return map to a section and its exact Jacobian: phase transition matrices, saltation at switches.

Within one combination of contact modes the motion is linear with constant
coefficients, so the flow over a fixed duration is *affine* in the initial
state (q, q'): y(tau) = Phi(tau) y0 + c.  :func:`phase_matrix` takes Phi
column by column as differences of the engine's own closed-form
advances (:func:`frictionflow.core.structure.run.advance`) from unit states
and from 0 -- exact to rounding, with no finite-difference truncation.  A
stuck contact's phase forgets the velocity perturbations across its
constraint direction, as the closed form does.

At every switch the perturbation crosses with the saltation matrix
(:mod:`frictionflow.core.saltation`): the event's gradient, the vector fields
of the combinations before and after it at the switch state.  The events
and their gradients:

* a slipping contact j reaching V_r,j = 0 (stick onset, or a slip reversal
  when its held force is over the limit there): h = sigma_j (b_j - e_j . q'),
  gradient (0, -sigma_j e_j);
* a stuck contact's held force reaching F_s N_j: the engine's event function
  F_s N_j -+ lambda_j, an affine map of (q, q') (its row of ``Combo.D``) plus
  harmonic terms whose time derivative is h_t.

Into stick, f+ has no component across the constraint, so the perturbation
leaves the switch tangent to it (n . dy+ = 0): the stuck state's reduction is
consistent with the closed form's.  Several contacts switching at one
instant are crossed one after another in contact order (one of the one-sided
derivatives of a map that is not differentiable there).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from .._lazy import lazy_module
from ..core import saltation
from ..core.assembly import natural_frequencies
from ..core.layout import STICK
from ..core.structure.combo import N_SLOTS, build
from ..core.structure.phase import start, state_at
from ..core.structure.stick import acceleration
from ..core.structure.work import n_channels
from ..solvers.structure import (free_direction_text, free_motion_solvers, in_model_terms, is_free_motion,
                                 is_repeated_root, run_assembly)
from ..system.assemble import free_directions, state_scales

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick

#: grid points per fastest natural period when looking for section crossings
GRID_PER_PERIOD = 64
#: velocities below this fraction of the largest speed are rounding (sign changes there are not crossings)
NOISE = 1e-10
#: the longest run (in slowest natural periods) looked through for the next section crossing
MAX_PERIODS = 400


class Return(NamedTuple):
    """One evaluation of the return map from ``start``.

    ``time``: the return time T; ``end``: y(T); ``monodromy``: d y(T) / d y(0) over the fixed time T (saltation
    included); ``jacobian``: the section-projected map's Jacobian (the time T varying with the start);
    ``motion``: the run; ``modes``: the contact modes at the start.
    """

    start: np.ndarray
    time: float
    end: np.ndarray
    monodromy: np.ndarray
    jacobian: np.ndarray
    motion: Any
    modes: np.ndarray


class Flow:
    """The exact flow of a structure (:class:`~frictionflow.core.assembly.Assembly`) and its linearisation."""

    def __init__(self, assembly: Any, names: dict[str, Any] | None = None) -> None:
        self.assembly = assembly
        self.n = len(assembly.q0)
        self.minv = np.linalg.inv(assembly.mass)
        self.names = names
        self.n_work = n_channels(assembly)
        self._combos: dict[bytes, Any] = {}
        omega = natural_frequencies(assembly)
        self.omega_max = max(float(omega.max(initial=0.0)), 1e-6)
        self.omega_min = max(float(omega.min(initial=1.0)), 1e-6)
        _, position, velocity, _ = state_scales(assembly, 2.0 * math.pi / self.omega_min)
        #: the state's sizes, per component: the phase matrix's differences are taken over steps of these
        self.sizes = np.repeat([position, velocity], self.n)

    def combo(self, modes: np.ndarray) -> Any:
        """The engine's combination record of ``modes`` (cached)."""
        modes = np.ascontiguousarray(modes, dtype=np.int8)
        key = modes.tobytes()
        if key not in self._combos:
            try:
                self._combos[key] = build(self.assembly, self.minv, modes)
            except ValueError as e:
                raise self._in_orbit_terms(e) from None
        return self._combos[key]

    def run(self, y0: np.ndarray, t_end: float) -> Any:
        """The engine's :class:`~frictionflow.motion.Motion` from state ``y0`` (2n,) at t = 0 to ``t_end``."""
        n = self.n
        asm = self.assembly._replace(q0=np.array(y0[:n], dtype=float), v0=np.array(y0[n:], dtype=float))
        try:
            return run_assembly(asm, t_end, names=self.names)
        except ValueError as e:
            raise self._in_orbit_terms(e) from None

    def _in_orbit_terms(self, error: ValueError) -> ValueError:
        """An undamped free motion met by the flow's phases, said for orbits (no other solver gives their
        monodromy; ``simulate`` runs such a structure with one that runs it); an element too stiff for the
        modes said in the model's terms (:func:`~frictionflow.solvers.structure.in_model_terms`); any other
        error as it is."""
        dof = (self.names or {}).get("dof") or tuple(f"q{i}" for i in range(self.n))
        free = free_directions(self.assembly, undamped=True)
        runs = " or ".join(free_motion_solvers())
        if not (free.shape[1] and is_free_motion(error)):
            names = {kind: (self.names or {}).get(kind) or tuple(f"{kind}.{i}" for i in range(count))
                     for kind, count in (("spring", len(self.assembly.spring_k)),
                                         ("damper", len(self.assembly.damper_c)))}
            said = in_model_terms(error, self.assembly, {"dof": dof, **names})
            if not is_repeated_root(said):
                return said
            return ValueError(f"orbits follow the exact engine's phases: "
                              f"{str(said).split('; use')[0].split(': ', 1)[1]}; simulate runs it with solver={runs}")
        return ValueError(f"orbits follow the exact engine's phases, which do not describe an undamped free motion: "
                          f"along {free_direction_text(free, dof)} no spring, damper or normal load holds the "
                          f"structure; simulate runs it with solver={runs}")

    def advance(self, modes: np.ndarray, y: np.ndarray, t0: float, tau: float) -> np.ndarray:
        """y(t0 + tau) from y at t0 in the modes ``modes`` (no switch between): the phase's closed form."""
        n, asm = self.n, self.assembly
        cb = self.combo(modes)
        ph = start(cb, asm, np.array(y[:n], dtype=float), np.array(y[n:], dtype=float), float(t0))
        q, v = state_at(cb, ph, asm.force_omega, float(tau))
        return np.concatenate((q, v))

    def states(self, motion: Any, times: np.ndarray) -> np.ndarray:
        """(len(times), 2n): the exact states of ``motion`` at ``times`` (:meth:`Motion.states`, transposed)."""
        return motion.states(times).T

    def field(self, modes: np.ndarray, y: np.ndarray, t: float) -> np.ndarray:
        """The vector field (q', q'') at (y, t) in the modes ``modes`` (stuck contacts held)."""
        n = self.n
        q, v = np.array(y[:n], dtype=float), np.array(y[n:], dtype=float)
        return np.concatenate((v, acceleration(self.assembly, self.combo(modes), q, v, float(t))))

    def phase_matrix(self, modes: np.ndarray, t0: float, tau: float) -> np.ndarray:
        """Phi: the linear part of the phase's affine flow over ``tau`` (differences of exact advances)."""
        size = 2 * self.n
        if tau == 0.0:
            return np.eye(size)
        # steps of the state's own sizes: a unit step in picoseconds (a velocity of 1e-12 natural units) moved
        # the positions by 1e-12 of theirs, and the difference kept 4 digits (a multiplier 5e-5 off)
        base = self.advance(modes, np.zeros(size), t0, tau)
        return np.column_stack([(self.advance(modes, d * e, t0, tau) - base) / d for d, e in zip(self.sizes, np.eye(size))])

    def event_normal(self, modes: np.ndarray, j: int, y: np.ndarray, t: float) -> tuple[np.ndarray, float]:
        """(gradient, time derivative) of the event function of contact ``j`` that ends its mode at (y, t)."""
        n, asm = self.n, self.assembly
        if modes[j] != STICK:
            normal = np.zeros(2 * n)
            normal[n:] = -modes[j] * asm.contact_dir[j]
            return normal, 0.0
        cb = self.combo(modes)
        arg = asm.force_omega * t + asm.force_phi
        slots = [N_SLOTS * j, N_SLOTS * j + 1]
        values = [abs(cb.D[s] @ y + cb.dc[s] + cb.Dh[s] @ np.cos(arg)) for s in slots]
        s = slots[int(np.argmin(values))]  # the side whose limit was reached
        return cb.D[s].copy(), float(-(cb.Dh[s] * asm.force_omega) @ np.sin(arg))

    def switch_matrix(self, y: np.ndarray, t: float, old: np.ndarray, new: np.ndarray) -> np.ndarray:
        """The saltation matrix of the switch at (y, t) from the modes ``old`` to ``new``."""
        S = np.eye(2 * self.n)
        cur = np.array(old, dtype=np.int8)
        for j in np.flatnonzero(np.asarray(old) != np.asarray(new)):
            nxt = cur.copy()
            nxt[j] = new[j]
            normal, h_t = self.event_normal(cur, int(j), y, t)
            S = saltation.matrix(self.field(cur, y, t), self.field(nxt, y, t), normal, h_t) @ S
            cur = nxt
        return S

    def monodromy(self, motion: Any, T: float) -> np.ndarray:
        """d y(T) / d y(0) along ``motion`` (which starts at t = 0 and reaches ``T``)."""
        t, modes, state = np.asarray(motion.t), np.asarray(motion.modes), np.asarray(motion.state)
        last = int(np.searchsorted(t, T, side="right")) - 1
        M = np.eye(2 * self.n)
        for i in range(1, last + 1):
            M = self.phase_matrix(modes[:, i - 1], t[i - 1], t[i] - t[i - 1]) @ M
            if np.any(modes[:, i] != modes[:, i - 1]):
                M = self.switch_matrix(state[:, i], t[i], modes[:, i - 1], modes[:, i]) @ M
        return self.phase_matrix(modes[:, last], t[last], T - t[last]) @ M


def crossings(flow: Flow, motion: Any, row: int, t0: float = 0.0) -> np.ndarray:
    """The times after ``t0`` where state row ``row`` (a velocity) crosses 0 downwards, located to rounding."""
    t_end = float(motion.t[-1])
    if t_end <= t0:
        return np.zeros(0)
    count = int(math.ceil((t_end - t0) * flow.omega_max / (2.0 * math.pi) * GRID_PER_PERIOD)) + 2
    knots = np.asarray(motion.t)
    grid = np.union1d(np.linspace(t0, t_end, count), knots[(knots > t0) & (knots < t_end)])
    values = flow.states(motion, grid)[:, row]
    values[0] = 0.0 if t0 == 0.0 else values[0]  # the start lies on the section: not a crossing
    # a motion settled on an equilibrium has velocities of rounding size: their sign changes are no crossings.
    # Grid points whose value lies in (0, floor] are passed over, not taken as the end of a descent: a trial
    # return's run is 1.5 times the last return time, so the crossing near that time is often a grid point
    # itself, of rounding size: ending the descent there would miss the crossing.
    floor = NOISE * max(float(np.max(np.abs(values))), float(np.max(np.abs(flow.assembly.belt), initial=0.0)))
    keep = np.flatnonzero((values <= 0.0) | (values > floor))
    kept = values[keep]
    hits = np.flatnonzero((kept[:-1] > floor) & (kept[1:] <= 0.0))
    return np.array([_locate(flow, motion, row, grid[keep[i]], grid[keep[i + 1]]) for i in hits])


def _locate(flow: Flow, motion: Any, row: int, a: float, b: float) -> float:
    """The crossing in [a, b], by bracketing then a Newton polish with the exact acceleration."""
    def value(s: float) -> float:
        return float(flow.states(motion, np.array([s]))[0, row])

    if value(b) == 0.0:
        return b
    t = optimize.brentq(value, a, b, xtol=1e-15 * max(abs(a), abs(b)), rtol=4.0 * np.finfo(float).eps)
    i = int(np.searchsorted(motion.t, t, side="right")) - 1
    y = flow.states(motion, np.array([t]))[0]
    rate = flow.field(motion.modes[:, i], y, t)[row]
    step = -y[row] / rate if rate != 0.0 else 0.0
    return t + step if a <= t + step <= b else t


def return_map(flow: Flow, start: np.ndarray, row: int, returns: int, horizon: float,
               limit: float | None = None) -> Return:
    """P(start): the ``returns``-th downward crossing of q'_row = 0, with the exact Jacobians.

    ``horizon``: the first run's length; doubled until the crossings are found, up to ``limit`` (default
    :data:`MAX_PERIODS` slowest natural periods).  RuntimeError if the motion never returns or loses a contact.
    """
    limit = MAX_PERIODS * 2.0 * math.pi / flow.omega_min if limit is None else max(limit, horizon)
    t_end = horizon
    while True:
        motion = flow.run(start, t_end)
        if motion.status != "ok":
            contact, when = motion.lost
            raise RuntimeError(f"{contact} lost its normal load at t={when:.6g} before the motion returned")
        times = crossings(flow, motion, row)
        if len(times) >= returns:
            break
        if t_end >= limit:
            raise RuntimeError(f"the motion does not come back to the section within t={t_end:.6g}")
        t_end = min(2.0 * t_end, limit)
    T = float(times[returns - 1])
    end = flow.states(motion, np.array([T]))[0]
    M = flow.monodromy(motion, T)
    i = int(np.searchsorted(motion.t, T, side="right")) - 1
    f_end = flow.field(motion.modes[:, i], end, T)
    proj = np.eye(2 * flow.n) - np.outer(f_end, np.eye(2 * flow.n)[row]) / f_end[row]
    return Return(np.array(start, dtype=float), T, end, M, proj @ M, motion, np.asarray(motion.modes[:, 0]).copy())
