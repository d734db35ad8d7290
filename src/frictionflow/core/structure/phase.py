"""A phase: one mode combination from a start state; its closed form and its event functions at any time.

In modal coordinates z = V^-1 (y, y') the reduced equations decouple:
z_m' = lam_m z_m + beta_m(tau), beta = b0 + b1 tau + sum_i bh_i cos(theta_i + Omega_i tau)
(tau: the time since the phase's start t0, theta_i = Omega_i t0 + phi_i), so

    z_m(tau) = e^{lam tau} z_m(0) + expint(lam, 0, tau) b0_m + linint(lam, tau) b1_m
               + sum_i bh_mi (e^{i theta} expint(lam, i Omega, tau) + e^{-i theta} expint(lam, -i Omega, tau)) / 2

(:mod:`.spectral`).  Every event function is g(tau) = Re(W z(tau)) + e0 + e1 tau
+ sum_i Dh_i cos(theta_i + Omega_i tau).

:func:`bound` bounds |g^(p)| (p = 2, 3) on [a, a + h] from the modal amplitudes:
|z_m(s)| <= e^{max(Re lam, 0) h} (|z_m(a)| + h max|beta_m|), and
z^(p) = lam^p z + sum_{i < p} lam^(p-1-i) beta^(i).
"""

from __future__ import annotations

import cmath
import math
from collections import namedtuple

import numpy as np
from numba import njit

from .combo import mm
from .spectral import expint, linint

Phase = namedtuple("Phase", "t0 z0 b0 b1 bh theta e0 e1 u0 bs")


@njit(cache=True)
def start(cb, asm, q, v, t0):
    """The :data:`Phase` of combination ``cb`` from the state (q, q') = (``q``, ``v``) at time ``t0``."""
    n, ns, r = len(q), len(cb.stuck), cb.Z.shape[1]
    u0, bs = np.empty(ns), np.empty(ns)
    for i in range(ns):
        u0[i] = asm.contact_dir[cb.stuck[i]] @ q
        bs[i] = asm.belt[cb.stuck[i]]
    ru, rb = cb.R @ u0 if ns else np.zeros(n), cb.R @ bs if ns else np.zeros(n)
    zt = cb.Z.T.copy()
    x = np.concatenate((zt @ (q - ru), zt @ (v - rb))).astype(np.complex128)
    z0 = cb.Vi @ x if r else np.zeros(0, dtype=np.complex128)
    p0 = zt @ (cb.f0 - asm.damping @ rb - cb.keff @ ru)
    p1 = -(zt @ (cb.keff @ rb))
    pg = mm(zt, asm.force_dir.T.copy())
    for f in range(pg.shape[1]):
        pg[:, f] *= asm.force_amp[f]
    vb = cb.VB
    b0 = vb @ p0.astype(np.complex128) if r else np.zeros(0, dtype=np.complex128)
    b1 = vb @ p1.astype(np.complex128) if r else np.zeros(0, dtype=np.complex128)
    bh = mm(vb, pg.astype(np.complex128))
    theta = asm.force_omega * t0 + asm.force_phi
    tv = np.concatenate((ru, rb))
    e0 = cb.D @ tv + cb.dc
    e1 = cb.D[:, :n] @ rb
    return Phase(t0, z0, b0, b1, bh, theta, e0, e1, u0, bs)


@njit(cache=True)
def modal_at(cb, ph, om, tau):
    """z(tau): the modal coordinates ``tau`` after the phase's start (``om``: the forces' Omega)."""
    r2 = len(cb.lam)
    z = np.empty(r2, dtype=np.complex128)
    for a in range(r2):
        lam = cb.lam[a]
        s = cmath.exp(lam * tau) * ph.z0[a] + expint(lam, 0.0j, tau) * ph.b0[a] + linint(lam, tau) * ph.b1[a]
        for f in range(len(om)):
            w = 1j * om[f]
            ep = cmath.exp(1j * ph.theta[f])
            s += 0.5 * ph.bh[a, f] * (ep * expint(lam, w, tau) + ep.conjugate() * expint(lam, -w, tau))
        z[a] = s
    return z


