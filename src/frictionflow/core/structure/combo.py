"""One combination of contact modes: its reduced equations, their eigen-decomposition, its event maps.

With the stuck contacts S (directions E_S, belt speeds b_S) the coordinates
split as q = Z y + R u: Z (n, r) an orthonormal basis of E_S's null space,
R = M^-1 E_S^T G with G = (E_S M^-1 E_S^T)^-1, so that E_S R = I and
Z^T M R = 0, and u = E_S q = u(t0) + b_S (t - t0) is known.  Projected on Z
the equations lose the constraint forces:

    M_r y'' + C_r y' + K_r y = Z^T (f0 - C R b_S - K_eff R u(t) + forces(t))

with M_r = Z^T M Z, C_r = Z^T C Z, K_r = Z^T K_eff Z.  K_eff = K - sum over
slipping j of sigma_j F_d,j e_j n_j^T (a normal load N_j = P_j + n_j . q
makes the friction force depend on q), f0 = sum sigma_j F_d,j P_j e_j.  The
first-order matrix A = [[0, I], [-M_r^-1 K_r, -M_r^-1 C_r]] is
eigen-decomposed once per combination: A = V diag(lam) V^-1.

The held forces of the stuck contacts (what the constraints must hold) are
lambda_S = G E_S M^-1 (C q' + K_eff q - f0 - forces(t)): with the contact's
``stick_force`` "spring" the damper term is left out of the force compared
with F_s N_j (the friction force itself always keeps it).

Event functions (three slots per contact j, in this order):
slot 3j: slipping, sigma_j V_r,j; stuck, F_s,j N_j - lambda_j; slot 3j+1:
stuck, F_s,j N_j + lambda_j; slot 3j+2: N_j (when it depends on q).  Each is
an affine map of (q, q') (rows of ``D``, constant ``dc``) plus harmonic
terms (``Dh``: coefficient of cos(Omega_i t + phi_i)); ``W`` = D T V maps
the modal coordinates (T: (y, y') -> (q, q')).

Conjugate pairs.  On the real-mode route (:func:`classical`) an underdamped
mode a has the roots lam_a and conj(lam_a), with conjugate columns of V and
rows of V^-1 and V^-1 B: from real start data its two modal coordinates stay
conjugate, and the engine only takes Re(sum_m row_m z_m) or bounds
sum_m |row_m| |z_m|, in which the pair counts twice its representative.  So
a :data:`Combo` keeps one root of each such pair (:func:`classical`): ``lam``
holds each underdamped mode's root with Im > 0 and both real roots of each
overdamped one; ``Vi``, ``VB`` (and ``b1``, ``bh``) their rows; ``V``
(2 r rows) and ``W`` their columns, the representatives' doubled.  Then
Re(V z) and Re(W z) are the full sums, and |2 W_a| |z_a| the pair's two
terms.  V diag(lam) V^-1 is no longer the first-order matrix there: V, Vi
are not square.  The general route (np.linalg.eig) keeps every root.
``WA`` = |W| elementwise (the walk's bounds take it at every interval).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit
from numba.typed import List

from ..layout import FD, FS, RESULTANT, STICK
from ..options import NO_RUNTIME
from .pencil import refine
from .sparsity import combo_pattern

Combo = namedtuple("Combo", "modes stuck Z R HE keff f0 lam V Vi VB D dc Dh active W ZT bs rb b1 bh e1 WA nz")
#: a reduced first-order matrix's eigen-decomposition (:func:`decompose`): the roots kept, V's columns, V^-1's and
#: V^-1 B's rows for them, whether it is the real-mode route's (:func:`classical`: one root of each conjugate pair), its
#: real modes Phi (r x r; empty off that route) and each kept root's index among both roots of every mode (l1 of mode
#: a at a, l2 at r + a; every root's index off that route)
Modes = namedtuple("Modes", "lam V Vi VB real phi orig")
#: what the stick rule needs of a combination (no eigen-decomposition): its held forces and accelerations
Split = namedtuple("Split", "modes stuck R HE keff f0")
#: the parts of an Assembly a :data:`Split` is made of (a function with numba's runtime that takes a record counts
#: references to each of its arrays on entry and exit: 4 here, 17 for the Assembly)
Contacts = namedtuple("Contacts", "stiffness law normal contact_dir")
#: event slots per contact: the mode's own boundary (two sides while stuck) and the normal load
N_SLOTS = 3
#: a stuck set whose directions are this close to dependent is refused (its held forces are not defined)
RANK_TOL = 1e-10
#: the combinations kept per run, and the memory they may take: the first ones met (a chain with many contacts
#: meets new ones at most switches; on ten masses a third of the switches return to one met before)
CACHE_SIZE = 1024
CACHE_BYTES = 32_000_000
#: a run's combinations: the records (a typed list), their :data:`Split` parts (a typed list of the same records' arrays:
#: the stick rule reads 6 arrays instead of 23, each counted at every read), their modes as the rows of ``keys`` (scanned
#: instead of the records: reading a record from the list counts references to each of its arrays) and ``used`` =
#: [count, bytes], and its :data:`Eigs`
Cache = namedtuple("Cache", "combos splits keys used eigs")
#: a run's eigen-decompositions of the symmetric blocks :func:`block_eigh` met (a chain cut into pieces by its stuck
#: masses meets the same pieces in many combinations): ``index`` rows [offset, size] into ``store``, which holds at each
#: offset the block's entries (the key: the same numbers give LAPACK the same call, so a hit is exact), its eigenvalues
#: and its eigenvectors (row-major); ``used`` = [entries, numbers]
Eigs = namedtuple("Eigs", "index store used")
EIG_ENTRIES = 4096
EIG_NUMBERS = 1 << 19
#: K_r symmetric and the modal damping diagonal to this fraction of their size: the real-mode route (:func:`classical`)
SYM_TOL = 1e-13
#: a mode's two roots closer than this fraction of the system's rates: (nearly) defective, the general route decides
NEAR_DOUBLE = 1e-6
#: an eigenvector basis this ill-conditioned is refused (a defective matrix: an undamped rigid mode)
COND_MAX = 1e10
#: ... and above this one where two roots coincide to :data:`REPEATED_APART` of their size: a (nearly) defective
#: double root (a critically damped mode) whose two computed roots part by ~sqrt(EPS) and whose basis loses
#: ~cond EPS: the motion ~1e-8 off (a one-dof model at zeta = 1 ended 1.1e-9 from its rest position).  A root
#: pair apart by 1e-6 of its size has a basis of condition ~1e6 and keeps its motion to ~1e-10.
COND_REPEATED = 1e6
REPEATED_APART = 1e-5


@njit(cache=True)
def mm(a, b):
    """a @ b that also takes empty operands (both of one dtype)."""
    if a.shape[0] == 0 or a.shape[1] == 0 or b.shape[1] == 0:
        return np.zeros((a.shape[0], b.shape[1]), dtype=a.dtype)
    return np.ascontiguousarray(a) @ np.ascontiguousarray(b)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def slip_into(asm, modes, keff, f0):
    """(K_eff, f0), the stiffness and the constant force of the slipping contacts' friction, into ``keff`` (holding K)
    and ``f0`` (zeros)."""
    law, normal, cdir = asm.law, asm.normal, asm.contact_dir
    n = keff.shape[0]
    for j in range(len(modes)):
        if modes[j] == STICK:
            continue
        fd = modes[j] * law[j, FD]
        for a in range(n):
            f0[a] += fd * normal[j, 0] * cdir[j, a]
        if not depends(normal, j):  # a constant normal load leaves K as it is
            continue
        for a in range(n):
            for b in range(n):
                keff[a, b] -= fd * cdir[j, a] * normal[j, 1 + b]


@njit(cache=True, inline="always")
def depends(normal, j):
    """True when contact ``j``'s normal load depends on q (a nonzero of ``normal[j, 1:]``)."""
    for b in range(1, normal.shape[1]):
        if normal[j, b] != 0.0:
            return True
    return False


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def axes_of(cdir, stuck, axis, scale, seen):
    """True when every stuck direction is scale * a unit coordinate vector, all axes distinct: ``axis`` (-1s),
    ``scale`` and ``seen`` (False per coordinate) filled in (``cdir``: the contacts' directions, a row each)."""
    n = cdir.shape[1]
    for i in range(len(stuck)):
        j = stuck[i]
        for a in range(n):
            if cdir[j, a] != 0.0:
                if axis[i] >= 0:
                    return False
                axis[i] = a
        if axis[i] < 0 or seen[axis[i]]:  # a zero or a repeated direction: the general route refuses it
            return False
        seen[axis[i]] = True
        scale[i] = cdir[j, axis[i]]
    return True


