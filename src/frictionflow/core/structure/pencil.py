"""Eigenpairs of the general route refined on the quadratic pencil P(l) = l^2 M_r + l C_r + K_r.

``np.linalg.eig`` of the first-order matrix A = [[0, I], [-M_r^-1 K_r, -M_r^-1 C_r]] is backward stable: each root
comes out within about EPS ||A|| of a root of a nearby matrix.  A stiff damper makes ||A|| its rate c while the
structure's other roots stay of order 1 (and a creep root of order k / c): those lose about c EPS of their size
(a 2-dof chain with a damper of 1e9: its oscillating pair 3e-8 off, its creep root 4e-7, and the run's switch times
7e-7).  Newton's method on P(l) phi = 0 evaluates the pencil in the structure's own terms, where the terms that
cancel are each of the size of the root's own, so a few steps take each root and its vectors to rounding of
their size.  The right vector phi and the left one psi (psi^T P(l) = 0) then give V's column [phi; l phi] and
V^-1's row [psi^T (l M_r + C_r), psi^T M_r] / (psi^T P'(l) phi) without inverting the ill-conditioned V.

Only roots whose backward error bound EPS ||A|| exceeds :data:`REFINE_ABOVE` of their modulus are refined: on
well-scaled structures ``eig``'s answer stands as it was.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..stiff import lu_factor, lu_solve

#: refine a root when EPS ||A|| is above this fraction of its modulus (rates spread beyond about 500)
REFINE_ABOVE = 1e-13
#: Newton steps at most per vector (each converges quadratically from eig's answer; two reach rounding)
STEPS = 3
EPS = np.finfo(np.float64).eps


@njit(cache=True)
def pencil(mr, cr, kr, lam, transpose):
    """(P(lam), P'(lam)) as complex matrices, transposed for a left vector."""
    p = (lam * lam) * mr + lam * cr + kr
    dp = (2.0 * lam) * mr + cr
    if transpose:
        return np.ascontiguousarray(p.T).astype(np.complex128), np.ascontiguousarray(dp.T).astype(np.complex128)
    return p.astype(np.complex128), dp.astype(np.complex128)


@njit(cache=True)
def newton(mr, cr, kr, lam, x, transpose):
    """(lam, x) after Newton's steps on P(lam) x = 0 (P^T for a left vector), x scaled to 1 at its largest entry
    (the bordered system of a simple root is regular); the steps stop once the root no longer moves."""
    r = len(x)
    k = np.argmax(np.abs(x))
    x = x / x[k]
    b = np.zeros((r + 1, r + 1), dtype=np.complex128)
    rhs = np.zeros((1, r + 1), dtype=np.complex128)  # one row: lu_solve's layout
    piv = np.zeros(r + 1, dtype=np.int64)
    for _ in range(STEPS):
        p, dp = pencil(mr, cr, kr, lam, transpose)
        b[:r, :r] = p
        b[:r, r] = dp @ x
        b[r, :] = 0.0
        b[r, k] = 1.0
        rhs[0, :r] = -(p @ x)
        rhs[0, r] = 0.0
        # LU, not np.linalg.solve: its compiled form (and the try a singular matrix needs), linked into every
        # caller of the combination builder and optimised again in each, made the first structure run compile
        # about 17 s longer
        if not lu_factor(b, piv):  # singular to rounding: a defective root, left to the caller's check
            return complex(np.nan, 0.0), x
        lu_solve(b, piv, rhs, 0)
        d = rhs[0]
        x = x + d[:r]
        lam = lam + d[r]
        if abs(d[r]) <= EPS * abs(lam):
            break
    return lam, x


@njit(cache=True)
def refined_root(mr, cr, kr, lam, phi, bound):
    """(ok, root, right vector) of ``lam`` with start vector ``phi`` after :func:`newton`; ok False where it did not
    converge near ``lam`` (``bound``: EPS ||A||, the size below which a root is rounding)."""
    lr, x = newton(mr, cr, kr, lam, phi, np.bool_(False))
    size = max(abs(lr), bound)
    return np.isfinite(lr) and abs(lr - lam) <= 1e-4 * size, lr, x


@njit(cache=True)
def left_row(mr, cr, kr, lr, start, bound):
    """(ok, psi): the left vector of the root ``lr`` (psi^T P(lr) = 0) from ``start`` (psi^T up to scale), which makes
    V^-1's row [psi^T (l M_r + C_r), psi^T M_r] / (psi^T P'(l) phi); ok False where it converged elsewhere."""
    ll, psi = newton(mr, cr, kr, lr, start, np.bool_(True))
    return abs(ll - lr) <= 1e3 * EPS * max(abs(lr), bound), psi


@njit(cache=True)
def refine(mr, cr, kr, a, lam, v, vi):
    """Refine in place the roots ``lam``, the columns [phi; lam phi] of ``v`` (2 r rows) and, where ``vi`` has rows
    (V^-1 of the general route; none: the right vectors only), its rows, of the roots whose backward error bound
    EPS ||A|| (``a``: the first-order matrix) is above :data:`REFINE_ABOVE` of their size; how many were refined.

    A refinement is kept only where the vectors converged to the same root (a defective, repeated root has no
    regular bordered system: it stays as ``eig`` gave it, and the caller's repeated-root check decides)."""
    r = mr.shape[0]
    bound = EPS * np.max(np.abs(a).sum(axis=1)) if a.size else 0.0
    rows = vi.shape[0] > 0
    mri = np.linalg.inv(mr).astype(np.complex128)  # vi's velocity columns over it: a left vector's start
    done = 0
    for i in range(len(lam)):
        if bound <= REFINE_ABOVE * abs(lam[i]):
            continue
        ok, lr, phi = refined_root(mr, cr, kr, lam[i], np.ascontiguousarray(v[:r, i]), bound)
        if rows and ok:  # vi's row is psi^T M_r / d at the start
            ok, psi = left_row(mr, cr, kr, lr, np.ascontiguousarray(vi[i, r:]) @ mri, bound)
            d = psi @ (((2.0 * lr) * mr + cr).astype(np.complex128) @ phi) if ok else 0j
            ok = d != 0.0
            if ok:
                vi[i, :r] = (psi @ (lr * mr + cr).astype(np.complex128)) / d
                vi[i, r:] = (psi @ mr.astype(np.complex128)) / d
        if ok:
            lam[i] = lr
            v[:r, i], v[r:, i] = phi, lr * phi
            done += 1
    return done
