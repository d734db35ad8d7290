"""An independent event-driven integrator for a linear structure with friction contacts (issue 22's reference).

Written for the tests and the benchmark from the equations alone, without the
package's engine: scipy's ``solve_ivp`` (DOP853) integrates each phase of
constant contact modes, its events end a phase, and the modes of the next
phase are decided here.  The model (:class:`frictionflow.core.assembly.Assembly`):

    M q'' + C q' + K q = sum_j e_j F_j + sum_i g_i A_i cos(Omega_i t + phi_i)

with V_r,j = b_j - e_j . q', the normal load N_j = P_j + n_j . q and, while
contact j slips, F_j = s_j mu_j(|V_r,j|) N_j (s_j = sgn V_r,j): Coulomb's
mu = F_d, Stribeck's F_d + (F_s - F_d) exp(-(v / v_s)^delta) + c_v v, the
cubic law's F_s - k_1 v + k_3 v^3 (each starts at F_s: mu(0) = F_s for the
last two, so a contact leaving a stick slips without a jump in its force).

Stuck contacts S are constraints E_S q' = b_S.  With r(q, q', t) every force
but theirs (springs, dampers, applied forces, slipping contacts), Lagrange's
multipliers make E_S q'' = 0:

    M q'' = r + E_S^T lam,   lam = -(E_S M^-1 E_S^T)^-1 E_S M^-1 r,

so lam_j is the friction force contact j holds (positive along +e_j).  A
contact with the law's ``stick_force = "spring"`` is judged on the held force
with the dampers left out of r; the motion uses the true lam either way.
Contact j stays stuck while |held_j| < F_s,j N_j; on reaching the limit it
slips with s_j = sgn held_j.  A slipping contact reaching V_r,j = 0 is tried
stuck together with the stuck ones; the worst violator of the rule is
released (slipping towards its held force's sign) and the others are
re-judged until none violates (the active-set loop: simultaneous contacts);
where that leaves a contact slipping back into V_r = 0, the assignment of
the contacts at V_r = 0 that holds and changes the fewest is taken.
N_j reaching 0 stops the run (contact lost).

In every phase the motion is linear in the state, y' = J y + c + D f(t) with
f_i(t) = A_i cos(Omega_i t + phi_i), but for the slip forces of contacts with
a smooth law, added through their own columns: y' += S F_smooth(y); J, c, D
and S are formed once per phase, as a careful scipy user would.  The work each element does on the structure is
integrated alongside when asked (``work=True``): springs, dampers, forces,
then each contact's belt input F_j b_j, then its heat F_j V_r,j.
"""

from __future__ import annotations

import itertools
from typing import Callable, NamedTuple

import numpy as np
from scipy.integrate import solve_ivp

from frictionflow.core import layout

EPS = np.finfo(float).eps


class Reference(NamedTuple):
    """What the reference integrator returns.

    ``t`` (T,) samples; ``state`` (2n, T) rows q then q'; ``modes`` (k, T)
    int8 (-1 slip-, 0 stick, +1 slip+); ``force`` (k, T) friction force on
    the structure along e_j; ``switches`` the times the modes changed;
    ``switch_modes`` (len(switches), k) the modes entered there; ``status``
    "ok" or "contact_lost" (then ``lost`` = (contact, time)); ``work``
    (W, T) cumulative work per channel (``None`` unless asked);
    ``channels`` their names; ``evaluations`` right-hand-side calls.
    """

    t: np.ndarray
    state: np.ndarray
    modes: np.ndarray
    force: np.ndarray
    switches: np.ndarray
    switch_modes: np.ndarray
    status: str
    lost: tuple | None
    work: np.ndarray | None
    channels: tuple
    evaluations: int


class Phase(NamedTuple):
    """The linear data of one combination of modes.

    State y = (q, q').  y' = ``jac`` y + ``const`` + ``drive`` f(t).  The
    friction forces are F = ``fy`` y + ``f0`` + ``ff`` f(t) (slip: s F_d N;
    stick: lam); the stuck contacts' held forces (per their stick rule) are
    ``hy`` y + ``h0`` + ``hf`` f(t), one row per entry of ``stuck``.  The
    slipping contacts with a smooth law (``smooth``) add their slip forces
    ``slip(y)``: ``sy`` slip(y) to y', ``sl`` slip(y) to the stuck contacts'
    lam and held forces (the "spring" rule leaves out the dampers only).
    """

    modes: np.ndarray
    stuck: np.ndarray
    jac: np.ndarray
    const: np.ndarray
    drive: np.ndarray
    fy: np.ndarray
    f0: np.ndarray
    ff: np.ndarray
    hy: np.ndarray
    h0: np.ndarray
    hf: np.ndarray
    smooth: np.ndarray
    sy: np.ndarray
    sl: np.ndarray
    slip: Callable[[np.ndarray], np.ndarray]