@njit(cache=True)
def axes_basis(n, axis):
    """Z of stuck directions along the coordinate axes ``axis``: it selects the other coordinates, in order."""
    free = np.ones(n, dtype=np.bool_)
    free[axis] = False
    z = np.zeros((n, n - len(axis)))
    c = 0
    for a in range(n):
        if free[a]:
            z[a, c] = 1.0
            c += 1
    return z


@njit(cache=True)
def axes_held(minv, axis, scale):
    """(R, HE) of stuck directions along coordinate axes (:func:`held_split`'s numbers on that route)."""
    n, ns = minv.shape[0], len(axis)
    mie, gi = np.empty((n, ns)), np.empty((ns, ns))  # M^-1 E_S^T, E_S M^-1 E_S^T
    for a in range(n):
        for i in range(ns):
            mie[a, i] = minv[a, axis[i]] * scale[i]
    for i in range(ns):
        for c in range(ns):
            gi[i, c] = scale[i] * mie[axis[i], c]
    r = mie_times_g(mie, gi)
    return r, r.T.copy()


@njit(cache=True)
def mie_times_g(mie, gi):
    """R = M^-1 E_S^T G, G = gi^-1: a diagonal gi (a diagonal M) divides columns (G's entries are 1 / gi_ii)."""
    ns = gi.shape[0]
    for i in range(ns):
        for c in range(ns):
            if i != c and gi[i, c] != 0.0:
                return mm(mie, np.linalg.inv(gi))
    r = np.empty_like(mie)
    for c in range(ns):
        g = 1.0 / gi[c, c]
        for a in range(mie.shape[0]):
            r[a, c] = mie[a, c] * g
    return r


@njit(cache=True)
def constraint_split(cdir, minv, stuck):
    """(Z, R, HE) of the stuck set (HE = G E_S M^-1: held forces from the forces on the structure; ``cdir``: the
    contacts' directions, a row each)."""
    r, he = held_split(cdir, minv, stuck)
    return null_basis(cdir, stuck), r, he


@njit(cache=True)
def null_basis(cdir, stuck):
    """Z: an orthonormal basis of the stuck directions' null space (``cdir``: the contacts' directions, a row each)."""
    n, ns = cdir.shape[1], len(stuck)
    if ns == 0:
        return np.eye(n)
    axis, scale = np.full(ns, -1, dtype=np.int64), np.zeros(ns)
    if axes_of(cdir, stuck, axis, scale, np.zeros(n, dtype=np.bool_)):  # no SVD: the other axes span the null space
        return axes_basis(n, axis)
    _, s, vt = np.linalg.svd(stuck_rows(cdir, stuck), full_matrices=True)
    if s.min() <= RANK_TOL * s.max():
        raise ValueError("structure: the stuck contacts' directions are dependent (their held forces are not defined)")
    return vt[ns:].T.copy()


@njit(cache=True)
def held_split(cdir, minv, stuck):
    """(R, HE) of the stuck set (entries picked out when its directions are axes)."""
    n, ns = minv.shape[0], len(stuck)
    if ns == 0:
        return np.zeros((n, 0)), np.zeros((0, n))
    axis, scale = np.full(ns, -1, dtype=np.int64), np.zeros(ns)
    if axes_of(cdir, stuck, axis, scale, np.zeros(n, dtype=np.bool_)):  # the same numbers with entries picked out
        return axes_held(minv, axis, scale)
    return general_split(minv, stuck_rows(cdir, stuck))


@njit(cache=True)
def stuck_rows(cdir, stuck):
    """E_S: the stuck contacts' directions (rows of ``cdir``), one per row."""
    es = np.empty((len(stuck), cdir.shape[1]))
    for i in range(len(stuck)):
        es[i] = cdir[stuck[i]]
    return es


