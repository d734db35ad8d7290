"""``frictionflow stability --model FILE``: the eigenvalues of steady sliding along one model entry (issue 22, 5-6).

The model files are written here; the thresholds are the closed forms derived in the tests (the same derivations
as tests/analysis/test_stability.py, on these files' numbers).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from frictionflow._ranges import Range
from frictionflow.cli import main

# Hoffmann's minimal model: x1 tangential, x2 normal, M = I; springs k1 on x1, k2 on x2, k3 along (1, 1); one
# contact along x1 with N = P + c x2, Coulomb at mu = fd (fs = 2 keeps fd <= fs over the range)
HOFFMANN = """
dof = ["x1", "x2"]
mass = [1.0, 1.0]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x2 = 1.0 }
k = 1.8
[[spring]]
on = { x1 = 1.0, x2 = 1.0 }
k = 0.5
[[contact]]
on = { x1 = 1.0 }
belt = 0.5
friction = "coulomb"
fd = 0.3
fs = 2.0
normal = { preload = 1.0, x2 = 2.0 }
"""

# one mass on a Stribeck curve |F| = fd + (fs - fd) exp(-v / vs) (delta = 1), zeta = 0.05
SINGLE = """
dof = ["x"]
mass = [1.0]
[[spring]]
on = { x = 1.0 }
k = 1.0
[[damper]]
on = { x = 1.0 }
c = 0.1
[[contact]]
on = { x = 1.0 }
belt = 0.05
friction = "stribeck"
fd = 0.02
fs = 0.04
vs = 0.01
delta = 1.0
"""


def hoffmann_threshold() -> tuple[float, float]:
    """K = [[1.5, 0.5], [0.5, 2.3]], K_eff = K - mu e n^T = [[1.5, 0.5 - 2 mu], [0.5, 2.3]]: det(K_eff - s I) = 0 has
    the discriminant (K11 - K22)^2 + 4 K21 (K12 - 2 mu), zero at mu_c; the frequencies meet at sqrt((K11 + K22)/2)."""
    k11, k12, k21, k22, c = 1.5, 0.5, 0.5, 2.3, 2.0
    return ((k11 - k22) ** 2 + 4.0 * k21 * k12) / (4.0 * k21 * c), math.sqrt((k11 + k22) / 2.0)


@pytest.fixture
def models(tmp_path):
    (tmp_path / "hoffmann.toml").write_text(HOFFMANN)
    (tmp_path / "single.toml").write_text(SINGLE)
    return tmp_path


def run_json(capsys, *args):
    assert main(["stability", *args, "--json"]) == 0
    out, err = capsys.readouterr()
    return json.loads(out), err


def test_the_flutter_threshold_of_a_model_file(models, capsys):
    report, err = run_json(capsys, "--model", str(models / "hoffmann.toml"), "--vary", "contact.0.fd=0.1:0.8:15")
    mu_c, omega_c = hoffmann_threshold()
    assert err == ""
    assert report["param"] == "contact.0.fd" and len(report["values"]) == 15
    assert len(report["eigenvalues"]) == 15 and all(len(row) == 4 for row in report["eigenvalues"])
    [crit] = report["critical"]
    assert crit["kind"] == "mode_coupling"
    assert crit["value"] == pytest.approx(mu_c, rel=1e-12) and crit["frequency"] == pytest.approx(omega_c, rel=1e-12)


def test_the_issues_spelling_gives_the_same_result_without_a_warning(models, capsys):
    model = str(models / "hoffmann.toml")
    new, _ = run_json(capsys, "--model", model, "--vary", "contact.0.fd=0.1:0.8:15")
    old, err = run_json(capsys, "--model", model, "--param", "contact.0.fd", "--from", "0.1", "--to", "0.8",
                        "--points", "15")
    assert old == new and err == ""


def test_negative_damping_of_one_mass_at_the_closed_form_belt_speed(models, capsys):
    # 2 zeta + d|F|/dv = 0: 0.1 = (fs - fd)/vs exp(-v/vs) -> v* = vs ln((fs - fd) / (0.1 vs))
    report, _ = run_json(capsys, "--model", str(models / "single.toml"), "--vary", "contact.0.belt=0.005:0.08:31")
    [crit] = report["critical"]
    assert crit["kind"] == "negative_damping" and not crit["unstable_above"]
    assert crit["value"] == pytest.approx(0.01 * math.log(0.02 / (0.1 * 0.01)), rel=1e-12)
    assert crit["frequency"] == pytest.approx(1.0, rel=1e-12)


def test_out_writes_what_json_prints_and_plot_draws(models, capsys):
    args = ["--model", str(models / "hoffmann.toml"), "--vary", "contact.0.fd=0.1:0.8:9"]
    printed, _ = run_json(capsys, *args)
    out, fig = models / "s.json", models / "s.png"
    assert main(["stability", *args, "--out", str(out), "--plot", str(fig)]) == 0
    table = " ".join(capsys.readouterr().out.split())
    assert json.loads(out.read_text()) == printed and fig.stat().st_size > 0
    assert "mode_coupling" in table and "2 dof, 1 contact;" in table


@pytest.mark.parametrize("args, words", [
    (["--vary", "spring.7.k=0:1"], "spring.7"),
    (["--vary", "contact.0.fd=0.1:0.8:1"], "--vary contact.0.fd: N must be >= 2"),
    (["--vary", "contact.0.fd=0.1:0.8:0"], "--vary contact.0.fd: N must be >= 2"),  # one bound, not ">= 1" here
    (["--vary", "contact.0.fd=0.3:0.3"], "FROM and TO must differ"),
    (["--vary", "contact.0.belt=-0.5:0.5:3"], "contact.0.belt = 0.0: contact.0.belt must be nonzero"),
    # a bad end is named before the values between are computed (the scan named the first bad one: 2.1 here)
    (["--vary", "contact.0.fd=0.1:3.9:20"], "contact.0.fd = 3.9: model "),
    (["--param", "spring.0.k", "--from", "0.5", "--to", "1e20"], "spring.0.k = 1e+20: model "),
    (["--vary", "contact.0.fd=0.1:0.8", "--param", "contact.0.fd", "--from", "0.1", "--to", "0.2"], "not both"),
    (["--param", "contact.0.fd", "--from", "0.1"], "--param, --from and --to go together"),
    (["--vary", "contact.0.fd=0.1:0.8", "--out", "{dir}/s.txt"], "--out must end in"),
    (["--vary", "contact.0.fd=0.1:0.8", "--plot", "{dir}/s.txt"], "--plot must end in"),
    # an entry that is no number, and the initial state, which steady sliding does not depend on (both were
    # taken: the first failed at its first value, the second scanned the same eigenvalues at every value)
    (["--vary", "contact.0.stick_force=0:1"], "--vary contact.0.stick_force: not a numeric entry"),
    (["--vary", "initial.q.x1=0:1"], "--vary initial.q.x1: steady sliding and its eigenvalues do not depend"),
])
def test_bad_input_is_refused_in_one_line_with_nothing_written(models, capsys, args, words):
    argv = ["stability", "--model", str(models / "hoffmann.toml"), *[a.format(dir=models) for a in args]]
    if "--out" not in args:
        argv += ["--out", str(models / "written.json")]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not (models / "written.json").exists() and not (models / "s.txt").exists()


def test_a_missing_or_bad_model_file_is_refused_in_one_line(models, capsys):
    assert main(["stability", "--model", str(models / "none.toml"), "--vary", "contact.0.fd=0.1:0.8"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    (models / "bad.toml").write_text(HOFFMANN.replace('x2 = 2.0 }', 'x3 = 2.0 }'))
    assert main(["stability", "--model", str(models / "bad.toml"), "--vary", "contact.0.fd=0.1:0.8"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "x3" in err[0]


def test_a_scan_estimated_above_the_limit_is_refused_before_it_starts(models, capsys):
    # a chain of 100 masses: 10^5 eigenvalue problems of size 200 are hours of work
    n = 100
    lines = [f"dof = [{', '.join(f'{chr(34)}x{i}{chr(34)}' for i in range(n))}]", f"mass = [{', '.join(['1.0'] * n)}]"]
    for i in range(n):
        on = f"x{i} = 1.0" if i == 0 else f"x{i} = 1.0, x{i - 1} = -1.0"
        lines += ["[[spring]]", f"on = {{ {on} }}", "k = 1.0"]
    lines += ["[[contact]]", "on = { x0 = 1.0 }", "belt = 0.1", 'friction = "coulomb"', "fd = 0.1", "fs = 0.2"]
    (models / "chain.toml").write_text("\n".join(lines) + "\n")
    args = ["stability", "--model", str(models / "chain.toml"), "--vary", "contact.0.belt=0.1:0.2:100000"]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "estimated" in err[0] and "--no-limit" in err[0], err


# -- two entries: --x and --y ------------------------------------------------------------------------------------------

def test_a_chart_over_two_entries_locates_the_threshold_on_every_line(models, capsys):
    # spring.1.k = k2 sets K22 = k2 + 0.5; the discriminant's root moves with it (the closed form above, K22 free)
    report, err = run_json(capsys, "--model", str(models / "hoffmann.toml"), "--x", "contact.0.fd=0.05:1.5:30",
                           "--y", "spring.1.k=1.4:2.3:4")
    assert err == "" and report["x"] == "contact.0.fd" and report["y"] == "spring.1.k"
    assert len(report["growth"]) == 4 and all(len(row) == 30 for row in report["growth"])
    assert [b["y_value"] for b in report["boundary"]] == pytest.approx(report["y_values"], rel=0, abs=0)
    k11, k12, k21, c = 1.5, 0.5, 0.5, 2.0
    for point in report["boundary"]:
        k22 = point["y_value"] + 0.5
        assert point["kind"] == "mode_coupling"
        assert point["value"] == pytest.approx(((k11 - k22) ** 2 + 4.0 * k21 * k12) / (4.0 * k21 * c), rel=1e-12)
        assert point["frequency"] == pytest.approx(math.sqrt((k11 + k22) / 2.0), rel=1e-12)


def test_a_chart_line_equals_the_scan_of_that_line(models, capsys):
    model = str(models / "hoffmann.toml")
    chart, _ = run_json(capsys, "--model", model, "--x", "contact.0.fd=0.1:0.8:15", "--y", "spring.1.k=1.8:2.0:2")
    scan, _ = run_json(capsys, "--model", model, "--vary", "contact.0.fd=0.1:0.8:15")
    [point] = [b for b in chart["boundary"] if b["y_value"] == 1.8]
    assert {k: point[k] for k in scan["critical"][0]} == scan["critical"][0]
    top = [max(z["re"] for z in row) for row in scan["eigenvalues"]]
    assert chart["growth"][0] == top


def test_a_chart_over_entries_that_bound_each_other_sets_both_at_once(models, capsys):
    """F_s from 0.2 is below the file's F_d = 0.3, but every point's F_d (at most 0.15) is below its F_s: each point
    is a valid contact (it was refused when F_s was set before F_d).  Steady sliding knows F_d only: every line of
    the chart is the scan of F_d."""
    model = str(models / "hoffmann.toml")
    chart, err = run_json(capsys, "--model", model, "--x", "contact.0.fd=0.05:0.15:5", "--y", "contact.0.fs=0.2:0.25:2")
    scan, _ = run_json(capsys, "--model", model, "--vary", "contact.0.fd=0.05:0.15:5")
    top = [max(z["re"] for z in row) for row in scan["eigenvalues"]]
    assert err == "" and chart["growth"] == [top, top]


def test_the_chart_writes_its_json_and_figure(models, capsys):
    args = ["--model", str(models / "hoffmann.toml"), "--x", "contact.0.fd=0.1:0.8:8", "--y", "spring.1.k=1.5:2.5:3"]
    printed, _ = run_json(capsys, *args)
    out, fig = models / "c.json", models / "c.png"
    assert main(["stability", *args, "--out", str(out), "--plot", str(fig)]) == 0
    table = " ".join(capsys.readouterr().out.split())
    assert json.loads(out.read_text()) == printed and fig.stat().st_size > 0
    assert "StabilityChart" in table and "8 x 3 values of contact.0.fd x spring.1.k" in table


@pytest.mark.parametrize("args, words", [
    (["--vary", "contact.0.fd=0.1:0.8", "--x", "contact.0.fd=0.1:0.8"], "one or the other"),
    (["--x", "contact.0.fd=0.1:0.8"], "needs --y"),
    (["--y", "spring.1.k=1:2"], "needs --x"),
    ([], "needs --vary, or --x with --y"),
    (["--x", "contact.0.fd=0.1:0.8", "--y", "contact.0.fd=0.2:0.3"], "the same entry"),
    (["--x", "contact.0.fd=0.1:0.8", "--y", "spring.9.k=1:2"], "spring.9"),
    (["--x", "contact.0.fd=0.1:0.8", "--y", "spring.1.k=1:2:1"], "--y spring.1.k: N must be >= 2"),
    (["--x", "spring.0.k=0.5:2:5", "--y", "spring.1.k=0.1:1e20:5"], "spring.1.k = 1e+20, spring.0.k = 0.5: model "),
    (["--x", "contact.0.fd=0.1:0.8", "--y", "initial.v.x2=0:1"], "--y initial.v.x2: steady sliding"),
])
def test_bad_chart_input_is_refused_in_one_line_with_nothing_written(models, capsys, args, words):
    argv = ["stability", "--model", str(models / "hoffmann.toml"), *args, "--out", str(models / "written.json")]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert not (models / "written.json").exists()


def test_the_initial_state_plays_no_part_in_a_scan(models, capsys):
    """Steady sliding alone: an [initial] state whose normal load P + 2 x2 is <= 0 at the smaller preloads (x2 = -0.3:
    P <= 0.6) no longer refuses the scan (QA: the whole scan failed on the file's start at one value).  With Coulomb
    and N linear in q, K_eff = K - mu e n^T does not depend on P: every row is +-i sqrt of K_eff's eigenvalues, and
    N* = P / (1 + 2 mu 0.15625) > 0 everywhere (K^-1's (2, 1) entry is -0.5 / 3.2)."""
    (models / "start.toml").write_text(HOFFMANN + "[initial]\nq = { x2 = -0.3 }\n")
    report, err = run_json(capsys, "--model", str(models / "start.toml"), "--vary", "contact.0.normal.preload=0.1:1:10")
    assert err == "" and not any(report["lost"]) and report["critical"] == []
    k_eff = [[1.5, 0.5 - 2.0 * 0.3], [0.5, 2.3]]
    half = (k_eff[0][0] + k_eff[1][1]) / 2
    root = math.sqrt(half ** 2 - (k_eff[0][0] * k_eff[1][1] - k_eff[0][1] * k_eff[1][0]))
    expected = sorted(math.sqrt(lam) for lam in (half - root, half + root))
    for row in report["eigenvalues"]:
        assert all(abs(e["re"]) < 1e-12 for e in row)
        assert sorted(abs(e["im"]) for e in row) == pytest.approx(sorted(expected * 2), rel=1e-12)


def test_a_scan_s_values_are_the_decimals_its_range_implies():
    # linspace's 0.7000000000000001 would be refused beside F_s = 0.7; a value that is no short decimal is kept
    values = Range(0.5, 0.8).grid(7)
    assert values.tolist() == [0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8]
    assert np.abs(values - np.linspace(0.5, 0.8, 7)).max() <= 2 * np.spacing(0.8)
    assert Range(0.0, 1.0).grid(4).tolist() == np.linspace(0.0, 1.0, 4).tolist()
