"""Steady sliding of a structure: equilibrium, linearisation, complex eigenvalues and critical points (issue 22, 4).

Every structure here is assembled by hand (no model file): the expected values come from closed forms derived
in the tests (the discriminant of det(K_eff - omega^2 M) = 0 for the flutter threshold, 2 zeta + mu'(b) = 0 for
negative damping) and from numpy on matrices written out entry by entry.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from frictionflow import BeltOscillator, Coulomb, Cubic, Karnopp, Stribeck, sliding_equilibrium
from frictionflow.analysis.stability import stability_scan, steady_sliding
from frictionflow.core.assembly import Assembly


def assembly(mass, stiffness, damping, contact_dir, belt, laws, normal=None) -> Assembly:
    """An Assembly from its matrices and contacts (no forces; the per-element arrays are not read here)."""
    n = len(mass)
    e = np.array(contact_dir, dtype=float).reshape(-1, n)
    if normal is None:
        normal = np.hstack([np.ones((len(e), 1)), np.zeros((len(e), n))])
    empty, none = np.zeros((0, n)), np.zeros(0)
    return Assembly(mass=np.array(mass, dtype=float), stiffness=np.array(stiffness, dtype=float),
                    damping=np.array(damping, dtype=float), contact_dir=e, belt=np.array(belt, dtype=float),
                    law=np.array([law.kernel_params() for law in laws]), normal=np.array(normal, dtype=float),
                    force_dir=empty, force_amp=none, force_omega=none, force_phi=none, spring_dir=empty,
                    spring_k=none, damper_dir=empty, damper_c=none, q0=np.zeros(n), v0=np.zeros(n))


def same_spectrum(a, b, rtol):
    """Two sets of eigenvalues equal within ``rtol`` of the larger's size (matched one to one, nearest)."""
    a, b = np.asarray(a, dtype=complex), np.asarray(b, dtype=complex)
    rows, cols = linear_sum_assignment(np.abs(a[:, None] - b[None, :]))
    return np.max(np.abs(a[rows] - b[cols])) <= rtol * max(np.abs(a).max(), np.abs(b).max())


# -- the linearisation against numpy on a hand-assembled 2-dof matrix ---------------------------------------------------

def test_linearisation_of_a_two_dof_structure_against_numpy_on_the_matrices_written_out():
    # two contacts: a Stribeck one along x1 whose normal load follows x2, a Coulomb one between x1 and x2 whose
    # belt runs backwards; a full mass matrix
    M = [[2.0, 0.3], [0.3, 1.0]]
    K = [[3.0, -1.0], [-1.0, 2.0]]
    C = [[0.05, -0.02], [-0.02, 0.04]]
    fd, fs, vs, cv, b0 = 0.3, 0.5, 0.1, 0.05, 0.2
    P, n2 = 1.0, -0.5
    asm = assembly(M, K, C, [[1.0, 0.0], [1.0, -1.0]], [b0, -0.1],
                   [Stribeck(fd=fd, fs=fs, vs=vs, delta=1.0, viscous=cv), Coulomb(fd=0.2, fs=0.3)],
                   normal=[[P, 0.0, n2], [1.0, 0.0, 0.0]])
    s = steady_sliding(asm)

    m0 = fd + (fs - fd) * math.exp(-b0 / vs) + cv * b0  # the slip curve and its slope, by hand
    dm0 = -(fs - fd) / vs * math.exp(-b0 / vs) + cv
    mu1 = -0.2  # Coulomb, belt backwards
    # K_eff = K - mu0 e0 n0^T (e0 = (1, 0), n0 = (0, n2)); the second contact has no normal-load coefficients
    k_eff = np.array([[3.0, -1.0 - m0 * n2], [-1.0, 2.0]])
    rhs = np.array([m0 * P + mu1, -mu1])  # e0 mu0 P + e1 mu1 * 1, e1 = (1, -1)
    q = np.linalg.solve(k_eff, rhs)
    n_star = P + n2 * q[1]
    c_eff = np.array([[0.05 + n_star * dm0, -0.02], [-0.02, 0.04]])  # + N0 mu0' e0 e0^T; Coulomb's slope is 0
    minv = np.linalg.inv(np.array(M))
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-minv @ k_eff, -minv @ c_eff]])

    assert np.allclose(s.q, q, rtol=1e-13, atol=0) and np.isclose(s.normal[0], n_star, rtol=1e-14)
    assert np.allclose(s.stiffness, k_eff, rtol=1e-14, atol=0) and np.allclose(s.damping, c_eff, rtol=1e-14, atol=0)
    assert np.allclose(s.mu, [m0, mu1], rtol=1e-14) and np.allclose(s.slope, [dm0, 0.0], rtol=1e-14, atol=0)
    assert same_spectrum(s.eigenvalues, np.linalg.eigvals(a), 1e-13)
    for lam, v in zip(s.eigenvalues, s.eigenvectors.T):  # each eigenpair solves the quadratic problem
        x = v[:2]
        residual = (lam * lam * np.array(M) + lam * c_eff + k_eff) @ x
        assert np.linalg.norm(residual) <= 1e-12 * (1 + abs(lam) ** 2) * np.linalg.norm(x)