@njit(cache=True)
def where_equal(x, value):
    """The indices of ``x``'s entries equal to ``value`` (np.nonzero(x == value)[0] without the mask's array)."""
    count = 0
    for i in range(len(x)):
        count += x[i] == value
    out, m = np.empty(count, dtype=np.int64), 0
    for i in range(len(x)):
        if x[i] == value:
            out[m] = i
            m += 1
    return out


@njit(cache=True)
def general_split(minv, es):
    """(R, HE) for any stuck directions E_S: R = M^-1 E_S^T G, G = (E_S M^-1 E_S^T)^-1, HE = R^T."""
    mie = mm(minv, es.T.copy())
    r = np.ascontiguousarray(mm(mie, np.linalg.inv(mm(es, mie))))
    return r, r.T.copy()


@njit(cache=True, inline="always")
def contacts_of(asm):
    """The :data:`Contacts` of the Assembly ``asm`` (its arrays, not copies)."""
    return Contacts(asm.stiffness, asm.law, asm.normal, asm.contact_dir)


@njit(cache=True)
def split(asm, minv, modes):
    """The :data:`Split` of ``modes``: the stuck set's R and HE and the slipping contacts' K_eff and f0 (without Z,
    which :func:`null_basis` makes by an SVD in general; ``asm``: an Assembly or its :data:`Contacts`)."""
    stuck = where_equal(modes, STICK)
    keff, f0 = asm.stiffness.copy(), np.zeros(minv.shape[0])
    slip_into(asm, modes, keff, f0)  # a kernel without numba's runtime: the record passed costs no reference counts
    r, he = held_split(asm.contact_dir, minv, stuck)
    return Split(modes.copy(), stuck, r, he, keff, f0)


@njit(cache=True)
def selected(z):
    """(ok, rows): ok when Z only selects coordinates (one 1 per column, zeros elsewhere): column c is e_rows[c]."""
    n, r = z.shape
    rows = np.full(r, -1, dtype=np.int64)
    for i in range(n):  # row by row (row-major)
        for c in range(r):
            x = z[i, c]
            if x == 0.0:
                continue
            if x != 1.0 or rows[c] >= 0:
                return False, rows
            rows[c] = i
    return rows.min() >= 0 if r else True, rows


@njit(cache=True)
def project(a, z, sel, rows):
    """Z^T A Z (entries picked out when Z is a selection: the same numbers without the products)."""
    if not sel:
        return mm(mm(z.T.copy(), a), z)
    r = len(rows)
    out = np.empty((r, r))
    for c in range(r):
        for d in range(r):
            out[c, d] = a[rows[c], rows[d]]
    return out


@njit(cache=True)
def columns(a, z, sel, rows):
    """A Z (columns picked out when Z is a selection)."""
    if not sel:
        return mm(a, z)
    out = np.empty((a.shape[0], len(rows)))
    for i in range(a.shape[0]):
        for c in range(len(rows)):
            out[i, c] = a[i, rows[c]]
    return out


@njit(cache=True)
def decompose(m, c, k, z, sel, rows, eigs=None):
    """:data:`Modes` of the reduced first-order matrix (B = [0; M_r^-1]): one root of each conjugate pair on the
    real-mode route (the module's docstring), every root on the general one.

    ``sel``, ``rows``: :func:`selected` of Z; ``eigs``: the run's :data:`Eigs` (or None).
    """
    r = z.shape[1]
    if r == 0:
        e = np.zeros((0, 0), dtype=np.complex128)
        return Modes(np.zeros(0, dtype=np.complex128), e, e, e, True, np.zeros((0, 0)), np.zeros(0, dtype=np.int64))
    mr, kr, cr = project(m, z, sel, rows), project(k, z, sel, rows), project(c, z, sel, rows)
    md = classical(mr, kr, cr, eigs)
    if not md.real:
        mri = np.linalg.inv(mr)
        a = np.zeros((2 * r, 2 * r))
        a[:r, r:] = np.eye(r)
        a[r:, :r] = -mm(mri, kr)
        a[r:, r:] = -mm(mri, cr)
        lam, v = np.linalg.eig(a.astype(np.complex128))
        vi = np.ascontiguousarray(np.linalg.inv(v))  # C order, as the stability analysis's: one compiled refine
        refine(mr, cr, kr, a, lam, v, vi)  # roots a stiff element's rate would leave ~its rate x EPS off
        vb = mm(np.ascontiguousarray(vi[:, r:]), mri.astype(np.complex128))
        c_ = np.ascontiguousarray
        md = Modes(c_(lam), c_(v), c_(vi), c_(vb), False, np.zeros((0, 0)), np.arange(2 * r))
    fv, fvi = full_norms(md, rate_scale(mr, kr, cr))
    if math.sqrt(fv * fvi) > COND_MAX * 2 * r:
        raise ValueError("structure: a mode combination's matrix is defective (e.g. an undamped rigid mode)")
    if math.sqrt(fv * fvi) > COND_REPEATED * 2 * r and repeated_root(md, rate_scale(mr, kr, cr)):
        raise ValueError("structure: a mode combination has a repeated root (e.g. a critically damped mode)")
    return md


@njit(cache=True)
def repeated_root(md, rate):
    """Whether two roots coincide to :data:`REPEATED_APART` of the larger's modulus (both nonzero), each ill
    conditioned beyond :data:`COND_REPEATED` (:func:`root_condition`): a defective pair.  Equal roots of
    independent modes (two equal masses) have well-conditioned columns and pass."""
    lam = md.lam
    for i in range(len(lam)):
        for j in range(i):
            size = max(abs(lam[i]), abs(lam[j]))
            if size > 0.0 and abs(lam[i] - lam[j]) <= REPEATED_APART * size:
                if min(root_condition(md, rate, i), root_condition(md, rate, j)) > COND_REPEATED:
                    return True
    return False


@njit(cache=True)
def root_condition(md, rate, c):
    """|V e_c| |e_c^T V^-1| of root ``c``, velocities over ``rate`` (:func:`root_norms`): its eigenvalue's
    condition number, ~1 / the distance to its partner in a defective pair."""
    sv, svi = root_norms(md, rate, c)
    return math.sqrt(sv * svi)


