"""``Motion``: the result of a run of a linear structure with friction contacts (issue 22).

The samples hold the state, each contact's friction force and mode and the
cumulative work of every element; between the samples the motion is the
phase's closed form, which :meth:`Motion.at` evaluates exactly (from the
last sample before t, in its modes: no switch lies between).  A run of the
adaptive solver (any switch-rule law) samples every step instead and keeps
the accelerations and the channels' powers at both ends of each interval
(:attr:`Motion.accel`, :attr:`Motion.power`): its :meth:`Motion.at` is the
quintic Hermite form of q, the cubic one of q' and of the works.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._lazy import lazy_module
from .core.assembly import Assembly
from .core.hermite import hermite, quintic
from .core.structure.evaluate import states as exact_states
from .core.structure.run import advance

#: the friction mode codes of :attr:`Motion.modes`
MODE_NAMES = {-1: "slip-", 0: "stick", 1: "slip+"}


#: the long names of :meth:`Motion.to_xarray`'s variables and coordinates
DATASET_NAMES = {
    "time": "time", "q": "generalised coordinate q", "v": "generalised velocity q'",
    "force": "friction force along the contact's direction", "mode": "contact mode (0 stick, +-1 slip)",
    "work": "work done since the start, per element channel (heat: dissipated at the contact)",
}

@dataclass(repr=False)
class Motion:
    """Samples of one run of a structure, and the exact motion between them.

    Attributes
    ----------
    t:
        (T,) sample times: the start, every switch, the dense grid if asked, the end.
    state:
        (2n, T): rows q (named by ``dof``) then q'.
    force:
        (k, T): each contact's friction force on the structure.
    modes:
        (k, T) int8: -1 slip-, 0 stick, +1 slip+ (V_r > 0) after each sample.
    work:
        (W, T): cumulative work since t = 0 of each channel in :attr:`channels`: the work each spring,
        damper and force does on the structure, then ``contact.j.belt`` (the belt's input F_j b_j) and
        ``contact.j.heat`` (the interface heat F_j V_r,j >= 0).
    channels:
        The channel names.
    switches:
        (S,) switch times.
    switch_contact:
        (S,) the index of the contact that switched.
    switch_mode:
        (S,) the mode it entered.
    dof, contacts:
        The names of the coordinates and of the contacts.
    status:
        ``"ok"`` or ``"contact_lost"``.
    assembly, system:
        What was run (``system``: the model object when the run came from one, else None).
    lost:
        (contact name, time) when a normal load reached zero, else None.
    elements:
        Element kind -> the names of its elements (``spring``, ``damper``, ``force``, ``contact``).
    accel:
        None for the exact engine's runs (the closed forms hold between samples); for a run sampled at
        every step (2n, T): rows 0..n-1 q'' just after each sample, rows n..2n-1 the q'' the next sample
        is reached with (both in the sample's modes), from which :meth:`at` interpolates.
    power:
        With :attr:`accel`, (2W, T): each channel's power just after each sample and the one the next
        sample is reached with, from which :meth:`work_at` interpolates the works.
    solver:
        The name of the solver that made the run.
    settings:
        That solver's own settings by keyword (the adaptive one's ``rtol``, ``atol``, ``max_steps``; none for
        the exact one): what a further run of the same structure passes on to agree with this one.
    """

    t: np.ndarray
    state: np.ndarray
    force: np.ndarray
    modes: np.ndarray
    work: np.ndarray
    channels: tuple[str, ...]
    switches: np.ndarray
    switch_contact: np.ndarray
    switch_mode: np.ndarray
    dof: tuple[str, ...]
    contacts: tuple[str, ...]
    status: str
    assembly: Assembly
    lost: tuple[str, float] | None = None
    system: Any = None
    elements: dict[str, tuple[str, ...]] = field(default_factory=dict)
    accel: np.ndarray | None = None
    power: np.ndarray | None = None
    solver: str = "exact"
    settings: dict[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        return (f"Motion(n={len(self.dof)}, contacts={len(self.contacts)}, samples={len(self.t)}, "
                f"switches={len(self.switches)}, status={self.status!r})")

    @property
    def n(self) -> int:
        """The number of generalised coordinates."""
        return len(self.dof)

    def _from_sample(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, q', cumulative work) at ``t``, from the last sample at or before it."""
        t = float(t)
        if not self.t[0] <= t <= self.t[-1]:
            raise ValueError(f"t must be in [{self.t[0]}, {self.t[-1]}], got {t}")
        i = int(np.searchsorted(self.t, t, side="right")) - 1
        n, a = self.n, self.assembly
        if self.t[i] == t:
            return self.state[:n, i].copy(), self.state[n:, i].copy(), self.work[:, i].copy()
        if self.accel is not None:
            s = (t - self.t[i]) / (self.t[i + 1] - self.t[i])
            state = self._interpolate(np.array([i]), np.array([s]))[:, 0]
            h, w = self.t[i + 1] - self.t[i], len(self.channels)
            work = hermite(self.work[:, i], self.work[:, i + 1], h * self.power[:w, i], h * self.power[w:, i], s)
            return state[:n], state[n:], work
        q, v, dw = advance(a, np.linalg.inv(a.mass), self.modes[:, i].copy(), self.state[:n, i].copy(),
                           self.state[n:, i].copy(), self.t[i], t - self.t[i], len(self.channels))
        return q, v, self.work[:, i] + dw

    def at(self, t: float) -> np.ndarray:
        """The state (q, q') at time ``t`` (2n,), exact: the closed form of the phase that holds t."""
        q, v, _ = self._from_sample(t)
        return np.concatenate((q, v))

    def states(self, times: Any) -> np.ndarray:
        """The exact state (2n, m) at each of ``times`` (any order), each from the phase that holds it.

        Unlike :meth:`at`, no work is integrated, and each sample's phase is
        set up once for all the times after it: the way to evaluate a grid.
        """
        times = np.asarray(times, dtype=float).ravel()
        if times.size and not (self.t[0] <= times.min() and times.max() <= self.t[-1]):
            raise ValueError(f"times must lie in [{self.t[0]}, {self.t[-1]}]")
        if self.accel is not None:
            i = np.clip(np.searchsorted(self.t, times, side="right") - 1, 0, max(len(self.t) - 2, 0))
            span = np.where(self.t[i + 1] > self.t[i], self.t[i + 1] - self.t[i], 1.0)
            return self._interpolate(i, np.clip((times - self.t[i]) / span, 0.0, 1.0))
        order = np.argsort(times, kind="stable")
        out = np.empty((2 * self.n, times.size))
        filled = np.empty_like(out)
        a = self.assembly
        exact_states(a, np.linalg.inv(a.mass), np.ascontiguousarray(self.t), np.ascontiguousarray(self.state),
               np.ascontiguousarray(self.modes), np.ascontiguousarray(times[order]), filled)
        out[:, order] = filled
        return out

    def _interpolate(self, i: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(2n, m): the Hermite forms on the intervals ``i`` at their local times ``s`` in [0, 1]."""
        n, a = self.n, self.accel
        h = self.t[i + 1] - self.t[i]
        q0, q1, v0, v1 = self.state[:n, i], self.state[:n, i + 1], self.state[n:, i], self.state[n:, i + 1]
        a0, a1 = a[:n, i], a[n:, i]
        q, _ = quintic(q0, q1, h * v0, h * v1, h * h * a0, h * h * a1, s)
        return np.concatenate((q, hermite(v0, v1, h * a0, h * a1, s)))

    def work_at(self, t: float) -> np.ndarray:
        """The cumulative work of every channel at time ``t``."""
        return self._from_sample(t)[2]

    def element_power(self, t0: float, t1: float) -> dict[str, dict[str, float]]:
        """Element name -> its average powers over [t0, t1]: ``{"P": ...}`` for springs, dampers and forces,
        ``{"P_belt": ..., "P_heat": ...}`` for contacts."""
        if not t1 > t0:
            raise ValueError(f"t1 must be > t0, got t0={t0}, t1={t1}")
        avg = dict(zip(self.channels, (self.work_at(t1) - self.work_at(t0)) / (t1 - t0)))
        out: dict[str, dict[str, float]] = {}
        for name, value in avg.items():
            if name.endswith(".belt") or name.endswith(".heat"):
                element, part = name.rsplit(".", 1)
                out.setdefault(element, {})["P_" + part] = float(value)
            else:
                out[name] = {"P": float(value)}
        return out

    def energy(self, state: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(kinetic, spring potential) energy at each sample, or of each column of ``state`` (2n, m)."""
        a, n = self.assembly, self.n
        state = self.state if state is None else state
        q, v = state[:n], state[n:]
        kinetic = 0.5 * np.einsum("it,ij,jt->t", v, a.mass, v)
        potential = 0.5 * np.einsum("s,st->t", a.spring_k, (a.spring_dir @ q) ** 2)
        return kinetic, potential

    def balance(self) -> np.ndarray:
        """At each sample: Delta(KE + PE) - (damper + force works + belt input - heat); 0 up to rounding."""
        kinetic, potential = self.energy()
        e = kinetic + potential
        sign = np.array([0.0 if c.startswith("spring.") else (-1.0 if c.endswith(".heat") else 1.0)
                         for c in self.channels])
        return (e - e[0]) - sign @ self.work

    @property
    def energy_residual(self) -> float:
        """max |:meth:`balance`| relative to the size of the works (the largest sum of |work| over the channels)."""
        scale = float(np.abs(self.work).sum(axis=0).max()) if self.work.size else 0.0
        res = float(np.abs(self.balance()).max())
        return res / scale if scale > 0.0 else res

    def to_xarray(self):
        """An xarray Dataset: ``q`` and ``v`` over (time, dof), ``force`` and ``mode`` over (time, contact),
        ``work`` over (time, channel), each with its ``long_name`` (the model file's units: numbers are used as
        given); the switches and the whole run's energy residual (:attr:`energy_residual`) as attributes."""
        xr = lazy_module("xarray")  # slow to import: loaded when a dataset is first asked for
        n = self.n
        data = {"q": (("time", "dof"), self.state[:n].T), "v": (("time", "dof"), self.state[n:].T),
                "force": (("time", "contact"), self.force.T), "mode": (("time", "contact"), self.modes.T),
                "work": (("time", "channel"), self.work.T)}
        ds = xr.Dataset(
            data, coords={"time": self.t, "dof": list(self.dof), "contact": list(self.contacts),
                          "channel": list(self.channels)},
            attrs={"status": self.status, "switch_times": self.switches, "switch_contact": self.switch_contact,
                   "switch_mode": self.switch_mode, "energy_residual": self.energy_residual,
                   "energy_residual_span": "the whole run (max over time of the balance, relative to the works)"},
        )
        for name, long_name in DATASET_NAMES.items():
            ds[name].attrs["long_name"] = long_name
        return ds