#: the laws the reference models, by their kernel code
LAWS = (layout.COULOMB, layout.STRIBECK, layout.CUBIC)


def check(asm) -> None:
    """Refuse what the reference does not model: laws other than Coulomb, Stribeck and the cubic law."""
    codes = np.asarray(asm.law)[:, layout.LAW] if len(asm.belt) else np.zeros(0)
    if not np.all(np.isin(codes, LAWS)):
        raise ValueError("reference: every contact's law must be Coulomb, Stribeck or the cubic law")


def slip_level(p: np.ndarray, speed: np.ndarray) -> np.ndarray:
    """mu(|V_r|), the slip force per unit normal load, of the law rows ``p`` (kernel layout) at ``speed``."""
    code = p[:, layout.LAW]
    stribeck = p[:, layout.FD] + (p[:, layout.FS] - p[:, layout.FD]) * np.exp(
        -(speed / np.where(code == layout.STRIBECK, p[:, layout.LAW_A], 1.0)) ** p[:, layout.LAW_B]) \
        + p[:, layout.LAW_C] * speed
    cubic = p[:, layout.FS] - p[:, layout.LAW_A] * speed + p[:, layout.LAW_B] * speed ** 3
    return np.where(code == layout.STRIBECK, stribeck, np.where(code == layout.CUBIC, cubic, p[:, layout.FD]))


def forcing(asm, t: float) -> np.ndarray:
    """f_i(t) = A_i cos(Omega_i t + phi_i)."""
    return asm.force_amp * np.cos(asm.force_omega * t + asm.force_phi)


def normal_load(asm, q: np.ndarray) -> np.ndarray:
    """N_j = P_j + n_j . q."""
    return asm.normal[:, 0] + asm.normal[:, 1:] @ q


def _slip_rows(asm, modes: np.ndarray):
    """The slipping Coulomb contacts' forces s F_d (P + n.q) as Fq q + F0, one row per contact (0 for the others)."""
    coulomb = asm.law[:, layout.LAW] == layout.COULOMB
    s = modes.astype(float) * np.where(coulomb, asm.law[:, layout.FD], 0.0)  # 0 for the stuck ones
    return s[:, None] * asm.normal[:, 1:], s * asm.normal[:, 0]


def _smooth_slip(asm, smooth: np.ndarray, modes: np.ndarray):
    """y -> the slip forces s_j mu_j(|V_r,j|) N_j(q) of the contacts ``smooth`` (slipping, smooth laws)."""
    n = asm.mass.shape[0]
    e, b, p, nr = asm.contact_dir[smooth], asm.belt[smooth], asm.law[smooth], asm.normal[smooth]
    s = modes[smooth].astype(float)

    def slip(y: np.ndarray) -> np.ndarray:
        return s * slip_level(p, np.abs(b - e @ y[n:2 * n])) * (nr[:, 0] + nr[:, 1:] @ y[:n])

    return slip