@njit(cache=True)
def rate_scale(mr, kr, cr):
    """A rate of the reduced structure from its diagonals: sqrt(max K_ii / M_ii), else max C_ii / M_ii, else 1.
    The velocities are measured over it when the basis's condition is judged (:func:`full_norms`)."""
    k2, c1 = 0.0, 0.0
    for i in range(mr.shape[0]):
        k2 = max(k2, abs(kr[i, i]) / mr[i, i])
        c1 = max(c1, abs(cr[i, i]) / mr[i, i])
    return math.sqrt(k2) if k2 > 0.0 else (c1 if c1 > 0.0 else 1.0)


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def full_norms(md, rate):
    """(sum |V_ij|^2, sum |V^-1_ij|^2) of the full first-order decomposition (every root's column and row) from
    :data:`Modes` that keep one root of a pair: its partner's column and row are the conjugates, and the kept column
    of V is doubled.  The velocity rows of V count over ``rate`` (and V^-1's velocity columns times it): the
    condition of the basis in the structure's own time, the same in any unit of time (in picoseconds a chain's
    velocity rows, 1e12 times its position rows, made a well-resolved basis look defective)."""
    fv, fvi = 0.0, 0.0
    for c in range(len(md.lam)):
        s = pair_scale(md.lam[c]) if md.real else 1.0
        sv, svi = root_norms(md, rate, c)
        fv += sv / s
        fvi += svi * s
    return fv, fvi


@njit(cache=True, inline="always")
def root_norms(md, rate, c):
    """(|V e_c|^2, |e_c^T V^-1|^2) of root ``c``, V's velocity rows over ``rate`` and V^-1's velocity columns
    times it (:func:`full_norms`)."""
    v, vi = md.V, md.Vi
    r = v.shape[0] // 2
    sv, svi = 0.0, 0.0
    for i in range(v.shape[0]):
        sv += (v[i, c].real ** 2 + v[i, c].imag ** 2) * (1.0 if i < r else 1.0 / (rate * rate))
    for i in range(vi.shape[1]):
        svi += (vi[c, i].real ** 2 + vi[c, i].imag ** 2) * (1.0 if i < r else rate * rate)
    return sv, svi


@njit(cache=True)
def modal(m, c, k, z):
    """(lam, V, V^-1, V^-1 B) of the reduced first-order matrix (B = [0; M_r^-1]), every root's (pairs expanded:
    :func:`expanded`).  With an :data:`Eigs` of its own, as a run's builder passes one: ``decompose`` is then the
    run's compilation (without one, a second of its whole tree)."""
    sel, rows = selected(z)
    return expanded(decompose(m, c, k, z, sel, rows, new_eigs()))


@njit(cache=True)
def expanded(md):
    """(lam, V, V^-1, V^-1 B) with every root of :data:`Modes` that keep one of each conjugate pair: the partner's
    root, row and column are the conjugates, the kept column of V halved."""
    if not md.real:
        return md.lam, md.V, md.Vi, md.VB
    m, n2 = len(md.lam), md.V.shape[0]
    pairs = 0
    for c in range(m):
        pairs += md.lam[c].imag != 0.0
    lam = np.empty(m + pairs, dtype=np.complex128)
    v, vi = np.empty((n2, m + pairs), dtype=np.complex128), np.empty((m + pairs, n2), dtype=np.complex128)
    vb = np.empty((m + pairs, md.VB.shape[1]), dtype=np.complex128)
    x = m
    for c in range(m):
        lam[c], v[:, c], vi[c], vb[c] = md.lam[c], md.V[:, c], md.Vi[c], md.VB[c]
        if md.lam[c].imag != 0.0:
            v[:, c] = 0.5 * md.V[:, c]
            lam[x], v[:, x] = md.lam[c].conjugate(), np.conj(v[:, c])
            vi[x], vb[x] = np.conj(md.Vi[c]), np.conj(md.VB[c])
            x += 1
    return lam, v, vi, vb


@njit(cache=True)
def blocks(a):
    """(label, count): the connected blocks of a symmetric matrix's nonzero pattern, numbered by first index."""
    r = a.shape[0]
    label, stack = np.full(r, -1, dtype=np.int64), np.empty(r, dtype=np.int64)
    count = 0
    for s in range(r):
        if label[s] >= 0:
            continue
        label[s], stack[0], top = count, s, 1
        while top:
            top -= 1
            i = stack[top]
            for j in range(r):
                if label[j] < 0 and a[i, j] != 0.0:
                    label[j], stack[top] = count, j
                    top += 1
        count += 1
    return label, count


@njit(cache=True)
def block_order(label, count):
    """(order, first): the indices block by block, ascending in each; block b's are order[first[b]:first[b + 1]] (views:
    no array per block)."""
    first = np.zeros(count + 1, dtype=np.int64)
    for i in range(len(label)):
        first[label[i] + 1] += 1
    for b in range(count):
        first[b + 1] += first[b]
    order, fill = np.empty(len(label), dtype=np.int64), first.copy()
    for i in range(len(label)):
        order[fill[label[i]]] = i
        fill[label[i]] += 1
    return order, first


@njit(cache=True)
def block_eigh(sym, eigs=None):
    """eigh of a symmetric matrix block by block (its entries outside the blocks are exact zeros); ``eigs``: the run's
    :data:`Eigs` (blocks met before taken from it) or None.

    Stuck coordinates cut a chain into pieces that do not couple: several small problems instead of one.
    """
    label, count = blocks(sym)
    if count == 1 and eigs is None:
        return np.linalg.eigh(sym)
    r = sym.shape[0]
    w2, u = np.empty(r), np.zeros((r, r))
    order, first = block_order(label, count)
    col = np.int64(0)  # (a literal 0 would compile eigs_into once more for it)
    for b in range(count):
        idx = order[first[b]:first[b + 1]]
        if len(idx) == 1:
            w2[col], u[idx[0], col] = sym[idx[0], idx[0]], 1.0
        elif eigs is None or not eigs_into(eigs, sym, idx, col, w2, u):
            sub = np.empty((len(idx), len(idx)))
            for i in range(len(idx)):
                for j in range(len(idx)):
                    sub[i, j] = sym[idx[i], idx[j]]
            wb, ub = np.linalg.eigh(sub)
            for c in range(len(idx)):
                w2[col + c] = wb[c]
                for i in range(len(idx)):
                    u[idx[i], col + c] = ub[i, c]
            if eigs is not None:
                eigs_keep(eigs, sub, wb, ub)
        col += len(idx)
    return w2, u


