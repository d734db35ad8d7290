"""Karnopp's law (Eq. 5): its three branches, F_s >= F_d and the stick force."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from frictionflow import Karnopp
from frictionflow.core.friction import band_force, band_force_select, band_law, band_mode


def force(law: Karnopp, x, v, zeta=0.0, vb=0.01):
    """(F_c, mode) from the compiled law; the branchy and the select forms must agree."""
    p = law.kernel_params()
    args = (band_law(int(p[0]), p), x, v, zeta, vb, 0.0)
    f = band_force(*args)
    assert band_force_select(*args) == f
    return f, band_mode(v, vb, p[3])


small = st.floats(-0.1, 0.1, allow_nan=False)


@given(x=small, v=small, zeta=st.floats(0, 1), vb=small, fd=st.floats(0, 0.05, allow_subnormal=False), gap=st.floats(0, 0.05, allow_subnormal=False), spring=st.booleans())
@settings(max_examples=300, deadline=None)
def test_eq5_reference(x, v, zeta, vb, fd, gap, spring):
    """The compiled law against Eq. 5 written out directly."""
    vd = 1e-3
    law = Karnopp(fd, fs=fd + gap, vd=vd, stick_force="spring" if spring else "resultant")
    vr = vb - v
    fe = x if spring else x + 2 * zeta * v
    if abs(vr) > vd:
        want = fd if vr > 0 else -fd
    elif abs(fe) >= fd + gap:
        want = fd + gap if fe > 0 else -(fd + gap)
    else:
        want = fe
    f, mode = force(law, x, v, zeta, vb)
    # The compiled rule may fuse X + 2 zeta X' into one multiply-add (FASTMATH, as in the RK4
    # kernels); Python cannot: they may differ by the rounding of that product, no more.
    assert f == pytest.approx(want, rel=0.0, abs=2.0**-52 * (abs(x) + abs(2 * zeta * v)))
    assert mode == (0 if abs(vr) <= vd else (1 if vr > 0 else -1))


def test_slip_branch_is_fd_sign_vr():
    law = Karnopp(fd=0.02, fs=0.03, vd=1e-3)
    assert force(law, x=0.5, v=0.0) == (0.02, 1)  # V_r = 0.01 > V_d
    assert force(law, x=-0.5, v=0.02) == (-0.02, -1)  # V_r = -0.01 < -V_d


def test_band_edges_belong_to_the_band():
    law = Karnopp(fd=0.02, fs=0.03, vd=1e-3)
    # |V_r| = V_d exactly: stick branch (Eq. 5 uses <=)
    f, mode = force(law, x=0.01, v=0.01 - 1e-3, vb=0.01)
    assert mode == 0 and f == 0.01


def test_saturated_stick_branch_is_fs_sign_fe():
    law = Karnopp(fd=0.02, fs=0.03, vd=1e-3, stick_force="spring")
    assert force(law, x=0.05, v=0.01) == (0.03, 0)
    assert force(law, x=-0.05, v=0.01) == (-0.03, 0)
    assert force(law, x=0.03, v=0.01) == (0.03, 0)  # |F_e| = F_s is saturated (>=)


def test_holding_stick_branch_is_fe():
    spring = Karnopp(fd=0.02, fs=0.03, vd=1e-3, stick_force="spring")
    resultant = Karnopp(fd=0.02, fs=0.03, vd=1e-3, stick_force="resultant")
    assert force(spring, x=0.01, v=0.01, zeta=0.2) == (0.01, 0)
    # resultant: F_e = X + 2 zeta X' = 0.01 + 2*0.2*0.01 = 0.014
    f, mode = force(resultant, x=0.01, v=0.01, zeta=0.2)
    assert mode == 0 and f == pytest.approx(0.014)


def test_resultant_stick_force_holds_the_mass_exactly():
    # In the holding branch with F_e = X + 2 zeta X', X'' = F_c - X - 2 zeta X' = 0.
    law = Karnopp(fd=0.02, fs=0.05, stick_force="resultant")
    x, v, zeta = 0.013, 0.0102, 0.3
    f, _ = force(law, x, v, zeta=zeta, vb=0.01)
    assert f - x - 2 * zeta * v == pytest.approx(0.0, abs=1e-17)


def test_fs_defaults_to_fd_and_is_validated():
    assert Karnopp(fd=0.04).fs == 0.04
    with pytest.raises(ValueError, match=r"^fs must be >= fd"):
        Karnopp(fd=0.04, fs=0.03)
    with pytest.raises(ValueError, match=r"^fd must be"):
        Karnopp(fd=-0.01)
    with pytest.raises(ValueError, match=r"^vd must be finite and in \(0, 1000\]"):
        Karnopp(fd=0.01, vd=0.0)
    with pytest.raises(ValueError, match=r"^stick_force must be one of"):
        Karnopp(fd=0.01, stick_force="both")


def test_slip_force_vectorised_matches_kernel():
    law = Karnopp(fd=0.02)
    assert list(law.slip_force([0.5, -0.5])) == [0.02, -0.02]
    assert law.sliding_equilibrium(0.01) == 0.02
