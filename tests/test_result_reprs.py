"""SteadyState and PowerFlow read like the other results: a short repr in significant digits, an HTML table."""

from __future__ import annotations

import dataclasses
import re

import pytest

from frictionflow import BeltOscillator, Coulomb, analyze, simulate
from frictionflow.analysis.power_flow import power_flow

MAX_LINES, MAX_CHARS = 12, 900


@pytest.fixture(scope="module")
def result():
    return analyze(simulate(BeltOscillator(0.05, 0.00772279), Coulomb(0.02, 0.04), t_end=100.0))


def no_long_numbers(text: str) -> bool:
    """No number with more than 8 significant digits (a dataclass repr prints 16-17)."""
    return all(len(m.replace(".", "").lstrip("0")) <= 8 for m in re.findall(r"\d+\.\d+", text))


def test_steady_state_repr(result):
    ss = result.steady_state
    text = repr(ss)
    assert text.startswith("SteadyState\n") and "SteadyState(" not in text
    assert len(text.splitlines()) <= MAX_LINES and len(text) <= MAX_CHARS and no_long_numbers(text)
    assert "periodic, stable" in text and f"{ss.period:.8g}" in text and f"{ss.n_periods} in the window" in text
    assert f"tau {ss.window[0]:.6g} .. {ss.window[1]:.6g}" in text and f"{ss.stick_fraction:.4g}" in text
    assert "decay rate" not in text  # unset fields are not shown
    page = ss._repr_html_()
    assert page.startswith("<table") and page.count("<tr>") == len(text.splitlines()) - 1


def test_an_equilibrium_shows_its_limit_and_decay_rate():
    """Sliding on a slowly damped spiral: the decay rate is zeta, the limit X = F_d."""
    ss = analyze(simulate(BeltOscillator(0.01, 0.01), Coulomb(0.02, 0.02), t_end=60.0, x0=0.03, v0=0.0)).steady_state
    text = repr(ss)
    assert ss.kind == "equilibrium" and "period" not in text
    assert f"decay rate      {ss.decay_rate:.4g}" in text and f"limit           x={ss.limit['x']:.4g}" in text
    assert no_long_numbers(text)


def test_power_flow_repr(result):
    pf = result.power
    text = repr(pf)
    assert text.startswith("PowerFlow\n") and "PowerFlow(" not in text
    assert len(text.splitlines()) <= MAX_LINES and len(text) <= MAX_CHARS and no_long_numbers(text)
    for k in ("P_fin", "P_df", "P_dv", "R_c", "R_f", "P_belt", "P_heat", "P_f"):
        assert f"{k}={getattr(pf, k):.4g}" in text
    assert "P_ex" not in text  # unforced
    assert f"residual      {pf.energy_residual:.2g}" in text
    assert pf._repr_html_().count("<tr>") == len(text.splitlines()) - 1
    # the values themselves stay exact: only the display is rounded
    assert pf.to_dict()["P_fin"] == pf.P_fin and dataclasses.replace(pf) == pf


def test_forced_power_flow_shows_the_external_force():
    traj = simulate(BeltOscillator(0.05, 0.01, fex=0.1, omega=0.9), Coulomb(0.02, 0.04), t_end=60.0)
    pf = power_flow(traj)
    assert f"P_ex={pf.P_ex:.4g}" in repr(pf)