@njit(cache=True)
def new_eigs():
    """An empty :data:`Eigs` (its store is only written as blocks are met)."""
    return Eigs(np.empty((EIG_ENTRIES, 2), dtype=np.int64), np.empty(EIG_NUMBERS), np.zeros(2, dtype=np.int64))


@njit(cache=True, inline="always")
def same_number(a, b):
    """a and b the same float64 (0.0 and -0.0 told apart: LAPACK is only known to repeat itself on the same bits)."""
    return a == b and (a != 0.0 or math.copysign(1.0, a) == math.copysign(1.0, b))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def eigs_into(eigs, sym, idx, col, w2, u):
    """When ``eigs`` holds the block ``sym[idx][:, idx]`` (entry for entry): its eigenvalues into ``w2[col:]``, its
    eigenvectors into ``u[idx, col:]``, True; else False."""
    s, index, store = len(idx), eigs.index, eigs.store
    for e in range(eigs.used[0]):
        off = index[e, 0]
        if index[e, 1] != s or not block_equal(store, off, sym, idx):
            continue
        off += s * s
        for c in range(s):
            w2[col + c] = store[off + c]
        off += s
        for i in range(s):
            for c in range(s):
                u[idx[i], col + c] = store[off + i * s + c]
        return True
    return False


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def block_equal(store, off, sym, idx):
    """``store[off:]`` holds ``sym[idx][:, idx]`` row by row, the same bits."""
    s = len(idx)
    for i in range(s):
        for j in range(s):
            if not same_number(store[off + i * s + j], sym[idx[i], idx[j]]):
                return False
    return True


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def eigs_keep(eigs, sub, wb, ub):
    """Keep the block ``sub``'s eigenvalues ``wb`` and eigenvectors ``ub`` in ``eigs`` while there is room."""
    s, used, store = sub.shape[0], eigs.used, eigs.store
    off = used[1]
    if used[0] >= eigs.index.shape[0] or off + 2 * s * s + s > len(store):
        return
    for i in range(s):
        for j in range(s):
            store[off + i * s + j] = sub[i, j]
            store[off + s * s + s + i * s + j] = ub[i, j]
        store[off + s * s + i] = wb[i]
    eigs.index[used[0], 0], eigs.index[used[0], 1] = off, s
    used[0], used[1] = used[0] + 1, off + 2 * s * s + s


@njit(cache=True)
def mass_modes(mr, kr, eigs=None):
    """(w^2, Phi, Phi^T M_r): M_r = L L^T, L^-1 K_r L^-T = U diag(w^2) U^T, Phi = L^-T U (a diagonal M_r: L = sqrt;
    ``eigs``: the run's :data:`Eigs` or None)."""
    r = mr.shape[0]
    diagonal = True
    for a in range(r):
        for b in range(r):
            if a != b and mr[a, b] != 0.0:
                diagonal = False
    if not diagonal:
        li = np.linalg.inv(np.linalg.cholesky(mr))
        sym = mm(mm(li, kr), li.T.copy())
        w2, u = np.linalg.eigh(0.5 * (sym + sym.T))
        phi = mm(li.T.copy(), u)
        return w2, phi, mm(phi.T.copy(), mr)
    s = np.empty(r)
    for a in range(r):
        s[a] = 1.0 / math.sqrt(mr[a, a])
    sym = np.empty((r, r))
    for a in range(r):
        for b in range(r):
            sym[a, b] = 0.5 * (s[a] * kr[a, b] * s[b] + s[b] * kr[b, a] * s[a])
    w2, u = block_eigh(sym, eigs)
    phi, xm = np.empty((r, r)), np.empty((r, r))
    for i in range(r):
        for a in range(r):
            phi[i, a] = s[i] * u[i, a]
            xm[a, i] = phi[i, a] * mr[i, i]
    return w2, phi, xm


@njit(cache=True)
def modal_damping(mr, cr, phi):
    """(ok, c_m): the modal damping Phi^T C_r Phi when diagonal (ok), c_m its diagonal.

    C_r = alpha M_r exactly: alpha on the diagonal (the modes are M_r-orthonormal), no products.
    """
    r = mr.shape[0]
    alpha = cr[0, 0] / mr[0, 0]
    proportional = True
    for a in range(r):
        for b in range(r):
            if cr[a, b] != alpha * mr[a, b]:
                proportional = False
    if proportional:
        return True, np.full(r, alpha)
    cm = mm(mm(phi.T.copy(), cr), phi)
    scale, cd = np.abs(cm).max(), np.diag(cm).copy()
    for a in range(r):
        cm[a, a] = 0.0
    return np.abs(cm).max() <= SYM_TOL * scale, cd


@njit(cache=True)
def classical(mr, kr, cr, eigs=None):
    """:data:`Modes` from the real modes when K_r is symmetric and C_r diagonal in them (classical damping;
    ``eigs``: the run's :data:`Eigs` or None), one root of each conjugate pair (the module's docstring).

    M_r = L L^T, L^-1 K_r L^-T = U diag(w^2) U^T (symmetric), Phi = L^-T U: each mode
    x'' + c_m x' + w^2 x = phi^T f decouples, with the pair of roots l1, l2 of l^2 + c_m l + w^2,
    z1 + z2 = x = phi^T M_r y and l1 z1 + l2 z2 = x'.  A symmetric problem of size r instead of a
    general one of size 2 r; V^-1 needs no inverse, and V^-1 B = [-Phi^T; Phi^T] / (l2 - l1) no M_r^-1
    (Phi^T M_r M_r^-1).  ``real`` is False (nothing else meant) when the damping couples the modes.
    """
    r = mr.shape[0]
    asym, size = asymmetry(kr)
    if asym > SYM_TOL * size:
        return refused()
    w2, phi, xm = mass_modes(mr, kr, eigs)
    ok, cd = modal_damping(mr, cr, phi)
    if not ok:
        return refused()
    lam2 = np.empty(2 * r, dtype=np.complex128)  # both roots of each mode: l1 at a, l2 at r + a
    scale_l = math.sqrt(abs_max(w2)) + abs_max(cd)
    pairs = np.int64(0)  # (a literal 0 would compile kept_roots once more for it)
    for a in range(r):
        lam2[a], lam2[r + a] = roots(cd[a], w2[a])
        if abs(lam2[r + a] - lam2[a]) <= NEAR_DOUBLE * scale_l:  # (nearly) a double root: the general route decides
            return refused()
        pairs += lam2[a].imag != 0.0
    orig = kept_roots(lam2, pairs)
    lam = np.empty(len(orig), dtype=np.complex128)
    for c in range(len(orig)):
        lam[c] = lam2[orig[c]]
    v, vi, vb = np.empty((2 * r, len(orig)), dtype=np.complex128), np.empty((len(orig), 2 * r), dtype=np.complex128), \
        np.empty((len(orig), r), dtype=np.complex128)
    real_columns(phi, lam2, orig, v)
    real_rows(phi, xm, lam2, orig, vi, vb)
    return Modes(lam, v, vi, vb, True, phi, orig)


