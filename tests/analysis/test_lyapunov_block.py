"""The renormalisation interval of strongly overdamped runs, the collapse verdict, the argument checks.

Steady sliding under Coulomb friction is linear, X'' + 2 zeta X' + X = const: its exponents are the eigenvalues
-zeta -+ sqrt(zeta^2 - 1).  Over one default block (2 pi) the two tangent vectors grow apart by
e^((lambda_1 - lambda_2) 2 pi), beyond the float range's 1 / 2^-52 ~ e^36 from zeta ~ 3 on: lambda_2 read
rounding noise (or -inf, called a stick collapse with no stick at all) until the run was repeated with shorter
renormalisation intervals.
"""

from __future__ import annotations

import json
import math

import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.analysis import lyapunov as lyap
from frictionflow.analysis.lyapunov import GROWTH_CHECK, lyapunov_exponents

EPS = 2.0**-52
STEPS = 2000  # the QA command's --steps-per-period
T_TRANSIENT, T_END = 10.0, 300.0


def sliding(zeta: float) -> tuple[BeltOscillator, Coulomb, float, float]:
    """(model, law, x0, v0): sliding from X' = 0, never sticking (F_e = X + 2 zeta V_b stays off F_s)."""
    return BeltOscillator(zeta=zeta, vb=0.01), Coulomb(0.02, 0.04), 0.02, 0.0


def eigenvalues(zeta: float) -> tuple[float, float]:
    r = math.sqrt(zeta * zeta - 1.0)
    return -zeta + r, -zeta - r


def rk4_exponent(lam: float, h: float) -> float:
    """The exponent RK4 at step h gives y' = lam y: log |R(h lam)| / h."""
    z = h * lam
    return math.log(abs(1.0 + z + z**2 / 2.0 + z**3 / 6.0 + z**4 / 24.0)) / h


def tolerance(zeta: float, r) -> float:
    """What may separate a run's lambda_2 from the closed form, term by term.

    * RK4's own error at the run's step: |log|R(h lambda_2)| / h - lambda_2| (computed, not guessed);
    * the frame's start: after the transient the first vector is off the slow eigenvector by about
      e^(-(lambda_1 - lambda_2) t_transient), which moves log r11 (and so log r22, their sum being the trace's)
      by about as much over the whole averaging time: 10 e^(-(l1 - l2) t_tr) / (t_end - t_tr);
    * rounding: each renormalisation interval may lose GROWTH_CHECK eps of log |r22| (the ratio the run accepts),
      qr_per_block of them per block.
    """
    l1, l2 = eigenvalues(zeta)
    s = r.settings
    h = s["block"] / s["steps_per_block"]
    averaged = s["t_end"] - s["t_transient"]
    rk4 = abs(rk4_exponent(l2, h) - l2)
    start = 10.0 * math.exp(-(l1 - l2) * s["t_transient"]) / averaged
    rounding = GROWTH_CHECK * EPS * s["qr_per_block"] / s["block"]
    return rk4 + start + rounding


@pytest.mark.parametrize("zeta", [3.0, 5.0, 10.0, 40.0])
def test_overdamped_second_exponent_is_the_closed_form(zeta):
    model, law, x0, v0 = sliding(zeta)
    r = lyapunov_exponents(model, law, x0, v0, t_transient=T_TRANSIENT, t_end=T_END, steps_per_block=STEPS)
    l1, l2 = eigenvalues(zeta)
    assert not any(r.switches.values()) and not r.collapsed
    tol = tolerance(zeta, r)
    assert tol < 1e-4 * abs(l2)  # the check has teeth: the old -9.9 -> -inf, -19.95 -> -6.64 are far outside
    assert abs(r.exponents[1] - l2) <= tol
    assert abs(r.exponents[0] - l1) <= tol
    assert r.settings["block"] == pytest.approx(2.0 * math.pi)  # the default block, renormalised within
    assert r.settings["qr_per_block"] >= math.ceil((l1 - l2) * 2.0 * math.pi / math.log(GROWTH_CHECK))
    assert r.running.shape == (r.settings["blocks"], 2) and len(r.sections) == len(r.times) + 2