# -- mode coupling: Hoffmann's minimal flutter model --------------------------------------------------------------------

# x1 tangential, x2 normal; M = I; springs to the ground on x1 (k1), on x2 (k2) and a coupling one along (1, 1) (k3):
# K = [[k1 + k3, k3], [k3, k2 + k3]].  A contact along x1 with its normal load N = P + c x2, Coulomb at mu.
K1, K2, K3, PRELOAD, CN = 1.0, 1.8, 0.5, 1.0, 2.0
KH = np.array([[K1 + K3, K3], [K3, K2 + K3]])


def hoffmann(mu: float, damping: float = 0.0) -> Assembly:
    return assembly(np.eye(2), KH, damping * np.eye(2), [[1.0, 0.0]], [0.5], [Coulomb(fd=mu, fs=mu)],
                    normal=[[PRELOAD, 0.0, CN]])


def hoffmann_threshold(damping: float = 0.0) -> tuple[float, float]:
    """(mu, omega) where the flutter starts, from det(K_eff - s I) = 0 with s = omega^2 (- i omega c).

    K_eff = K - mu e n^T = [[K11, K12 - mu c], [K21, K22]], so s^2 - (K11 + K22) s + K11 K22 - K21 (K12 - mu c) = 0;
    its discriminant D(mu) = (K11 - K22)^2 + 4 K21 K12 - 4 K21 mu c.  Undamped, lambda = +-i sqrt(s): the two
    frequencies coalesce where D = 0 and split into a +- i omega beyond.  With C = c_d I, lambda = i omega on
    the axis needs omega^2 - i omega c_d = s = tr/2 +- i sqrt(-D)/2: omega^2 = tr/2 and D = -4 omega^2 c_d^2.
    """
    (k11, k12), (k21, k22) = KH
    tr = k11 + k22
    omega2 = tr / 2.0
    mu = ((k11 - k22) ** 2 + 4.0 * k21 * k12 + 4.0 * omega2 * damping**2) / (4.0 * k21 * CN)
    return mu, math.sqrt(omega2)


def test_the_flutter_threshold_of_hoffmanns_undamped_model_is_the_discriminants_root():
    values = np.linspace(0.1, 0.8, 15)
    scan = stability_scan(hoffmann, values, param="contact.0.fd")
    mu_c, omega_c = hoffmann_threshold()
    assert 0.1 < mu_c < 0.8
    assert len(scan.critical) == 1
    crit = scan.critical[0]
    assert crit.kind == "mode_coupling" and crit.unstable_above
    assert crit.value == pytest.approx(mu_c, rel=1e-12)
    # at the coalescence each of the pair is only known to ~sqrt(eps); their mean, reported, to rounding
    assert crit.frequency == pytest.approx(omega_c, rel=1e-12)
    # the tracked eigenvalues are those of the closed form at every value: lambda = +-i sqrt(s)
    (k11, k12), (k21, k22) = KH
    for mu, lam in zip(values, scan.eigenvalues):
        s = np.roots([1.0, -(k11 + k22), k11 * k22 - k21 * (k12 - mu * CN)]).astype(complex)
        expected = np.concatenate([1j * np.sqrt(s), -1j * np.sqrt(s)])
        assert same_spectrum(lam, expected, 1e-12)
    assert np.array_equal(scan.stable, values < mu_c)  # undamped modes: stable, marginally, below the threshold
    assert np.all(scan.eigenvalues.real.max(axis=1)[values > mu_c] > 1e-3)