@njit(cache=True)
def kept_roots(lam2, pairs):
    """The roots kept of both roots of each mode (``lam2``: l1 at a, l2 at r + a): every l1, and l2 where it is real
    (an underdamped mode's l2 is l1's conjugate); ``pairs`` of them are underdamped."""
    r = len(lam2) // 2
    orig = np.empty(2 * r - pairs, dtype=np.int64)
    c = 0
    for a in range(2 * r):
        if a >= r and lam2[a - r].imag != 0.0:
            continue  # the partner of a pair
        orig[c] = a
        c += 1
    return orig


@njit(cache=True, inline="always")
def pair_scale(root):
    """2 for a root kept on the real-mode route that stands for its pair (not real: its column of V and W counts the
    conjugate's; an overdamped mode's roots are real and both kept), else 1."""
    return 2.0 if root.imag != 0.0 else 1.0


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def real_columns(phi, lam2, orig, v):
    """V's kept columns into ``v``: V = [[Phi, Phi], [l1 Phi, l2 Phi]], a pair's representative's doubled."""
    r = phi.shape[0]
    for i in range(r):  # row by row (row-major arrays)
        for c in range(len(orig)):
            a = orig[c]
            col = a if a < r else a - r
            x, y = phi[i, col] + 0.0j, lam2[a] * phi[i, col]
            s = pair_scale(lam2[a])
            v[i, c], v[r + i, c] = x * s, y * s


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def real_rows(phi, xm, lam2, orig, vi, vb):
    """V^-1's and V^-1 B's kept rows into ``vi``, ``vb``: [l2 X, -X] and -Phi^T / (l2 - l1) for l1's row,
    [-l1 X, X] and Phi^T / (l2 - l1) for l2's (X = Phi^T M_r / (l2 - l1))."""
    r = phi.shape[0]
    for c in range(len(orig)):
        a = orig[c]
        b = a if a < r else a - r
        l1, l2 = lam2[b], lam2[r + b]
        di = 1.0 / (l2 - l1)
        for i in range(r):
            x = xm[b, i] * di
            if a < r:
                vi[c, i], vi[c, r + i], vb[c, i] = l2 * x, -x, -phi[i, b] * di
            else:
                vi[c, i], vi[c, r + i], vb[c, i] = -l1 * x, x, phi[i, b] * di


@njit(cache=True)
def refused():
    """:func:`classical`'s answer off its route (empty arrays, made only then)."""
    ez = np.zeros((0, 0), dtype=np.complex128)
    return Modes(np.zeros(0, dtype=np.complex128), ez, ez, ez, False, np.zeros((0, 0)), np.zeros(0, dtype=np.int64))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def abs_max(a):
    """max |a_i| over a vector's entries (np.abs(a).max() without that temporary array)."""
    m = abs(a[0])
    for i in range(1, len(a)):
        m = max(m, abs(a[i]))
    return m


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def asymmetry(a):
    """(max |a - a^T|, max |a|) over a square matrix's entries (without the temporaries of np.abs(a - a.T).max()
    and np.abs(a).max())."""
    m, s = 0.0, 0.0
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            m, s = max(m, abs(a[i, j] - a[j, i])), max(s, abs(a[i, j]))
    return m, s


@njit(cache=True)
def roots(cd, w2):
    """The roots of l^2 + cd l + w2 = 0 (complex pair, or real without cancellation)."""
    disc = 0.25 * cd * cd - w2
    if disc < 0.0:
        s = math.sqrt(-disc)
        return complex(-0.5 * cd, s), complex(-0.5 * cd, -s)
    l1 = -(0.5 * cd + math.copysign(math.sqrt(disc), cd))
    return complex(l1, 0.0), complex(w2 / l1 if l1 != 0.0 else -cd - l1, 0.0)


@njit(cache=True)
def maps_room(k, n, m):
    """Room for :func:`maps_into` of ``k`` contacts, ``n`` coordinates and ``m`` forces: (D, dc, Dh, active) zeros and
    its work room (the numbers views of one allocation)."""
    ns = N_SLOTS * k
    buf = np.zeros(ns * (2 * n + 1 + m) + 2 * n + m)
    d, dc = buf[:ns * 2 * n].reshape((ns, 2 * n)), buf[ns * 2 * n:ns * (2 * n + 1)]
    dh = buf[ns * (2 * n + 1):ns * (2 * n + 1 + m)].reshape((ns, m))
    return d, dc, dh, np.zeros(ns, dtype=np.bool_), buf[ns * (2 * n + 1 + m):]


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def maps_into(asm, modes, stuck, he, keff, f0, d, dc, dh, active, room):
    """(D, dc, Dh, active) into ``d``, ``dc``, ``dh``, ``active`` (zeros; :func:`maps_room`): each event slot as
    D (q, q') + dc + sum_i Dh_i cos(Omega_i t + phi_i); ``room``: 2 n + (forces) numbers.

    lambda_i = HE_i (C q' + K_eff q - f0 - forces): HE's row times K_eff, C, f0 and the forces' directions,
    skipping its zeros (one entry per row when the stuck directions are axes of a diagonal M).
    """
    cdir, normal, law, belt, amp, fdir = asm.contact_dir, asm.normal, asm.law, asm.belt, asm.force_amp, asm.force_dir
    k, n = cdir.shape
    for j in range(k):
        if depends(normal, j):
            active[N_SLOTS * j + 2] = True
            for b in range(n):
                d[N_SLOTS * j + 2, b] = normal[j, 1 + b]
            dc[N_SLOTS * j + 2] = normal[j, 0]
        if modes[j] != STICK:
            active[N_SLOTS * j] = True
            for a in range(n):
                d[N_SLOTS * j, n + a] = -modes[j] * cdir[j, a]
            dc[N_SLOTS * j] = modes[j] * belt[j]
    for i in range(len(stuck)):
        j, hf = stuck[i], held_row(asm.damping, fdir, he[i], keff, f0, room)  # room: HE_i [K_eff, C], HE_i G
        fs = law[j, FS]
        for side in range(2):
            sl, sg = N_SLOTS * j + side, 1.0 if side else -1.0  # F_s N -+ lambda
            active[sl] = True
            for b in range(n):
                d[sl, b] = fs * normal[j, 1 + b] + sg * room[b]
            if law[j, RESULTANT] != 0.0:
                for b in range(n):
                    d[sl, n + b] = sg * room[n + b]
            dc[sl] = fs * normal[j, 0] - sg * hf
            for f in range(len(amp)):
                dh[sl, f] = -sg * room[2 * n + f] * amp[f]


