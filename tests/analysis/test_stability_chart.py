"""Steady sliding's stability over two parameters (issue 22, item 5: "the eigenvalue analysis over one or two
parameters").

The structure is Hoffmann's minimal model assembled by hand as in tests/analysis/test_stability.py; the boundary
is the closed form derived there from the discriminant of det(K_eff - s M) = 0, as a function of the second
parameter (the proportional damping c, or the stiffness K22), and the growth rates are numpy's eigenvalues of
the first-order matrix written out entry by entry.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import Coulomb
from frictionflow.analysis.stability_chart import chart_estimate, stability_chart
from tests.analysis.test_stability import CN, KH, PRELOAD, assembly, hoffmann, hoffmann_threshold


def first_order(mu: float, c: float, khat: np.ndarray = KH) -> np.ndarray:
    """A = [[0, I], [-K_eff, -c I]] with K_eff = K - mu e n^T (e = (1, 0), n = (0, CN)) and M = I."""
    k_eff = khat - mu * np.array([[0.0, CN], [0.0, 0.0]])
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-k_eff, -c * np.eye(2)]])


def test_the_boundary_follows_the_closed_form_threshold_as_the_damping_grows():
    mus, cs = np.linspace(0.1, 1.2, 23), np.array([0.0, 0.02, 0.05, 0.1])
    chart = stability_chart(hoffmann, mus, cs, x="contact.0.fd", y="damping")
    assert chart.growth.shape == chart.stable.shape == chart.frequency.shape == (len(cs), len(mus))
    for c in cs:
        [point] = [b for b in chart.boundary if b.y_value == c]
        mu_c, omega_c = hoffmann_threshold(c)
        assert point.point.kind == "mode_coupling" and point.point.unstable_above
        assert point.point.value == pytest.approx(mu_c, rel=1e-12)
        assert point.point.frequency == pytest.approx(omega_c, rel=1e-12)
    # the threshold rises with damping: the boundary is not one vertical line
    values = [b.point.value for b in chart.boundary]
    assert values == sorted(values) and values[-1] - values[0] > 0.01
    assert np.array_equal(chart.stable, mus[None, :] < np.array([hoffmann_threshold(c)[0] for c in cs])[:, None])


def test_the_growth_rate_is_numpys_largest_real_part_at_every_grid_point():
    mus, cs = np.linspace(0.2, 1.0, 9), np.array([0.01, 0.04])
    chart = stability_chart(hoffmann, mus, cs)
    for i, c in enumerate(cs):
        for j, mu in enumerate(mus):
            lam = np.linalg.eigvals(first_order(mu, c))
            top = lam[np.argmax(lam.real)]
            assert chart.growth[i, j] == pytest.approx(top.real, rel=1e-10, abs=1e-13)
            assert chart.frequency[i, j] == pytest.approx(abs(top.imag), rel=1e-10)


def test_a_stiffness_as_second_parameter_moves_the_threshold_as_the_discriminant_says():
    def at(mu: float, k22: float):
        khat = KH.copy()
        khat[1, 1] = k22
        return hoffmann_khat(mu, khat)

    mus, k22s = np.linspace(0.05, 1.5, 30), np.array([1.9, 2.3, 2.8])
    chart = stability_chart(at, mus, k22s, x="contact.0.fd", y="spring.1.k")
    (k11, k12), (k21, _) = KH
    for k22 in k22s:
        mu_c = ((k11 - k22) ** 2 + 4.0 * k21 * k12) / (4.0 * k21 * CN)
        [point] = [b.point for b in chart.boundary if b.y_value == k22]
        assert point.kind == "mode_coupling"
        assert point.value == pytest.approx(mu_c, rel=1e-12)
        assert point.frequency == pytest.approx(math.sqrt((k11 + k22) / 2.0), rel=1e-12)


def hoffmann_khat(mu: float, khat: np.ndarray):
    return assembly(np.eye(2), khat, np.zeros((2, 2)), [[1.0, 0.0]], [0.5], [Coulomb(fd=mu, fs=mu)],
                    normal=[[PRELOAD, 0.0, CN]])


def test_the_chart_reads_as_json_and_a_summary():
    chart = stability_chart(hoffmann, np.linspace(0.3, 0.9, 7), [0.0, 0.05], x="contact.0.fd", y="c")
    d = chart.to_dict()
    assert d["x"] == "contact.0.fd" and d["y"] == "c" and len(d["x_values"]) == 7 and d["y_values"] == [0.0, 0.05]
    assert np.array_equal(np.array(d["growth"]), chart.growth) and np.array_equal(np.array(d["stable"]), chart.stable)
    assert [b["y_value"] for b in d["boundary"]] == [0.0, 0.05]
    assert {"value", "kind", "frequency", "unstable_above"} <= set(d["boundary"][0])
    text = repr(chart)
    assert "StabilityChart" in text and "2 mode_coupling" in text


def test_bad_values_are_refused_in_one_line():
    with pytest.raises(ValueError, match="y_values must be at least 1 finite number"):
        stability_chart(hoffmann, [0.1, 0.2], [0.0, math.nan])
    with pytest.raises(ValueError, match="strictly increasing or strictly decreasing"):
        stability_chart(hoffmann, [0.1, 0.1], [0.0])


def test_the_estimate_is_one_line_scan_per_value_of_y():
    one = chart_estimate(2, 41, 1)
    assert chart_estimate(2, 41, 10).seconds == pytest.approx(10 * one.seconds)
    assert chart_estimate(2, 41, 10).work == 10 * one.work


def test_an_undamped_stable_cell_gives_its_lowest_frequency_not_the_one_rounding_picks():
    """Undamped and below the threshold, both modes sit on the axis (real parts +-1e-17): their growth is one tie,
    and the frequency is the lower sqrt of K_eff's eigenvalues (QA: cells jumped between the two modes).  Beyond
    the threshold it is the growing pair's, as numpy's largest real part says."""
    mu_c, _ = hoffmann_threshold()
    mus = np.linspace(0.1, 1.2, 23)
    chart = stability_chart(hoffmann, mus, [0.0])
    for j, mu in enumerate(mus):
        lam = np.linalg.eigvals(first_order(mu, 0.0))
        if mu < mu_c:
            low = math.sqrt(min(np.linalg.eigvals(-first_order(mu, 0.0)[2:, :2]).real))
            assert chart.stable[0, j] and chart.frequency[0, j] == pytest.approx(low, rel=1e-12)
        else:
            assert chart.frequency[0, j] == pytest.approx(abs(lam[np.argmax(lam.real)].imag), rel=1e-10)