def phase(asm, modes: np.ndarray) -> Phase:
    """The linear data of the phase with ``modes`` (see :class:`Phase`)."""
    n, k = asm.mass.shape[0], len(asm.belt)
    minv = np.linalg.inv(asm.mass)
    fq, f0s = _slip_rows(asm, modes)
    e = asm.contact_dir
    # r = Rq q + Rv q' + r0 + G^T f
    rq = -asm.stiffness + e.T @ fq
    rv = -asm.damping
    r0 = e.T @ f0s
    g = asm.force_dir.T
    stuck = np.flatnonzero(modes == 0)
    es = e[stuck]
    if len(stuck):
        lmat = np.linalg.solve(es @ minv @ es.T, es @ minv)  # lam = -L r
    else:
        lmat = np.zeros((0, n))
    proj = minv @ (np.eye(n) - es.T @ lmat)  # q'' = P r
    m = len(asm.force_amp)
    jac = np.zeros((2 * n, 2 * n))
    jac[:n, n:] = np.eye(n)
    jac[n:, :n] = proj @ rq
    jac[n:, n:] = proj @ rv
    const = np.concatenate((np.zeros(n), proj @ r0))
    drive = np.vstack((np.zeros((n, m)), proj @ g))
    lam_y = -lmat @ np.hstack((rq, rv))
    lam_0, lam_f = -lmat @ r0, -lmat @ g
    fy = np.hstack((fq, np.zeros((k, n))))
    f0, ff = f0s.copy(), np.zeros((k, m))
    fy[stuck], f0[stuck], ff[stuck] = lam_y, lam_0, lam_f
    # the "spring" rule leaves the dampers (Rv q') out of r
    spring = asm.law[stuck, layout.RESULTANT] == 0.0
    hy = lam_y.copy()
    hy[spring, n:] = 0.0
    smooth = np.flatnonzero((modes != 0) & (asm.law[:, layout.LAW] != layout.COULOMB))
    sy = np.vstack((np.zeros((n, len(smooth))), proj @ e[smooth].T))
    sl = -lmat @ e[smooth].T
    return Phase(modes.copy(), stuck, jac, const, drive, fy, f0, ff, hy, lam_0, lam_f, smooth, sy, sl,
                 _smooth_slip(asm, smooth, modes))