@njit(cache=True)
def beta_at(ph, om, tau, order):
    """beta^(order)(tau), order 0 or 1: the modal forcing or its rate."""
    r2 = len(ph.z0)
    out = np.empty(r2, dtype=np.complex128)
    for a in range(r2):
        s = ph.b0[a] + ph.b1[a] * tau if order == 0 else ph.b1[a]
        for f in range(len(om)):
            arg = ph.theta[f] + om[f] * tau
            s += ph.bh[a, f] * (math.cos(arg) if order == 0 else -om[f] * math.sin(arg))
        out[a] = s
    return out


@njit(cache=True)
def state_at(cb, ph, om, tau):
    """(q, q') at ``tau`` after the phase's start."""
    n, r = cb.Z.shape
    x = (cb.V @ modal_at(cb, ph, om, tau)).real if r else np.zeros(0)
    q, v = cb.Z @ x[:r], cb.Z @ x[r:]
    if len(ph.u0):
        q += cb.R @ (ph.u0 + ph.bs * tau)
        v += cb.R @ ph.bs
    return q, v


@njit(cache=True)
def harmonic(dh_row, ph, om, tau, order):
    """sum_i Dh_i d^order/dtau^order cos(theta_i + Omega_i tau)."""
    s = 0.0
    for f in range(len(om)):
        arg = ph.theta[f] + om[f] * tau
        c = math.cos(arg) if order % 2 == 0 else math.sin(arg)
        sign = 1.0 if order % 4 in (0, 3) else -1.0
        s += dh_row[f] * sign * om[f] ** order * c
    return s


@njit(cache=True)
def event_value(cb, ph, om, e, tau, z):
    """Event function ``e`` at ``tau`` (``z`` = z(tau))."""
    s = ph.e0[e] + ph.e1[e] * tau + harmonic(cb.Dh[e], ph, om, tau, 0)
    for a in range(len(z)):
        s += (cb.W[e, a] * z[a]).real
    return s


@njit(cache=True)
def event_rate(cb, ph, om, e, tau, z, order):
    """d^order g_e / dtau^order at ``tau`` (order 1 or 2; ``z`` = z(tau))."""
    lam = cb.lam
    beta = beta_at(ph, om, tau, 0)
    s = harmonic(cb.Dh[e], ph, om, tau, order) + (ph.e1[e] if order == 1 else 0.0)
    rate1 = beta_at(ph, om, tau, 1) if order == 2 else beta
    for a in range(len(z)):
        d = lam[a] * z[a] + beta[a]
        if order == 2:
            d = lam[a] * d + rate1[a]
        s += (cb.W[e, a] * d).real
    return s


@njit(cache=True)
def bound(cb, ph, om, e, a, h, za, order):
    """A bound on |g_e^(order)| over [a, a + h] (order 2 or 3) from the modal amplitudes |z(a)|."""
    tmax = abs(a) + h
    s = 0.0
    for f in range(len(om)):
        s += abs(cb.Dh[e, f]) * om[f] ** order
    for m in range(len(za)):
        lam = cb.lam[m]
        bt = np.zeros(order)  # bounds on |beta^(i)| over the interval
        bt[0] = abs(ph.b0[m]) + abs(ph.b1[m]) * tmax
        bt[1] = abs(ph.b1[m])
        for f in range(len(om)):
            for i in range(order):
                bt[i] += abs(ph.bh[m, f]) * om[f] ** i
        zb = math.exp(max(lam.real, 0.0) * h) * (abs(za[m]) + h * bt[0])
        al = abs(lam)
        dz = al ** order * zb
        for i in range(order):
            dz += al ** (order - 1 - i) * bt[i]
        s += abs(cb.W[e, m]) * dz
    return s


@njit(cache=True)
def event_size(cb, ph, e, tau, z):
    """The sum of the magnitudes of event function ``e``'s terms at ``tau``: its rounding is a few EPS of it."""
    s = abs(ph.e0[e]) + abs(ph.e1[e] * tau) + np.abs(cb.Dh[e]).sum()
    for a in range(len(z)):
        s += abs(cb.W[e, a] * z[a])
    return s