@pytest.mark.parametrize("c", [1e6, 1e9])
def test_a_stiff_damper_on_a_third_dof_leaves_the_flutter_pair_unstable_and_exact(c):
    """Hoffmann's pair beside a third dof held by a damper ``c``, coupled to x1 by a spring of 0.01: over the
    pair's period the damper holds x3 at 0, so the pair is that of Hoffmann's model with 0.01 added to K11 (numpy
    on that 2-dof matrix), up to x3's own dynamic stiffness, 0.01^2 / (i omega c) ~ 1e-4 / c.  Its growth rate 0.075 at mu = 0.7 counted as zero beside
    the damper's rate 1e9 (zero was 1e-8 of the spectrum's size), so the state was called stable; and the pair
    was ~c EPS off (3e-8 of its size at c = 1e9)."""
    k = KH + np.diag([0.01, 0.0])
    for mu in (0.2, 0.7):
        k_eff = k - mu * CN * np.array([[0.0, 1.0], [0.0, 0.0]])  # K - mu e n^T, e = (1, 0), n = (0, CN)
        pair = np.linalg.eigvals(np.block([[np.zeros((2, 2)), np.eye(2)], [-k_eff, np.zeros((2, 2))]]))
        stiff = np.array([[K1 + K3 + 0.01, K3, -0.01], [K3, K2 + K3, 0.0], [-0.01, 0.0, 1.01]])
        s = steady_sliding(assembly(np.eye(3), stiff, np.diag([0.0, 0.0, c]), [[1.0, 0.0, 0.0]], [0.5],
                                    [Coulomb(fd=mu, fs=mu)], normal=[[PRELOAD, 0.0, CN, 0.0]]))
        near = s.eigenvalues[np.abs(s.eigenvalues) < 10.0]
        near = near[np.abs(near.imag) > 0.1]  # the pair (the damper's creep root -1/c and fast root -c apart)
        assert same_spectrum(near, pair, 1e-4 / c + 1e-13)
        unstable = pair.real.max() > 1e-3
        assert unstable == (mu == 0.7) and s.stable == (not unstable)


def test_with_proportional_damping_the_flutter_starts_where_the_closed_form_says():
    c = 0.05
    values = np.linspace(0.1, 0.8, 15)
    scan = stability_scan(lambda mu: hoffmann(mu, c), values, param="contact.0.fd")
    mu_c, omega_c = hoffmann_threshold(c)
    assert len(scan.critical) == 1 and scan.critical[0].kind == "mode_coupling"
    assert scan.critical[0].value == pytest.approx(mu_c, rel=1e-12)
    assert scan.critical[0].frequency == pytest.approx(omega_c, rel=1e-12)
    assert np.array_equal(scan.stable, values < mu_c)


def test_decreasing_values_find_the_same_threshold():
    values = np.linspace(0.8, 0.1, 12)
    scan = stability_scan(hoffmann, values)
    assert len(scan.critical) == 1 and scan.critical[0].kind == "mode_coupling"
    assert scan.critical[0].unstable_above
    assert scan.critical[0].value == pytest.approx(hoffmann_threshold()[0], rel=1e-12)


# -- negative damping: one mass on a falling Stribeck curve --------------------------------------------------------------

ZETA = 0.05
STRIBECK = Stribeck(fd=0.02, fs=0.04, vs=0.01, delta=1.0)