@njit(cache=True, inline="always")
def held_row(damping, fdir, he_i, keff, f0, room):
    """HE_i f0; ``room`` = [HE_i K_eff, HE_i C, HE_i G] (the sums skip HE_i's zeros)."""
    n = len(he_i)
    room[:] = 0.0
    hf = 0.0
    for c in range(n):
        x = he_i[c]
        if x == 0.0:
            continue
        for b in range(n):
            room[b] += x * keff[c, b]
            room[n + b] += x * damping[c, b]
        hf += x * f0[c]
        for f in range(fdir.shape[0]):
            room[2 * n + f] += x * fdir[f, c]
    return hf


@njit(cache=True)
def constants(belt, fdir, amp, stuck, z, sel, rows, r, keff, vb, d):
    """(Z^T, b_S, R b_S, b1, bh, e1): the parts of every :func:`start` in one combination that the state leaves out
    (``belt``, ``fdir``, ``amp``: the Assembly's belt speeds, forces' directions and amplitudes; ``sel``, ``rows``:
    :func:`selected` of Z)."""
    n, ns, nr = z.shape[0], len(stuck), z.shape[1]
    bs = np.empty(ns)
    for i in range(ns):
        bs[i] = belt[stuck[i]]
    rb = r @ bs if ns else np.zeros(n)
    zt = z.T.copy()
    p1, pg = (picked(keff @ rb, fdir, amp, rows) if sel else
              (-(zt @ (keff @ rb)), mm(zt, fdir.T.copy()) * amp))
    b1 = vb @ p1.astype(np.complex128) if nr else np.zeros(0, dtype=np.complex128)
    bh = mm(vb, pg.astype(np.complex128))
    e1 = np.ascontiguousarray(d[:, :n]) @ rb
    return zt, bs, rb, b1, bh, e1


@njit(cache=True)
def picked(krb, fdir, amp, rows):
    """(-Z^T K_eff R b_S, Z^T G diag(amplitudes)) when Z selects the coordinates ``rows`` (entries picked out)."""
    nr, m = len(rows), len(amp)
    p1, pg = np.empty(nr), np.empty((nr, m))
    for c in range(nr):
        p1[c] = -krb[rows[c]]
        for f in range(m):
            pg[c, f] = fdir[f, rows[c]] * amp[f]
    return p1, pg


@njit(cache=True)
def sparse_mm(a, b):
    """a @ b, skipping b's zeros when most of its entries are (the real modes of a chain cut into pieces)."""
    nz = 0
    for i in range(b.shape[0]):
        for j in range(b.shape[1]):
            nz += b[i, j] != 0.0
    if 4 * nz > b.size:
        return mm(a, b)
    at, out = a.T.copy(), np.zeros((b.shape[1], a.shape[0]))  # transposed: rows are contiguous
    for i in range(b.shape[0]):
        for j in range(b.shape[1]):
            x = b[i, j]
            if x != 0.0:
                for e in range(at.shape[1]):
                    out[j, e] += x * at[i, e]
    return out.T.copy()


@njit(cache=True)
def event_modes(d, active, z, sel, rows, md):
    """W = D T V on the active slots (zero rows elsewhere), V's columns those of the :data:`Modes` ``md``;
    T: (y, y') -> (q, q') (``sel``, ``rows``: :func:`selected` of Z).

    On the real-mode route V = [[Phi, Phi], [l1 Phi, l2 Phi]]: W = [P + Q l1, P + Q l2] with the real
    P = D_q Z Phi and Q = D_q' Z Phi, a product of size r instead of 2 r, and no complex one (a pair's
    representative's column doubled, as V's).
    """
    n, r, lam = z.shape[0], z.shape[1], md.lam
    slots = where_equal(active, True)
    w = np.zeros((d.shape[0], len(lam)), dtype=np.complex128)
    if r == 0 or len(slots) == 0:
        return w
    if md.real and sel and 4 * nonzeros(md.phi) <= r * r:  # Phi of a chain cut into pieces: mostly zeros
        pq = np.zeros((2, len(slots), r))
        picked_modes(d, slots, rows, md.phi, pq)
        real_events(pq[0], pq[1], slots, md, w)
        return w
    dq, dv = np.empty((len(slots), n)), np.empty((len(slots), n))
    for e in range(len(slots)):
        for a in range(n):
            dq[e, a], dv[e, a] = d[slots[e], a], d[slots[e], n + a]
    dzq, dzv = columns(dq, z, sel, rows), columns(dv, z, sel, rows)
    if md.real:
        real_events(sparse_mm(dzq, md.phi), sparse_mm(dzv, md.phi), slots, md, w)
        return w
    dt = np.hstack((dzq, dzv))
    wr, wi = mm(dt, np.ascontiguousarray(md.V.real)), mm(dt, np.ascontiguousarray(md.V.imag))
    for e in range(len(slots)):
        w[slots[e]] = wr[e] + 1j * wi[e]
    return w


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def real_events(p, q, slots, md, w):
    """W's active rows on the real-mode route from P = D_q Z Phi and Q = D_q' Z Phi (a row per active slot):
    P + l Q for each kept root l, doubled for a pair's representative."""
    r, lam, orig = p.shape[1], md.lam, md.orig
    for e in range(len(slots)):
        for c in range(len(lam)):
            a = orig[c]
            col = a if a < r else a - r
            x = p[e, col] + lam[c] * q[e, col]
            w[slots[e], c] = x * pair_scale(lam[c])


