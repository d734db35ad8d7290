"""SwitchMode: every solver reports the modes its switches enter by public names.

The expected sequences are derived from the mechanics of each case (in the
comments), not read off a run; the mirror test pins the negative-direction
members, which the positive-belt cases never enter.
"""

import json

import numpy as np
import pytest

from frictionflow import RK4, Adaptive, BeltOscillator, Coulomb, Exact, Karnopp, Stribeck, SwitchMode, simulate
from frictionflow.core import exact as exact_kernel
from frictionflow.solvers.events import ADAPTIVE_EVENT_MODES, EXACT_EVENT_MODES, switch_modes

S = SwitchMode
FD, FS, ZETA, VB = 0.02, 0.04, 0.05, 0.01

#: what each mode becomes under X -> -X, X' -> -X', V_b -> -V_b (the band's lower edge V_r = +V_d
#: becomes the upper one)
MIRROR = {
    S.SLIP_POSITIVE: S.SLIP_NEGATIVE,
    S.SLIP_NEGATIVE: S.SLIP_POSITIVE,
    S.STICK: S.STICK,
    S.BAND_HOLD: S.BAND_HOLD,
    S.BAND_SATURATED_POSITIVE: S.BAND_SATURATED_NEGATIVE,
    S.BAND_SATURATED_NEGATIVE: S.BAND_SATURATED_POSITIVE,
    S.BAND_EDGE_LOWER: S.BAND_EDGE_UPPER,
    S.BAND_EDGE_UPPER: S.BAND_EDGE_LOWER,
}


def run(solver, law, vb=VB, sign=1.0, t_end=100.0):
    """From the paper's start X = F_d, X' = V_b (mirrored when sign = -1)."""
    return simulate(BeltOscillator(zeta=ZETA, vb=sign * vb), law, solver, t_end=t_end, x0=sign * law.fd, v0=sign * vb)


def modes_of(traj):
    return [SwitchMode(m) for m in traj.events["mode"]]


def alternating(first, second, n):
    return [first if i % 2 == 0 else second for i in range(n)]


STICK_SLIP_CASES = {
    "exact-coulomb": (Exact(), Coulomb(FD, FS)),
    "adaptive-coulomb": (Adaptive(), Coulomb(FD, FS)),
    "adaptive-stribeck": (Adaptive(), Stribeck(FD, FS, vs=0.01)),
}


@pytest.mark.parametrize("case", STICK_SLIP_CASES)
def test_stick_slip_alternates_slip_positive_and_stick(case):
    # The start is on the belt with |F_e| = F_d + 2 zeta V_b < F_s: it sticks until F_e = F_s, then
    # slips back (V_r > 0) and returns to X' = V_b with |F_e| < F_s, where it sticks again.
    solver, law = STICK_SLIP_CASES[case]
    tr = run(solver, law)
    modes = modes_of(tr)
    assert len(modes) >= 10
    assert modes == alternating(S.SLIP_POSITIVE, S.STICK, len(modes))
    assert tr.events["mode"].dtype == np.int8


def test_coulomb_events_agree_between_exact_and_adaptive():
    # The two kernels use different codes for the same physics; the public modes must coincide.
    exact, adaptive = run(Exact(), Coulomb(FD, FS)), run(Adaptive(), Coulomb(FD, FS))
    assert np.array_equal(exact.events["mode"], adaptive.events["mode"])
    assert np.allclose(exact.events["t"], adaptive.events["t"], rtol=0, atol=1e-7)


def test_karnopp_band_holds_and_saturates():
    # F_e = X + 2 zeta X': held in the band, X'' = 0, so X' stays at V_b (mid-band) while X grows to
    # F_e = F_s -> saturated at +F_s, which pulls X' down out of the band -> slip+; slip re-enters the
    # band at its lower edge -> hold; at F_e = F_s on the edge saturation would leave the band at
    # once, so slip+ follows directly.
    modes = modes_of(run(Exact(), Karnopp(FD, FS)))
    assert len(modes) >= 10
    assert modes == [S.BAND_SATURATED_POSITIVE] + alternating(S.SLIP_POSITIVE, S.BAND_HOLD, len(modes) - 1)


def test_karnopp_spring_force_slides_on_the_lower_band_edge():
    # F_e = X, zeta > 0: in the band X'' = -2 zeta X' carries X' out of its lower edge -> slip+;
    # slip+ brings X' back up to the edge while F_d - X - 2 zeta X' > 0 and the band pushes it out
    # again: Filippov sliding on the lower edge; it ends at F_d - X - 2 zeta X' = 0 -> slip+, and
    # from that velocity extreme the damped slip about F_d never reaches the band again.
    modes = modes_of(run(Exact(), Karnopp(FD, FS, stick_force="spring")))
    assert modes == [S.SLIP_POSITIVE, S.BAND_EDGE_LOWER, S.SLIP_POSITIVE]


MIRROR_CASES = {
    **STICK_SLIP_CASES,
    "exact-karnopp": (Exact(), Karnopp(FD, FS)),
    "exact-karnopp-spring": (Exact(), Karnopp(FD, FS, stick_force="spring")),
}


@pytest.mark.parametrize("case", MIRROR_CASES)
def test_a_mirrored_run_enters_the_mirrored_modes(case):
    # The equation is odd in (X, X', V_b): the mirrored run switches at the same times into the
    # mirror images of the modes.
    solver, law = MIRROR_CASES[case]
    tr, mirrored = run(solver, law), run(solver, law, sign=-1.0)
    assert modes_of(mirrored) == [MIRROR[m] for m in modes_of(tr)]
    assert np.allclose(mirrored.events["t"], tr.events["t"], rtol=1e-9, atol=1e-12)


def test_rk4_locates_no_switches_and_reports_none():
    tr = simulate(BeltOscillator(zeta=ZETA, vb=VB), Karnopp(FD, FS), RK4(dt=1e-3), t_end=20.0)
    assert tr.events is None


# The codes each kernel can record, taken from the kernels, not from the tables:
# the exact kernel enters a mode from its candidate lists; Dormand-Prince records
# the slip direction d = +-1, or 0 when it sticks.
KERNEL_CODES = {
    "exact": (EXACT_EVENT_MODES, set(exact_kernel.KARNOPP_ORDER.tolist()) | set(exact_kernel.COULOMB_ORDER.tolist())),
    "adaptive": (ADAPTIVE_EVENT_MODES, {-1, 0, 1}),
}


@pytest.mark.parametrize("solver", KERNEL_CODES)
def test_every_kernel_code_maps_to_its_own_switch_mode(solver):
    table, codes = KERNEL_CODES[solver]
    assert set(table) == codes
    assert all(isinstance(table[c], SwitchMode) for c in codes)
    assert len(set(table.values())) == len(codes)  # no two kernel modes merge


def test_every_switch_mode_is_some_kernel_mode():
    reached = set(EXACT_EVENT_MODES.values()) | set(ADAPTIVE_EVENT_MODES.values())
    assert reached == set(SwitchMode)


def test_an_unknown_kernel_code_is_refused_not_passed_through():
    with pytest.raises(ValueError, match="99"):
        switch_modes(np.array([exact_kernel.STICK, 99]), EXACT_EVENT_MODES)


def test_event_modes_export_as_plain_json_integers():
    tr = run(Exact(), Karnopp(FD, FS))
    back = json.loads(json.dumps(tr.events["mode"].tolist()))
    assert [SwitchMode(m) for m in back] == modes_of(tr)
    assert SwitchMode.BAND_HOLD in back