def single_mass(vb: float, law=STRIBECK, zeta: float = ZETA) -> Assembly:
    return assembly([[1.0]], [[1.0]], [[2.0 * zeta]], [[1.0]], [vb], [law])


def test_a_falling_slip_curve_destabilises_one_mass_below_the_closed_form_belt_speed():
    # |F| = fd + (fs - fd) exp(-v / vs): slope -(fs - fd)/vs exp(-v/vs); 2 zeta + slope = 0 at
    # v* = vs ln((fs - fd) / (2 zeta vs)), unstable below (the slope is steeper there)
    law = STRIBECK
    v_star = law.vs * math.log((law.fs - law.fd) / (2.0 * ZETA * law.vs))
    values = np.linspace(0.005, 0.08, 31)
    scan = stability_scan(single_mass, values, param="contact.0.belt")
    assert len(scan.critical) == 1
    crit = scan.critical[0]
    assert crit.kind == "negative_damping" and not crit.unstable_above
    assert crit.value == pytest.approx(v_star, rel=1e-12)
    assert crit.frequency == pytest.approx(1.0, rel=1e-12)  # zero damping: lambda = +-i
    assert np.array_equal(scan.stable, values > v_star)


def test_a_pair_that_is_two_real_roots_at_the_unstable_end_crosses_once():
    # a steeper curve: at the slowest belt 2 zeta + slope < -2, the pair is two real roots lambda > 0 (both
    # "upper half plane"); it turns into one complex pair and crosses once, where 2 zeta + slope = 0 (it was
    # reported twice: once per root)
    law = Stribeck(fd=0.02, fs=0.08, vs=0.01, delta=1.0)
    v_star = law.vs * math.log((law.fs - law.fd) / (2.0 * ZETA * law.vs))
    values = np.linspace(0.001, 0.119, 3)  # the first step holds both: the roots meeting (v = 0.0105) and the crossing
    slope = -(law.fs - law.fd) / law.vs * math.exp(-values[0] / law.vs)
    assert (2.0 * ZETA + slope) ** 2 > 4.0  # overdamped (two real roots) at the first value
    scan = stability_scan(lambda vb: single_mass(vb, law), values, param="contact.0.belt")
    assert len(scan.critical) == 1
    crit = scan.critical[0]
    assert crit.kind == "negative_damping" and not crit.unstable_above
    assert crit.value == pytest.approx(v_star, rel=1e-12)
    assert crit.frequency == pytest.approx(1.0, rel=1e-12)


def test_the_law_objects_give_the_slip_curve_where_the_kernel_rows_cannot():
    # a user's slip function (its kernel row cannot hold it): the curve of STRIBECK, its slope given; the
    # assemblies' rows are Coulomb's (flat, no instability): the laws given decide
    from frictionflow import SlipLaw

    law = SlipLaw(lambda v: 0.02 + 0.02 * math.exp(-v / 0.01), dfunc=lambda v: -2.0 * math.exp(-v / 0.01))
    v_star = 0.01 * math.log(0.02 / (2.0 * ZETA * 0.01))
    scan = stability_scan(lambda v: single_mass(v, Coulomb(0.02, 0.04)), np.linspace(0.005, 0.08, 31),
                          laws_at=lambda v: [law])
    [crit] = scan.critical
    assert crit.kind == "negative_damping" and crit.value == pytest.approx(v_star, rel=1e-12)
    with pytest.raises(ValueError, match="stick band"):
        steady_sliding(single_mass(5e-4, Coulomb(0.02, 0.04)), laws=[Karnopp(0.02, 0.04, vd=1e-3)])


@pytest.mark.parametrize("law", [Coulomb(fd=0.02, fs=0.04), STRIBECK, Stribeck(fd=0.02, fs=0.05, vs=0.02),
                                 Cubic(fs=0.04, k1=0.3, k3=10.0)])