@njit(cache=True, inline="always")
def nonzeros(a):
    """The nonzeros of a real matrix."""
    nz = 0
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            nz += a[i, j] != 0.0
    return nz


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def picked_modes(d, slots, rows, phi, pq):
    """P and Q into ``pq`` (zeros) when Z selects ``rows`` and Phi is mostly zeros: D's columns picked out,
    Phi's zeros skipped."""
    n, r = d.shape[1] // 2, len(rows)
    for i in range(r):
        for a in range(r):
            x = phi[i, a]
            if x != 0.0:
                for e in range(len(slots)):
                    pq[0, e, a] += x * d[slots[e], rows[i]]
                    pq[1, e, a] += x * d[slots[e], n + rows[i]]


@njit(cache=True, inline="always")  # inlined: a compiled caller would link build_from's tree once more
def build(asm, minv, modes):
    """The :data:`Combo` of the contact modes ``modes`` (int8: -1, 0, +1 per contact) on its own (a combination of a
    run comes from :func:`build_from` with the run's :data:`Eigs`)."""
    return build_from(asm, minv, split(asm, minv, modes), new_eigs())


@njit(cache=True)
def build_from(asm, minv, sp, eigs):
    """The :data:`Combo` of the :data:`Split` ``sp`` (its arrays taken, not copied: a combination's are never written;
    ``eigs``: the :data:`Eigs` its symmetric blocks are looked up in and kept in).

    Every caller passes an :data:`Eigs` (one signature): each compiled caller re-optimises this function's whole
    tree in its own library, so the engine calls it from as few compiled functions as it can (the run loop).
    """
    modes, stuck, r, he, keff, f0 = sp
    n = minv.shape[0]
    z = null_basis(asm.contact_dir, stuck)
    sel, rows = selected(z)  # Z a selection of coordinates (stuck directions along axes): products become picks
    md = decompose(asm.mass, asm.damping, keff, z, sel, rows, eigs)
    d, dc, dh, active, room = maps_room(len(modes), n, len(asm.force_amp))
    maps_into(asm, modes, stuck, he, keff, f0, d, dc, dh, active, room)
    w = event_modes(d, active, z, sel, rows, md)
    c = np.ascontiguousarray
    zt, bs, rb, b1, bh, e1 = constants(asm.belt, asm.force_dir, asm.force_amp, stuck, z, sel, rows, r, keff,
                                       md.VB, c(d))
    return Combo(modes, c(stuck), c(z), c(r), c(he), c(keff), f0, md.lam, md.V, md.Vi, md.VB, c(d), dc, c(dh),
                 active, w, zt, bs, rb, b1, bh, e1, np.abs(w), combo_pattern(z, r))


@njit(cache=True, inline="always")  # inlined: a compiled function taking the record counts references to its 23 arrays
def keep(cache, cb):
    """Keep the combination ``cb`` in the :data:`Cache` ``cache`` while there is room; ``cb``."""
    used, size = cache.used, combo_bytes(cb)
    if used[0] < len(cache.keys) and used[1] + size <= CACHE_BYTES:
        cache.combos.append(cb)  # (no eviction: popping records of arrays from a compiled list corrupts memory)
        cache.splits.append(split_of(cb))
        cache.keys[used[0]] = cb.modes
        used[0], used[1] = used[0] + 1, used[1] + size
    return cb


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def find(keys, used, modes):
    """The row of ``keys`` among the first ``used[0]`` that holds ``modes``; -1: none (entries compared in place: a
    row taken as a view would be reference-counted at every row of the scan)."""
    for i in range(used[0]):
        j = 0
        while j < len(modes) and keys[i, j] == modes[j]:
            j += 1
        if j == len(modes):
            return i
    return -1


@njit(cache=True, **NO_RUNTIME)  # allocates nothing: the record's arrays are not reference-counted
def combo_bytes(cb):
    """About the memory a combination holds (its largest arrays)."""
    return 16 * (cb.V.size + cb.Vi.size + cb.VB.size + cb.W.size) + 8 * (cb.D.size + cb.Z.size + cb.keff.size
                                                                         + cb.WA.size)


@njit(cache=True, inline="always")
def split_of(cb):
    """The :data:`Split` part of the :data:`Combo` ``cb`` (its arrays, not copies)."""
    return Split(cb.modes, cb.stuck, cb.R, cb.HE, cb.keff, cb.f0)


@njit(cache=True, inline="always")  # inlined: a compiled caller would link build_from's tree once more
def new_cache(asm, minv):
    """A run's :data:`Cache`, holding the combination with every contact stuck."""
    eigs = new_eigs()
    return cache_of(build_from(asm, minv, split(asm, minv, np.zeros(len(asm.belt), dtype=np.int8)), eigs), eigs)


@njit(cache=True)
def cache_of(cb, eigs):
    """A :data:`Cache` holding the combination ``cb`` (the typed lists take their type from it) and the :data:`Eigs`
    ``eigs`` it was built with."""
    combos, splits = List(), List()  # typed lists: appended to in place from compiled code and from Python alike
    combos.append(cb)
    splits.append(split_of(cb))
    cache = Cache(combos, splits, np.zeros((CACHE_SIZE, len(cb.modes)), dtype=np.int8), np.zeros(2, dtype=np.int64),
                  eigs)
    cache.keys[0] = cb.modes
    cache.used[0], cache.used[1] = 1, combo_bytes(cb)
    return cache


@njit(cache=True, inline="always")  # inlined: a compiled caller would link build_from's tree once more
def lookup(cache, asm, minv, modes):
    """The combination of ``modes`` from the :data:`Cache` ``cache``, built (and kept while there is room) when missing."""
    i = find(cache.keys, cache.used, modes)
    if i >= 0:
        return cache.combos[i]
    return keep(cache, build_from(asm, minv, split(asm, minv, modes), cache.eigs))


@njit(cache=True, **NO_RUNTIME)  # allocates nothing
def same_modes(a, b):
    """The two modes arrays hold the same entries."""
    for j in range(len(a)):
        if a[j] != b[j]:
            return False
    return True