def test_the_command_line_reports_the_closed_form_not_a_collapse(capsys):
    from frictionflow.cli import main
    import frictionflow.cli.lyapunov  # noqa: F401  (registers the command)

    args = ["lyapunov", "--zeta", "5", "--t-end", "300", "--t-transient", "10", "--steps-per-period", "2000"]
    assert main([*args, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["switches"]["stick_onsets"] == 0 and d["collapsed"] is False and d["minus_infinity"] == [False, False]
    assert d["exponents"][1] == pytest.approx(eigenvalues(5.0)[1], rel=1e-6)
    assert main(args) == 0
    assert "collapse" not in capsys.readouterr().out


def test_the_first_exponent_does_not_move_with_the_renormalisations(monkeypatch):
    model, law, x0, v0 = sliding(10.0)
    refined = lyapunov_exponents(model, law, x0, v0, t_transient=T_TRANSIENT, t_end=T_END, steps_per_block=STEPS)
    monkeypatch.setattr(lyap, "MAX_REFINE", 0)  # the old arithmetic: one QR per block
    once = lyapunov_exponents(model, law, x0, v0, t_transient=T_TRANSIENT, t_end=T_END, steps_per_block=STEPS)
    assert once.settings["qr_per_block"] == 1 and refined.settings["qr_per_block"] > 1
    assert refined.exponents[0] == pytest.approx(once.exponents[0], rel=1e-12)
    assert refined.sections == pytest.approx(once.sections, rel=1e-12, abs=1e-15)


def test_a_second_exponent_lost_without_a_stick_is_no_collapse(monkeypatch):
    monkeypatch.setattr(lyap, "MAX_REFINE", 0)  # keep the frame of one QR per block: r22 is rounding or 0
    model, law, x0, v0 = sliding(5.0)
    r = lyapunov_exponents(model, law, x0, v0, t_transient=T_TRANSIENT, t_end=T_END, steps_per_block=STEPS)
    assert not r.stuck and not r.collapsed
    d = r.as_dict()
    assert d["collapsed"] is False
    assert "collapse" not in r.summary()


def test_a_stick_slip_cycle_still_collapses():
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04)
    r = lyapunov_exponents(model, law, t_transient=100.0, t_end=600.0)  # from (F_d, V_b): the stick-slip cycle
    assert r.switches["stick_onsets"] > 0 and r.stuck
    assert r.exponents[1] == -math.inf and r.collapsed and r.settings["qr_per_block"] == 1
    assert "stick onsets collapse" in r.summary() and r.as_dict()["collapsed"] is True


def test_an_underestimated_spread_is_caught_by_the_measured_growth(monkeypatch):
    monkeypatch.setattr(lyap, "_slip_spread", lambda model, friction: 0.0)  # no a-priori help
    model, law, x0, v0 = sliding(10.0)
    r = lyapunov_exponents(model, law, x0, v0, t_transient=T_TRANSIENT, t_end=T_END, steps_per_block=STEPS)
    assert abs(r.exponents[1] - eigenvalues(10.0)[1]) <= tolerance(10.0, r)


def test_a_run_with_stop_keeps_one_renormalisation_per_block():
    model, law, x0, v0 = sliding(5.0)
    r = lyapunov_exponents(model, law, x0, v0, t_transient=T_TRANSIENT, t_end=T_END, steps_per_block=STEPS,
                           stop=(4, 2, 2.0, 1e-4))
    assert r.settings["qr_per_block"] == 1 and r.exponents[0] == pytest.approx(eigenvalues(5.0)[0], rel=1e-6)


@pytest.mark.parametrize("kw, says", [
    (dict(x0="a"), "x0 must be"), (dict(v0="a"), "v0 must be"), (dict(block="a"), "block must be"),
    (dict(t_transient="5"), "t_transient must be"), (dict(t_end="50"), "t_end must be"),
    (dict(steps_per_block="a"), "steps_per_block must be"), (dict(steps_per_block=True), "steps_per_block must be"),
    (dict(x0=True), "x0 must be"), (dict(max_memory=math.nan), "max_memory must be > 0"),
    (dict(max_memory=-1.0), "max_memory must be > 0"), (dict(max_memory=0.0), "max_memory must be > 0"),
    (dict(max_memory="4"), "max_memory must be"),
])
def test_bad_arguments_are_refused_by_name(kw, says):
    with pytest.raises(ValueError, match=f"^{says}") as info:
        lyapunov_exponents(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04), **kw)
    assert "\n" not in str(info.value) and "could not convert" not in str(info.value)


def test_the_memory_refusal_says_how_to_raise_the_limit():
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.04)
    with pytest.raises(ValueError, match="shorten t_end or raise max_memory") as info:
        lyapunov_exponents(model, law, t_transient=0.0, t_end=1e12)
    assert "--config" in str(info.value) and "max_memory = " in str(info.value)