@pytest.mark.parametrize("vb", [0.003, 0.0297, 0.07, -0.02])
def test_one_mass_agrees_with_the_single_mass_equilibrium_analysis(law, vb):
    s = steady_sliding(single_mass(vb, law))
    ref = sliding_equilibrium(BeltOscillator(zeta=ZETA, vb=vb), law)
    assert same_spectrum(s.eigenvalues, ref.eigenvalues, 1e-14)
    assert s.q[0] == pytest.approx(ref.x, rel=1e-14)
    assert np.allclose(s.jacobian, ref.jacobian, rtol=1e-14, atol=0)
    assert s.stable == (ref.stability == "stable")


# -- the result and the refusals --------------------------------------------------------------------------------------

def test_the_scan_reads_as_json():
    values = np.linspace(0.1, 0.8, 5)
    scan = stability_scan(hoffmann, values, param="contact.0.fd")
    report = json.loads(json.dumps(scan.to_dict(), allow_nan=False))
    assert report["param"] == "contact.0.fd" and report["values"] == values.tolist()
    assert len(report["eigenvalues"]) == 5 and all(len(row) == 4 for row in report["eigenvalues"])
    z = scan.eigenvalues[2, 1]
    assert report["eigenvalues"][2][1] == {"re": z.real, "im": z.imag}
    assert [set(c) for c in report["critical"]] == [{"value", "kind", "frequency", "unstable_above"}]
    assert "mode_coupling" in repr(scan)


@pytest.mark.parametrize("build, words", [
    (lambda: single_mass(0.0, Coulomb(0.02, 0.04)), "contact.0.belt must be nonzero"),
    (lambda: single_mass(5e-4, Karnopp(0.02, 0.04, vd=1e-3)), "stick band"),
    (lambda: assembly([[1.0]], [[1.0]], [[0.1]], [[1.0]], [1.0], [Coulomb(0.5, 0.5)], normal=[[0.2, 4.0]]),
     "contact.0: the normal load at steady sliding is N = -0.2 <= 0"),
    (lambda: assembly(np.eye(2), [[1.0, 0.0], [0.0, 0.0]], np.eye(2), [[1.0, 0.0]], [1.0], [Coulomb(0.1, 0.1)]),
     "singular"),
])
def test_no_steady_sliding_is_refused_in_one_line(build, words):
    with pytest.raises(ValueError) as info:
        steady_sliding(build())
    assert words in str(info.value) and "\n" not in str(info.value)


def test_a_scan_names_the_value_it_fails_at_and_refuses_bad_values():
    with pytest.raises(ValueError, match=r"^contact\.0\.belt = 0\.0: contact\.0\.belt must be nonzero"):
        stability_scan(single_mass, [-0.01, 0.0, 0.01], param="contact.0.belt")
    with pytest.raises(ValueError, match="strictly increasing or strictly decreasing"):
        stability_scan(single_mass, [0.01, 0.03, 0.02])
    with pytest.raises(ValueError, match="at least 2 finite"):
        stability_scan(single_mass, [0.01])


# -- the figure ---------------------------------------------------------------------------------------------------------

def test_the_loci_figure_marks_each_critical_point_where_it_was_found(tmp_path):
    import frictionflow  # noqa: F401  (registers the figures)
    from frictionflow.stability_plot import MARKERS
    from frictionflow.analysis.stability import KINDS

    assert set(MARKERS) == set(KINDS)
    scan = stability_scan(lambda mu: hoffmann(mu, 0.05), np.linspace(0.1, 0.8, 8), param="contact.0.fd")
    path = tmp_path / "loci.png"
    fig = scan.plot(path)
    assert path.stat().st_size > 0
    top, bottom = fig.axes[:2]
    marked = [line for line in top.lines if line.get_marker() == MARKERS["mode_coupling"][0]]
    assert len(marked) == 1 and marked[0].get_xdata()[0] == scan.critical[0].value
    freq = [line for line in bottom.lines if line.get_marker() == MARKERS["mode_coupling"][0]]
    assert freq[0].get_ydata()[0] == scan.critical[0].frequency
    assert bottom.get_xlabel() == "contact.0.fd"


