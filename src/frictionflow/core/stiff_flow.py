"""Flow maps of laws with internal state with their variational equations: the monodromy on the whole state.

The state y = (X, X', z_1 .. z_m) of :mod:`.stiff` flows by y' = f(t, y); its
sensitivity Phi = dy(t)/dy(t0) by Phi' = J(y) Phi, Phi(t0) = I, J the exact
Jacobian the engine assembles from the law's derivative record.  Both are
integrated together by Rodas4 on the augmented system (y, Phi).  Its Jacobian
is block lower-triangular,

    [[J, 0], [d(J Phi)/dy, I (x) J]],

so each stage solves with the one LU factorisation of (1/(gamma h) - J): first
the state's increment k_y, then each column of Phi's with the coupling
d(J Phi)/dy k_y on the right.  That coupling (the law's second derivatives)
is the one term taken by differences, of the exact Jacobian: Rosenbrock
methods keep their order with it.  At the kink of |V_r| (V_r = 0) the
difference is one-sided, both points on V_r's side, so it never spans the jump of J;
and a stage that reaches or passes V_r = 0 (the step that ends on the kink) takes
the start side's J continued to it: Phi' = J Phi is that side's motion up to the
kink, and J of the other side at a stage would make the step first order.

The error is controlled on y and on Phi (entry (i, j) against its own scale,
size_i / size_j of the state's scales, and the relative tolerance).  J does
not depend on tau (the external force is additive), so Phi has no
non-autonomous terms.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .friction import external_force_rate
from .roots import EPS, RUNNING, bracket, update
from .stiff import A_TAB, C_NODE, C_TAB, D_TAB, DONE, GAMMA, STEP_CAP, TINY_STEP, evaluate, lu_factor, lu_solve, scratch

#: relative size of the differences of the Jacobian (the coupling term): about the cube root of rounding
DIFF_STEP = 1e-6

__all__ = ["DONE", "STEP_CAP", "TINY_STEP", "field_at", "flow_variational"]


@njit(cache=True)
def field_at(q, zeta, vb, t, y):
    """(y', J): the vector field and its exact Jacobian at (t, y)."""
    n = len(y)
    ws = scratch(n)
    dy, dw, jac, jw, d, ft = ws[0], ws[1], ws[2], ws[3], ws[9], ws[10]
    evaluate(q, zeta, vb, t, y, dy, dw, jac, jw, ft, True, d)
    return dy.copy(), jac.copy()


@njit(cache=True)
def coupling(q, zeta, vb, t, y, size, ws, dj, jn):
    """dj[j] = dJ/dy_j at (t, y) by central differences of the exact Jacobian, and ``jn`` = J at (t, y); returns
    the side of V_r = 0 the step is on (+1, -1: V_r's sign, or where it is heading from V_r = 0).

    Within a difference step of V_r = 0 (the kink of |V_r|, where J jumps) both are one-sided, on the side
    V_r is heading for (V_r' = -X''): the difference never spans the jump, and J there is its limit from
    that side (by linear extrapolation), not the value at V_r = 0 exactly, which neither side has.
    """
    n = len(y)
    dy, dw, jac, jw, d, ft = ws[0], ws[1], ws[2], ws[3], ws[9], ws[10]
    evaluate(q, zeta, vb, t, y, dy, dw, jac, jw, ft, True, d)
    jn[:, :] = jac
    yp = y.copy()
    jp = np.empty((n, n))
    s = vb - y[1]
    toward = s if s != 0.0 else -dy[1]
    side = 1.0 if toward >= 0.0 else -1.0
    for j in range(n):
        dl = DIFF_STEP * (abs(y[j]) + size[j])
        near = j == 1 and abs(s) < dl
        lo, hi = -dl, dl
        if near:  # X' - dl, X' - 2 dl lie on V_r > 0
            lo, hi = (-2.0 * dl, -dl) if side > 0.0 else (dl, 2.0 * dl)
        yp[j] = y[j] + hi
        evaluate(q, zeta, vb, t, yp, dy, dw, jac, jw, ft, True, d)
        jp[:, :] = jac
        yp[j] = y[j] + lo
        evaluate(q, zeta, vb, t, yp, dy, dw, jac, jw, ft, True, d)
        yp[j] = y[j]
        for r in range(n):
            for c in range(n):
                dj[j, r, c] = (jp[r, c] - jac[r, c]) / (hi - lo)
                if near:  # the one-sided limit at V_r = 0
                    jn[r, c] = jac[r, c] - lo * dj[j, r, c]
    return side


@njit(cache=True)
def _phi_rhs(jac, phii, kp, st, h, dj, ky, phi, col, out):
    """The right-hand side of Phi's stage ``st``, column ``col``: J(Y_i) Phi_i + sum_j C_ij Kp_j / h
    + (d(J Phi)/dy k_y) of the step's start."""
    n = len(out)
    for r in range(n):
        acc = 0.0
        for c in range(n):
            acc += jac[r, c] * phii[c, col]
        for j in range(st):
            acc += C_TAB[st, j] * kp[j, r, col] / h
        for j in range(n):
            cj = 0.0
            for c in range(n):
                cj += dj[j, r, c] * phi[c, col]
            acc += ky[j] * cj
        out[r] = acc


@njit(cache=True)
def variational_step(q, zeta, vb, t, y, phi, h, ynew, phinew, tols, ws, vs):
    """One Rodas4 step of (y, Phi) of length ``h``; returns the error norm (rms over y and Phi; inf if it failed).

    ``tols``: (the state's absolute scales then rtol (as :func:`.stiff.rodas_step`), Phi's absolute scales
    (n x n), the state's scales for the differences); ``ws``: :func:`.stiff.scratch`;
    ``vs``: (Phi's stage increments (6, n, n), stage Phi, dJ/dy (n, n, n), a column, J at the start, an
    n x n room)."""
    n = len(y)
    tol, ptol, size = tols
    dy, dw, jac, jw, a, piv, k, kw, yi, d, ft = ws[:11]
    kp, phii, dj, col, jn = vs[:5]
    side = coupling(q, zeta, vb, t, y, size, ws, dj, jn)
    evaluate(q, zeta, vb, t, y, dy, dw, jac, jw, ft, False, d)
    jac[:, :] = jn
    fr = external_force_rate(q, t)
    for i in range(n):
        for j in range(n):
            a[i, j] = -jac[i, j]
        a[i, i] += 1.0 / (GAMMA * h)
    if not lu_factor(a, piv):
        return np.inf
    for st in range(6):
        yi[:] = y
        phii[:, :] = phi
        for j in range(st):
            yi += A_TAB[st, j] * k[j]
            phii += A_TAB[st, j] * kp[j]
        if st > 0 and (vb - yi[1]) * side <= 0.0:  # on or past the kink: the start side's J continued
            _side_jacobian(q, zeta, vb, t + C_NODE[st] * h, yi, side, size[1], ws, vs)
        elif st > 0:
            evaluate(q, zeta, vb, t + C_NODE[st] * h, yi, dy, dw, jac, jw, ft, True, d)
        for c in range(n):
            acc = dy[c]
            for j in range(st):
                acc += C_TAB[st, j] * k[j, c] / h
            k[st, c] = acc
        k[st, 1] += h * D_TAB[st] * fr
        lu_solve(a, piv, k, st)
        for cc in range(n):
            _phi_rhs(jac, phii, kp, st, h, dj, k[st], phi, cc, col[0])
            lu_solve(a, piv, col, 0)
            kp[st, :, cc] = col[0]
    return _finish(y, phi, yi, phii, k, kp, ynew, phinew, tol, ptol)


@njit(cache=True)
def _side_jacobian(q, zeta, vb, t, yi, side, size, ws, vs):
    """``jac`` at a stage point on or past V_r = 0: the J of V_r's ``side`` (+1, -1) continued to it, linear in
    V_r through two points on that side (V_r = side dl, 2 side dl), and ``dy`` the stage's own (the field is
    continuous across the kink)."""
    dy, dw, jac, jw, d, ft = ws[0], ws[1], ws[2], ws[3], ws[9], ws[10]
    jn, j2 = vs[4], vs[5]
    n = len(yi)
    dl = DIFF_STEP * (abs(yi[1]) + size)
    v = yi[1]
    yi[1] = vb - side * dl
    evaluate(q, zeta, vb, t, yi, dy, dw, jac, jw, ft, True, d)
    jn[:, :] = jac
    yi[1] = vb - 2.0 * side * dl
    evaluate(q, zeta, vb, t, yi, dy, dw, jac, jw, ft, True, d)
    j2[:, :] = jac
    yi[1] = v
    evaluate(q, zeta, vb, t, yi, dy, dw, jac, jw, ft, False, d)
    w = (vb - v - side * dl) / (side * dl)  # V_r's distance from the first point in steps of the second's
    for r in range(n):
        for c in range(n):
            jac[r, c] = jn[r, c] + w * (j2[r, c] - jn[r, c])


@njit(cache=True)
def _finish(y, phi, yi, phii, k, kp, ynew, phinew, tol, ptol):
    """The new (y, Phi) from the last stage, and the rms of its increment over the scales."""
    n = len(y)
    rtol = tol[n]
    err = 0.0
    for c in range(n):
        ynew[c] = yi[c] + k[5, c]
        e = k[5, c] / (tol[c] + rtol * max(abs(y[c]), abs(ynew[c])))
        err += e * e
    for r in range(n):
        for c in range(n):
            phinew[r, c] = phii[r, c] + kp[5, r, c]
            e = kp[5, r, c] / (ptol[r, c] + rtol * max(abs(phi[r, c]), abs(phinew[r, c])))
            err += e * e
    err = math.sqrt(err / (n + n * n))
    return err if err == err else np.inf


@njit(cache=True)
def to_kink(q, zeta, vb, t, y, phi, h, ynew, phinew, tols, ws, vs):
    """The step from (t, y, Phi) that ends where V_r = 0 inside the accepted step of length ``h`` (V_r changes
    sign over it): its length h' by Illinois on V_r(t + h'), to the step length at rounding, on the far side
    (V_r of the new sign, or 0).  Phi' jumps there with J: a step across it would be first order.
    ``ynew``, ``phinew``: the located step's end; returns (h', its error norm)."""
    b = bracket(0.0, h, vb - y[1], vb - ynew[1], 0.0, 4.0 * EPS, 0.0, 100)
    err = 0.0
    x_last = h
    while b.status == RUNNING:
        x_last = b.x
        err = variational_step(q, zeta, vb, t, y, phi, x_last, ynew, phinew, tols, ws, vs)
        b = update(b, x_last, vb - ynew[1] if err < np.inf else vb - y[1])
    if x_last != b.hi:  # the last point evaluated was not the end kept: the step to that end
        err = variational_step(q, zeta, vb, t, y, phi, b.hi, ynew, phinew, tols, ws, vs)
    return b.hi, err


@njit(cache=True)
def flow_variational(q, zeta, vb, y0, t0, duration, tol, ptol, size, steps):
    """(y, Phi) from (t0, y0, I) over ``duration``; returns (y, Phi, status, steps taken).

    ``steps``: (first step, largest step, step cap); status :data:`DONE`, :data:`STEP_CAP` or :data:`TINY_STEP`.
    """
    n = len(y0)
    h, h_max, max_steps = steps[0], steps[1], int(steps[2])
    y, ynew = y0.copy(), np.empty(n)
    phi, phinew = np.eye(n), np.empty((n, n))
    ws = scratch(n)
    vs = (np.zeros((6, n, n)), np.empty((n, n)), np.empty((n, n, n)), np.empty((1, n)), np.empty((n, n)),
          np.empty((n, n)))
    t, t_end = t0, t0 + duration
    tols = (tol, ptol, size)
    taken, rejected = 0, False
    while t < t_end:
        if taken >= max_steps:
            return y, phi, STEP_CAP, taken
        if h < 1e-14 * max(1.0, abs(t)):
            return y, phi, TINY_STEP, taken
        h = min(h, h_max)
        last = t + h >= t_end - 1e-14 * max(1.0, abs(t_end))
        hh = t_end - t if last else h
        err = variational_step(q, zeta, vb, t, y, phi, hh, ynew, phinew, tols, ws, vs)
        taken += 1
        adv = hh
        if err < np.inf and (vb - y[1]) * (vb - ynew[1]) < 0.0:  # V_r changes sign: J jumps there, a step ends on it
            adv, err = to_kink(q, zeta, vb, t, y, phi, hh, ynew, phinew, tols, ws, vs)
            last = last and adv == hh
        fac = 0.2 if err == np.inf else min(6.0, max(0.2, 0.9 * err ** -0.25))
        if err > 1.0:
            h, rejected = adv * fac, True
            continue
        t = t_end if last else t + adv
        y[:] = ynew
        phi[:, :] = phinew
        h = max(adv, 1e-3 * hh) * (min(fac, 1.0) if rejected else fac)  # no growth right after a rejection
        rejected = False
    return y, phi, DONE, taken