def friction(ph: Phase, y: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Each contact's friction force on the structure at state ``y`` with forcing ``f``."""
    out = ph.fy @ y + ph.f0 + ph.ff @ f
    if len(ph.smooth):
        slip = ph.slip(y)
        out[ph.stuck] += ph.sl @ slip
        out[ph.smooth] = slip
    return out


def held(ph: Phase, y: np.ndarray, f: np.ndarray) -> np.ndarray:
    """The stuck contacts' held forces (per their stick rule), in the order of ``ph.stuck``."""
    out = ph.hy @ y + ph.h0 + ph.hf @ f
    return out + ph.sl @ ph.slip(y) if len(ph.smooth) else out


def rate(asm, ph: Phase, t: float, y: np.ndarray) -> np.ndarray:
    """y' of the phase at (t, y) (y = (q, q'))."""
    out = ph.jac @ y + ph.const + ph.drive @ forcing(asm, t)
    return out + ph.sy @ ph.slip(y) if len(ph.smooth) else out


def relative_velocity(asm, y: np.ndarray) -> np.ndarray:
    """V_r,j = b_j - e_j . q'."""
    n = asm.mass.shape[0]
    return asm.belt - asm.contact_dir @ y[n:]


def _violation(asm, ph: Phase, y: np.ndarray, f: np.ndarray, q: np.ndarray):
    """The stuck contact breaking the stick rule worst, with its held force (None: none breaks it)."""
    if not len(ph.stuck):
        return None, 0.0
    h = held(ph, y, f)
    limit = asm.law[ph.stuck, layout.FS] * normal_load(asm, q)[ph.stuck]
    excess = np.abs(h) - limit
    bad = (excess > 0.0) | ((excess == 0.0) & (h != 0.0))
    if not np.any(bad):
        return None, 0.0
    i = int(np.argmax(np.where(bad, excess / np.maximum(limit, 1e-300), -np.inf)))
    return int(ph.stuck[i]), float(h[i])


def decide(asm, modes: np.ndarray, t: float, y: np.ndarray, release: dict) -> Phase:
    """The phase that follows at (t, y): contacts with ``modes`` 0 are at V_r = 0 and tried stuck.

    ``release`` maps contacts whose stick limit was just reached to their slip
    direction (they slip whatever the rounding of their held force says).
    """
    n = asm.mass.shape[0]
    zero = np.array([j for j in np.flatnonzero(modes == 0) if j not in release], dtype=int)
    modes = modes.copy()
    for j, s in release.items():
        modes[j] = s
    f = forcing(asm, t)
    for _ in range(len(modes) + 1):
        ph = phase(asm, modes)
        j, h = _violation(asm, ph, y, f, y[:n])
        if j is None:
            acc = rate(asm, ph, t, y)[n:]
            back = _turning_back(asm, ph, acc, np.array(list(release), dtype=int))  # the "spring" rule's release
            if len(back):
                raise RuntimeError(f"reference: contact {back[0]} can neither stick nor slip at t = {t!r}")
            return _search(asm, ph, t, y, zero) if len(_turning_back(asm, ph, acc, zero)) else ph
        modes[j] = 1 if h > 0.0 else -1
    raise RuntimeError(f"reference: no consistent modes at t = {t!r}")


def _turning_back(asm, ph: Phase, acc: np.ndarray, contacts: np.ndarray) -> np.ndarray:
    """Of ``contacts`` (at V_r = 0), those the phase slips straight back into V_r = 0 (s V_r' < 0 beyond rounding;
    ``acc`` the phase's q'').  The "spring" rule can release a contact whose true force, the dampers' share with
    it, is below its slip force: it can neither stick nor slip."""
    slip = contacts[ph.modes[contacts] != 0]
    return slip[ph.modes[slip] * (-asm.contact_dir[slip] @ acc) < -1e-10 * (1.0 + np.max(np.abs(acc)))]


def holds(asm, ph: Phase, t: float, y: np.ndarray, zero: np.ndarray) -> bool:
    """Whether the phase's modes hold at (t, y): no stuck contact past its limit, and each contact of ``zero``
    (at V_r = 0) that slips does not turn straight back into V_r = 0 (s V_r' >= 0 to rounding)."""
    n = asm.mass.shape[0]
    if _violation(asm, ph, y, forcing(asm, t), y[:n])[0] is not None:
        return False
    return not len(_turning_back(asm, ph, rate(asm, ph, t, y)[n:], zero))


def _search(asm, ph: Phase, t: float, y: np.ndarray, zero: np.ndarray) -> Phase:
    """The active-set loop's modes slip a contact back into V_r = 0: every assignment of the contacts ``zero``
    (at V_r = 0, not just released) that holds, the one closest to the loop's (fewest contacts changed).  None
    holds where the "spring" rule releases a contact whose true force is below its slip force: refused."""
    best, changed = None, len(zero) + 1
    for trial in itertools.product((-1, 0, 1), repeat=len(zero)):
        modes = ph.modes.copy()
        modes[zero] = trial
        cand = phase(asm, modes)
        count = int(np.sum(modes != ph.modes))
        if count < changed and holds(asm, cand, t, y, zero):
            best, changed = cand, count
    if best is None:
        raise RuntimeError(f"reference: contacts {zero.tolist()} can neither stick nor slip at t = {t!r}")
    return best


def project(asm, y: np.ndarray, zero: np.ndarray) -> np.ndarray:
    """y with q' moved (least kinetic energy) so that V_r,j = 0 exactly for the contacts ``zero``."""
    if not len(zero):
        return y
    n = asm.mass.shape[0]
    minv = np.linalg.inv(asm.mass)
    e = asm.contact_dir[zero]
    mu = np.linalg.solve(e @ minv @ e.T, asm.belt[zero] - e @ y[n:])
    out = y.copy()
    out[n:] += minv @ e.T @ mu
    return out


def _event(fn, direction: float, tag: tuple):
    fn.terminal, fn.direction, fn.tag = True, direction, tag
    return fn


def departing(asm, ph: Phase, y: np.ndarray) -> np.ndarray:
    """The slipping contacts at V_r = 0 (to rounding) in state ``y``: the phase starts them slipping from there."""
    n = asm.mass.shape[0]
    scale = np.abs(asm.belt) + np.abs(asm.contact_dir) @ np.abs(y[n:2 * n])
    return np.flatnonzero((ph.modes != 0) & (np.abs(relative_velocity(asm, y[:2 * n])) <= 8.0 * EPS * scale))


def events(asm, ph: Phase, t0: float = 0.0, y0: np.ndarray | None = None) -> list:
    """The events ending the phase: V_r,j = 0 (slipping j), |held_j| = F_s,j N_j (stuck j), N_j = 0.

    A contact the phase starts slipping from V_r = 0 (at ``t0``, ``y0``) in
    its slip's direction has V_r / (t - t0) as its event function instead (its
    departure slope at t0): solve_ivp looks for sign changes between steps, and
    V_r = 0 at the start would take a slip that ends within the first step for
    an event at t0, or miss it.  One starting against its slip's direction
    keeps V_r, whose event at t0 has its modes decided again.
    """
    n = asm.mass.shape[0]
    out = []
    e, b = asm.contact_dir, asm.belt
    leaving_zero = set() if y0 is None else set(departing(asm, ph, y0).tolist())
    for j in np.flatnonzero(ph.modes != 0):
        s = float(ph.modes[j])
        slope = float(-e[j] @ rate(asm, ph, t0, y0[:2 * n])[n:]) if j in leaving_zero else 0.0
        if s * slope > 0.0:
            def fn(t, y, j=j, slope=slope):
                return (b[j] - e[j] @ y[n:2 * n]) / (t - t0) if t > t0 else slope
        else:
            def fn(t, y, j=j):
                return b[j] - e[j] @ y[n:2 * n]
        out.append(_event(fn, -s, ("stick", int(j))))
    for i, j in enumerate(ph.stuck):
        fs, hy, h0, hf = asm.law[j, layout.FS], ph.hy[i], ph.h0[i], ph.hf[i]
        pj, nj = asm.normal[j, 0], asm.normal[j, 1:]

        def limit(t, y, hy=hy, h0=h0, hf=hf, fs=fs, pj=pj, nj=nj):
            return fs * (pj + nj @ y[:n]) - abs(hy @ y[:2 * n] + h0 + hf @ forcing(asm, t))

        def smooth_limit(t, y, i=i, fs=fs, pj=pj, nj=nj):
            return fs * (pj + nj @ y[:n]) - abs(held(ph, y[:2 * n], forcing(asm, t))[i])

        out.append(_event(smooth_limit if len(ph.smooth) else limit, -1.0, ("slip", int(j))))
    for j in np.flatnonzero(np.any(asm.normal[:, 1:] != 0.0, axis=1)):
        pj, nj = asm.normal[j, 0], asm.normal[j, 1:]
        out.append(_event(lambda t, y, pj=pj, nj=nj: pj + nj @ y[:n], -1.0, ("lost", int(j))))
    return out


def channels(asm) -> tuple:
    """The work channels' names, in the order of :attr:`Reference.work`."""
    k = len(asm.belt)
    return (tuple(f"spring.{i}" for i in range(len(asm.spring_k)))
            + tuple(f"damper.{i}" for i in range(len(asm.damper_c)))
            + tuple(f"force.{i}" for i in range(len(asm.force_amp)))
            + tuple(f"contact.{j}.belt" for j in range(k)) + tuple(f"contact.{j}.heat" for j in range(k)))


def powers(asm, ph: Phase, t: float, y: np.ndarray) -> np.ndarray:
    """The power each element feeds into the structure at (t, y) (the channels' order)."""
    n = asm.mass.shape[0]
    q, v = y[:n], y[n:2 * n]
    f = forcing(asm, t)
    fc = friction(ph, y[:2 * n], f)
    return np.concatenate((-asm.spring_k * (asm.spring_dir @ q) * (asm.spring_dir @ v),
                           -asm.damper_c * (asm.damper_dir @ v) ** 2,
                           f * (asm.force_dir @ v),
                           fc * asm.belt, fc * relative_velocity(asm, y[:2 * n])))


def rhs(asm, ph: Phase, work: bool):
    """The right-hand side of the phase for ``solve_ivp`` (with the work channels when ``work``)."""
    n2 = 2 * asm.mass.shape[0]
    jac, const, drive = ph.jac, ph.const, ph.drive
    forced = len(asm.force_amp) > 0
    if len(ph.smooth):
        if not work:
            return lambda t, y: rate(asm, ph, t, y)
        return lambda t, y: np.concatenate((rate(asm, ph, t, y[:n2]), powers(asm, ph, t, y)))
    if not work:
        if not forced:
            return lambda t, y: jac @ y + const
        return lambda t, y: jac @ y + const + drive @ forcing(asm, t)

    def full(t, y):
        z = y[:n2]
        dz = jac @ z + const + (drive @ forcing(asm, t) if forced else 0.0)
        return np.concatenate((dz, powers(asm, ph, t, y)))

    return full


def as_arrays(asm):
    """The record with every field a float64 array (a hand-built record may hold lists)."""
    return type(asm)(*(np.asarray(a, dtype=float) for a in asm))


class _Run:
    """What the phase loop accumulates."""

    def __init__(self, asm, grid: np.ndarray) -> None:
        self.asm, self.grid, self.next = asm, grid, 0
        self.t, self.y, self.modes, self.force = [], [], [], []
        self.switches, self.switch_modes, self.evaluations = [], [], 0

    def record(self, ph: Phase, sol) -> None:
        self.next += len(sol.t)
        self.evaluations += sol.nfev
        for i, t in enumerate(sol.t):
            self.point(ph, t, sol.y[:, i])

    def switch(self, t: float, modes: np.ndarray) -> None:
        """Record a switch; one within the tie window of the last is the same switch (a tie taken in two)."""
        if self.switches and t - self.switches[-1] <= _tie_window(t):
            self.switch_modes[-1] = modes.copy()
        else:
            self.switches.append(t)
            self.switch_modes.append(modes.copy())

    def point(self, ph: Phase, t: float, y: np.ndarray) -> None:
        n2 = 2 * self.asm.mass.shape[0]
        self.t.append(t)
        self.y.append(y)
        self.modes.append(ph.modes.copy())
        self.force.append(friction(ph, y[:n2], forcing(self.asm, t)))


def _after_event(asm, ph: Phase, sol):
    """(kind, contact, t, y) of the event that ended ``sol``'s phase."""
    for i, te in enumerate(sol.t_events):
        if len(te):
            kind, j = events(asm, ph)[i].tag
            return kind, j, float(te[0]), sol.y_events[i][0].copy()
    raise RuntimeError("reference: the phase stopped without an event")


def _start(asm) -> tuple:
    """The initial state and modes (contacts at V_r = 0 decided by the stick rule)."""
    y = np.concatenate((asm.q0, asm.v0))
    vr = relative_velocity(asm, y)
    modes = np.sign(vr).astype(np.int8)
    return y, decide(asm, modes, 0.0, y, {})


def _tie_window(t: float) -> float:
    """The time within which two events count as one (1e3 ulps of t): solve_ivp reports one event of a tie."""
    return 1e3 * np.finfo(float).eps * max(1.0, abs(t))


def arriving(asm, ph: Phase, t: float, y: np.ndarray) -> np.ndarray:
    """The slipping contacts reaching V_r = 0 within the tie window of t (approaching it, and that near)."""
    n = asm.mass.shape[0]
    acc = rate(asm, ph, t, y)[n:]
    vr, dvr = relative_velocity(asm, y), -asm.contact_dir @ acc
    s = ph.modes.astype(float)
    return np.flatnonzero((s != 0.0) & (s * dvr < 0.0) & (s * vr <= -s * dvr * _tie_window(t)))


def leaving(asm, ph: Phase, t: float, y: np.ndarray) -> dict:
    """The stuck contacts whose held force reaches the limit within the tie window of t -> their slip direction."""
    n = asm.mass.shape[0]
    if not len(ph.stuck):
        return {}
    f = forcing(asm, t)
    df = -asm.force_amp * asm.force_omega * np.sin(asm.force_omega * t + asm.force_phi)
    h = held(ph, y, f)
    dy = rate(asm, ph, t, y)
    dh = ph.hy @ dy + ph.hf @ df
    if len(ph.smooth):  # the smooth slip forces' share, by a central difference along y'
        step = 1e-7 / max(1e-300, float(np.max(np.abs(dy))))
        dh += ph.sl @ (ph.slip(y + step * dy) - ph.slip(y - step * dy)) / (2.0 * step)
    fs = asm.law[ph.stuck, layout.FS]
    g = fs * normal_load(asm, y[:n])[ph.stuck] - np.abs(h)
    dg = fs * (asm.normal[ph.stuck, 1:] @ y[n:]) - np.sign(h) * dh
    near = (dg < 0.0) & (g <= -dg * _tie_window(t))
    return {int(j): (1 if hi > 0.0 else -1) for j, hi in zip(ph.stuck[near], h[near])}


def _next_phase(asm, ph: Phase, kind: str, j: int, t: float, y: np.ndarray) -> Phase:
    """The phase after the event ``kind`` of contact ``j`` at (t, y) (y's q' projected onto V_r = 0).

    Contacts tied with ``j`` (:func:`arriving`, :func:`leaving`) switch with it.
    """
    n2 = 2 * asm.mass.shape[0]
    modes = ph.modes.copy()
    modes[arriving(asm, ph, t, y[:n2])] = 0
    release = leaving(asm, ph, t, y[:n2])
    if kind == "stick":
        modes[j] = 0
    else:
        i = int(np.flatnonzero(ph.stuck == j)[0])
        release[j] = 1 if held(ph, y[:n2], forcing(asm, t))[i] > 0.0 else -1
    zero = np.flatnonzero(modes == 0)
    y[:n2] = project(asm, y[:n2], zero)
    return decide(asm, modes, t, y[:n2], release)


def sample_grid(t_end: float, t_eval=None, dense_dt=None) -> np.ndarray:
    """The sample times: ``t_eval`` as given, or 0, dense_dt, ... and t_end, or just 0 and t_end."""
    if t_eval is not None:
        return np.asarray(t_eval, dtype=float)
    if dense_dt is None:
        return np.array([0.0, t_end])
    grid = np.arange(0.0, t_end, dense_dt)
    return np.append(grid, t_end) if grid[-1] < t_end else grid


def integrate(asm, t_end: float, *, t_eval=None, dense_dt=None, rtol: float = 1e-12, atol: float = 1e-14,
              work: bool = False, max_switches: int = 1_000_000, method: str = "DOP853",
              max_step: float = np.inf) -> Reference:
    """Integrate the structure from t = 0 to ``t_end`` phase by phase with DOP853 (or ``method``) and events.

    Samples at ``t_eval`` (ascending, within [0, t_end]) or every ``dense_dt``
    (default: 0 and t_end only).  ``rtol``/``atol`` are solve_ivp's; ``method="Radau"`` for a stiff damper.
    solve_ivp finds an event where its function changes sign between steps, so
    a V_r that dips through 0 and back within one step is missed: a
    ``max_step`` shorter than such dips finds them.
    """
    asm = as_arrays(asm)
    check(asm)
    grid = sample_grid(t_end, t_eval, dense_dt)
    run = _Run(asm, grid)
    t, (y, ph) = 0.0, _start(asm)
    chans = channels(asm)
    y = np.concatenate((y, np.zeros(len(chans)))) if work else y
    status, lost = "ok", None
    if np.any(normal_load(asm, asm.q0) <= 0.0):
        j = int(np.flatnonzero(normal_load(asm, asm.q0) <= 0.0)[0])
        status, lost, t_end = "contact_lost", (j, 0.0), 0.0
    while t < t_end and len(run.switches) <= max_switches:
        sel = grid[run.next:]
        sol = solve_ivp(rhs(asm, ph, work), (t, t_end), y, method=method, rtol=rtol, atol=atol,
                        events=events(asm, ph, t, y), t_eval=sel[sel <= t_end], max_step=max_step)
        if sol.status < 0:
            raise RuntimeError(f"reference: solve_ivp failed at t = {t!r}: {sol.message}")
        run.record(ph, sol)
        if sol.status == 0:
            break
        kind, j, t, y = _after_event(asm, ph, sol)
        if kind == "lost":  # the run ends on the loss, its last sample there
            status, lost = "contact_lost", (j, t)
            if not run.t or run.t[-1] < t:
                run.point(ph, t, y)
            break
        new = _next_phase(asm, ph, kind, j, t, y)
        if np.any(new.modes != ph.modes):
            run.switch(t, new.modes)
        ph = new
    return _result(asm, run, status, lost, work, chans)


def _result(asm, run: _Run, status: str, lost, work: bool, chans: tuple) -> Reference:
    n2, k = 2 * asm.mass.shape[0], len(asm.belt)
    rows = n2 + (len(chans) if work else 0)
    y = np.array(run.y).reshape(len(run.t), rows).T
    return Reference(t=np.array(run.t), state=y[:n2], modes=np.array(run.modes, dtype=np.int8).T.reshape(k, -1),
                     force=np.array(run.force).T.reshape(k, -1), switches=np.array(run.switches),
                     switch_modes=np.array(run.switch_modes, dtype=np.int8).reshape(-1, k), status=status,
                     lost=lost, work=y[n2:] if work else None, channels=chans, evaluations=run.evaluations)


def energy(asm, state: np.ndarray) -> np.ndarray:
    """Kinetic plus potential (springs) energy at each sample of ``state`` (2n, T)."""
    n = asm.mass.shape[0]
    q, v = state[:n], state[n:]
    return 0.5 * np.einsum("it,ij,jt->t", v, asm.mass, v) + 0.5 * np.einsum("it,ij,jt->t", q, asm.stiffness, q)
