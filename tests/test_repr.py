"""Results that read well: short reprs with the key numbers, HTML tables for notebooks, ``.plot()``."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from frictionflow import RK4, BeltOscillator, Coulomb, Karnopp, analyze, simulate  # noqa: E402
from frictionflow._display import render_html, render_text  # noqa: E402
from frictionflow.orbits import Bifurcation, Branch, ContinuationResult, find_orbit  # noqa: E402

MAX_LINES, MAX_CHARS = 12, 900


def short(text: str) -> bool:
    return len(text.splitlines()) <= MAX_LINES and len(text) <= MAX_CHARS


@pytest.fixture(scope="module")
def result():
    return analyze(simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=100.0))


def test_trajectory_repr_is_short_and_says_law_solver_span_samples_switches(result):
    traj = result.trajectory
    text = repr(traj)
    assert short(text) and "array(" not in text
    assert "Coulomb(fd=0.02, fs=0.04" in text and "exact" in text and "tau 0 .. 100" in text
    assert f"samples   {len(traj)}" in text and f"switches  {len(traj.events['t'])}" in text


def test_rk4_trajectory_repr_says_it_locates_no_switches():
    traj = simulate(BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04), RK4(dt=1e-2), t_end=30.0)
    text = repr(traj)
    assert short(text) and "rk4 (dt=0.01" in text and "mode changes" in text


def test_analysis_repr_has_kind_period_power_ratios_trb_and_residual(result):
    text = repr(result)
    ss, av = result.steady_state, result.power.averages()
    assert short(text) and "array(" not in text
    assert "periodic, stable" in text and f"period {ss.period:.8g}" in text
    for k in ("P_fin", "P_df", "P_dv", "R_c", "R_f", "P_belt", "P_heat"):
        assert f"{k}={av[k]:.4g}" in text
    assert f"TR_B          {result.TR_B:.6g}" in text
    assert f"residual      {result.energy_residual:.2g}" in text


def test_html_tables_hold_the_same_rows(result):
    page = result._repr_html_()
    assert page.startswith("<table") and page.endswith("</table>")
    assert f"{result.TR_B:.6g}" in page and "<caption" in page and "Analysis" in page
    assert page.count("<tr>") == len(repr(result).splitlines()) - 1
    assert "&#x27;resultant&#x27;" in page  # values are escaped
    assert result.trajectory._repr_html_().count("<tr>") == 5


def test_the_renderers_align_labels_and_escape():
    assert render_text("T", [("a", "1"), ("long", "<2>")]) == "T\n  a     1\n  long  <2>"
    assert "&lt;2&gt;" in render_html("T", [("long", "<2>")])


def test_periodic_orbit_repr():
    orbit = find_orbit(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04))
    text = repr(orbit)
    assert short(text) and text.startswith("PeriodicOrbit")
    assert f"{orbit.period:.10g}" in text and "stable" in text and f"{orbit.measures.TR_B:.6g}" in text
    assert f"{orbit.stick_fraction:.4g}" in text
    assert orbit._repr_html_().startswith("<table")


def test_continuation_repr_lists_branches_and_bifurcations_briefly():
    branches = [Branch("equilibrium", [object()] * 101, "sliding equilibrium", "interval end"),
                Branch("periodic", [object()] * 40, "hopf", "fold")]
    bifs = [Bifurcation("hopf", 0.0123, 0)] + [Bifurcation("grazing", 0.02 + 0.001 * k, 1) for k in range(9)]
    res = ContinuationResult("vb", 0.005, 0.05, {"friction": "stribeck", "zeta": 0.02, "fd": 0.02}, branches, bifs)
    text = repr(res)
    assert short(text)
    assert "vb from 0.005 to 0.05" in text and "stribeck: zeta=0.02, fd=0.02" in text
    assert "periodic (hopf, 40 points, fold)" in text and "hopf at 0.0123" in text and "and 6 more" in text


def test_plot_methods_return_figures(result, tmp_path):
    for obj in (result, result.trajectory):
        fig = obj.plot()
        assert isinstance(fig, plt.Figure)
        plt.close(fig)
    result.trajectory.plot(tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 0


def test_figures_draw_the_true_curve(result):
    """plot_run's time history has many more points than the exact solver's samples, and lies on the curve."""
    fig = result.plot()
    line = fig.axes[0].get_lines()[0]
    t, x = (np.asarray(a) for a in line.get_data())
    plt.close(fig)
    traj = result.trajectory
    assert len(t) > 5 * len(traj) and np.diff(t).max() <= 2 * np.pi / 64 * (1 + 1e-12)
    assert np.allclose(x, traj(t)[0], rtol=0, atol=1e-14)