# -- the mechanism, against Routh-Hurwitz on the characteristic polynomial written out --------------------------------

def quartic(mass, damping, stiffness) -> np.ndarray:
    """a0..a4 of det(lambda^2 M + lambda C + K) = a0 l^4 + a1 l^3 + a2 l^2 + a3 l + a4, a 2 x 2 written out."""
    entry = [[[mass[i][j], damping[i][j], stiffness[i][j]] for j in range(2)] for i in range(2)]
    return np.polysub(np.polymul(entry[0][0], entry[1][1]), np.polymul(entry[0][1], entry[1][0]))


def hurwitz(mass, damping, stiffness) -> float:
    """Delta_3 = a1 a2 a3 - a0 a3^2 - a1^2 a4: a complex pair crosses the imaginary axis where it vanishes (all
    a_i > 0: stable iff Delta_3 > 0), at lambda = +-i sqrt(a3 / a1)."""
    a0, a1, a2, a3, a4 = quartic(mass, damping, stiffness)
    return a1 * a2 * a3 - a0 * a3**2 - a1**2 * a4


def hurwitz_roots(delta, lo, hi, n=200) -> list[float]:
    """Every root of ``delta`` in [lo, hi] (a sign change between n grid points, then brentq)."""
    from scipy.optimize import brentq

    grid = np.linspace(lo, hi, n)
    signs = np.sign([delta(x) for x in grid])
    return [brentq(delta, grid[i], grid[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps)
            for i in np.flatnonzero(signs[:-1] != signs[1:])]


def test_damping_that_is_not_proportional_lowers_the_flutter_threshold_and_it_is_still_mode_coupling():
    # C = diag(0.02, 0.08) is positive definite and Coulomb's slope is 0: nothing feeds energy through the
    # damping, so the instability is the circulatory forces' (mode coupling), though it sets in before the
    # two frequencies meet (the destabilisation paradox): the threshold is Routh-Hurwitz's, below the undamped one
    c = np.diag([0.02, 0.08])

    def delta(mu):
        k_eff = KH - mu * np.array([[0.0, CN], [0.0, 0.0]])
        return hurwitz(np.eye(2), c, k_eff)

    [mu_h] = hurwitz_roots(delta, 0.1, 0.8)
    assert mu_h < hoffmann_threshold()[0]
    build = lambda mu: assembly(np.eye(2), KH, c, [[1.0, 0.0]], [0.5], [Coulomb(fd=mu, fs=mu)],  # noqa: E731
                                normal=[[PRELOAD, 0.0, CN]])
    scan = stability_scan(build, np.linspace(0.1, 0.8, 15))
    [crit] = scan.critical
    assert crit.kind == "mode_coupling" and crit.value == pytest.approx(mu_h, rel=1e-12)
    a = quartic(np.eye(2), c, KH - mu_h * np.array([[0.0, CN], [0.0, 0.0]]))
    assert crit.frequency == pytest.approx(math.sqrt(a[3] / a[1]), rel=1e-12)
    assert abs(crit.frequency - hoffmann_threshold()[1]) > 0.05  # the frequencies have not met


def test_a_falling_curve_on_a_two_mass_chain_is_negative_damping_where_routh_hurwitz_says():
    # x1 on the belt (Stribeck, delta = 1, no normal-load coupling: K_eff = K symmetric), x2 hung on x1
    law = Stribeck(fd=0.02, fs=0.04, vs=0.01, delta=1.0)
    M, K, C = np.diag([1.0, 0.5]), np.array([[1.6, -0.6], [-0.6, 0.6]]), np.diag([0.03, 0.02])

    def slope(v):
        return -(law.fs - law.fd) / law.vs * math.exp(-v / law.vs)

    # both modes are fed below their own belt speed: Delta_3 vanishes at each crossing
    roots = hurwitz_roots(lambda v: hurwitz(M, C + slope(v) * np.diag([1.0, 0.0]), K), 0.005, 0.08)
    scan = stability_scan(lambda v: assembly(M, K, C, [[1.0, 0.0]], [v], [law]), np.linspace(0.005, 0.08, 31))
    assert len(roots) == len(scan.critical) == 2
    for crit, b_h in zip(sorted(scan.critical, key=lambda c: c.value), roots):
        assert crit.kind == "negative_damping" and not crit.unstable_above
        assert crit.value == pytest.approx(b_h, rel=1e-12)
        a = quartic(M, C + slope(b_h) * np.diag([1.0, 0.0]), K)
        assert crit.frequency == pytest.approx(math.sqrt(a[3] / a[1]), rel=1e-12)
    # the two frequencies stay apart (the lower mode crosses first)
    assert abs(scan.critical[0].frequency - scan.critical[1].frequency) > 0.5


def test_a_real_eigenvalue_through_zero_is_a_divergence_where_the_stiffness_vanishes():
    # a hand-built negative stiffness 0.3 - p (no normal-load coupling: N = 1 on both sides): the equilibrium
    # q* = F / (0.3 - p) exists on both sides; one real eigenvalue passes 0 at p = 0.3, with no frequency
    build = lambda p: single_mass(0.05, Coulomb(0.02, 0.04))._replace(stiffness=np.array([[0.3 - p]]))  # noqa: E731
    scan = stability_scan(build, np.linspace(0.0, 0.6, 8))
    [crit] = scan.critical
    assert crit.kind == "divergence" and crit.unstable_above and crit.frequency == 0.0
    assert crit.value == pytest.approx(0.3, rel=1e-14)


def test_the_growth_parts_add_up_to_the_real_parts():
    law = Stribeck(fd=0.3, fs=0.5, vs=0.1, delta=1.0)
    s = steady_sliding(assembly(np.eye(2), KH, np.diag([0.02, 0.05]), [[1.0, 0.0]], [0.05], [law],
                                normal=[[PRELOAD, 0.0, CN]]))
    damping, circulatory = s.growth_parts()
    assert np.allclose(damping + circulatory, s.eigenvalues.real, rtol=0, atol=1e-13)
    assert np.all(circulatory != 0) and np.any(damping > 0)  # both mechanisms present here


def test_on_a_six_mass_chain_the_critical_points_account_for_every_change_in_the_unstable_count():
    # independent of the tracking: count the eigenvalues of the upper half plane with Re > 0 at each value; between
    # two values the count changes by the critical points there (+1 losing stability upwards, -1 regaining it)
    n, rng = 6, np.random.default_rng(3)
    K = np.diag(1.0 + rng.random(n))
    for i in range(1, n):
        k = 0.5 + rng.random()
        K[i - 1:i + 1, i - 1:i + 1] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    M = np.diag(1.0 + rng.random(n))
    C = 0.01 * K + 0.005 * M
    e = np.zeros((2, n))
    e[0, 0] = e[1, 3] = 1.0
    normal = np.zeros((2, n + 1))
    normal[:, 0], normal[0, 3], normal[1, 6] = 1.0, 1.5, -1.2

    def build(mu):
        laws = [Stribeck(fd=mu, fs=1.5 * mu, vs=0.1, delta=1.0), Coulomb(fd=mu, fs=mu)]
        return assembly(M, K, C, e, [0.3, 0.2], laws, normal=normal)

    values = np.linspace(0.05, 1.5, 60)
    scan = stability_scan(build, values)
    counts = []
    for mu in values:
        lam = np.linalg.eigvals(steady_sliding(build(mu)).jacobian)
        counts.append(int(np.sum((lam.real > 1e-8 * np.abs(lam).max()) & (lam.imag >= 0))))
    assert max(counts) >= 3  # several modes lose stability in the range
    for i in range(len(values) - 1):
        inside = [c for c in scan.critical if values[i] < c.value < values[i + 1]]
        assert counts[i + 1] - counts[i] == sum(1 if c.unstable_above else -1 for c in inside), i
