"""The dimensional table in the studies: a parameter a study varies and the table sets is refused in one line,
and orbit and continue report the table as simulate does.

``continue --dimensional '...,sigma0=180,...' --vary sigma0=90:360:4`` ran over non-dimensional sigma0 = 90..360
(the table's 180 means 10 non-dimensionally: the range was read in other units than the table's) and dropped the
table's value without a word, while ``--sigma0 10 --vary sigma0=...`` is refused as a conflict.  The dimensional
table's v_b and c are required, so with it vb and zeta cannot be varied: the message says to give the model
non-dimensionally.
"""

from __future__ import annotations

import json
import math

import pytest

from .processes import in_process, one_line

TABLE = "m=2,k=18,l_0=0.1,v_b=0.015,f_d=0.54,f_ms=0.9,vs=0.015,sigma1=3,c=12"


@pytest.mark.parametrize("argv, words", [
    (("continue", "--friction", "lugre", "--dimensional", TABLE + ",sigma0=180", "--vary", "sigma0=90:360:4"),
     ("--vary sigma0", "sigma0=180", "or leave sigma0 out of it")),
    (("continue", "--friction", "lugre", "--dimensional", TABLE, "--vary", "zeta=0.5:1:4"),
     ("--vary zeta", "c=12", "without the dimensional table")),
    (("continue", "--friction", "coulomb", "--dimensional", "m=1,k=1,c=0.1,v_b=0.01,f_d=0.02", "--vary",
      "vb=0.01:0.02:4"), ("--vary vb", "v_b=0.01")),
    (("forced-continue", "--friction", "coulomb", "--dimensional", "m=1,k=1,c=0.1,v_b=0,f_d=0.05,f_ex=0.3,w_ex=0.8",
      "--vary", "omega=0.7:0.9"), ("--vary omega", "w_ex=0.8")),
    (("map", "--friction", "stribeck", "--dimensional", "m=1,k=1,c=0.1,v_b=0.01,f_d=0.02,f_ms=0.04",
      "--x", "vb=0.004:0.03:4", "--y", "zeta=0:0.1:4"), ("--x vb", "v_b=0.01")),
])
def test_a_varied_parameter_the_table_sets_is_refused(tmp_path, argv, words) -> None:
    code, out, err, _ = in_process(*argv, "--json", cwd=tmp_path)
    assert code == 2, err
    one_line(err, *words)
    assert out == "" and list(tmp_path.iterdir()) == []


def test_a_parameter_the_table_leaves_out_is_varied(tmp_path) -> None:
    """sigma0 not in the table: the law's non-dimensional default stands, and the range is non-dimensional."""
    code, out, err, _ = in_process("continue", "--friction", "lugre", "--dimensional", TABLE, "--vary",
                                   "sigma0=5:20:4", "--seeds", "hopf", "--max-points", "5", "--json", cwd=tmp_path)
    assert code == 0, err
    assert '"param": "sigma0"' in out


@pytest.mark.parametrize("argv", [
    ("orbit", "--friction", "coulomb"),
    ("continue", "--friction", "stribeck", "--vary", "vs=0.005:0.02:5", "--max-points", "10"),
])
def test_orbit_and_continue_echo_the_dimensional_table(tmp_path, argv) -> None:
    """As simulate --json does: the results are non-dimensional, and omega0 = sqrt(k/m) converts their times."""
    table = "m=2,k=18,c=1.2,v_b=0.03,f_d=0.36,f_ms=0.72,l_0=0.1"
    code, out, err, _ = in_process(*argv, "--dimensional", table, "--json", cwd=tmp_path)
    assert code == 0, err
    report = json.loads(out)
    assert report["dimensional"] == {"m": 2.0, "k": 18.0, "c": 1.2, "v_b": 0.03, "f_d": 0.36, "f_ms": 0.72,
                                     "l_0": 0.1, "omega0": pytest.approx(3.0, rel=1e-15)}
    assert report["params"]["zeta"] == pytest.approx(1.2 / (2 * math.sqrt(2 * 18)), rel=1e-14)


FORCED = "m=2,k=18,c=1.2,v_b=0,f_d=0.36,f_ex=1.8,w_ex=2.4,l_0=0.1"


@pytest.mark.parametrize("argv, table", [
    (("simulate", "--friction", "coulomb", "--t-end", "50"), "m=2,k=18,c=1.2,v_b=0.03,f_d=0.36,f_ms=0.72,l_0=0.1"),
    (("orbit", "--friction", "coulomb"), "m=2,k=18,c=1.2,v_b=0.03,f_d=0.36,f_ms=0.72,l_0=0.1"),
    (("forced-orbit", "--friction", "coulomb"), FORCED),
    (("lyapunov", "--friction", "coulomb", "--t-end", "60", "--t-transient", "30"), FORCED),
])
def test_a_table_of_results_from_a_dimensional_table_says_they_are_non_dimensional(tmp_path, argv, table) -> None:
    """The printed table carries no units: its caption says the results are non-dimensional and gives the scales
    (omega0 = sqrt(k/m) = 3, l_0 = 0.1); the same run without the table says nothing of the kind."""
    code, out, err, _ = in_process(*argv, "--dimensional", table, cwd=tmp_path)
    assert code == 0, err
    assert "results non-dimensional: time tau = omega0 t (omega0 = 3)" in out and "(l_0 = 0.1)" in out, out
    params = {"--zeta": "0.1", "--fd": "0.2"} | ({"--vb": "0.0166667", "--fs": "0.4"} if "f_ms" in table else
                                                 {"--vb": "0", "--fex": "1", "--omega": "0.8"})
    code, out, err, _ = in_process(*argv, *(x for kv in params.items() for x in kv), cwd=tmp_path)
    assert code == 0, err
    assert "non-dimensional" not in out


@pytest.mark.parametrize("argv", [("forced-orbit", "--friction", "coulomb"),
                                  ("lyapunov", "--friction", "coulomb", "--t-end", "60", "--t-transient", "30")])
def test_forced_orbit_and_lyapunov_echo_the_dimensional_table(tmp_path, argv) -> None:
    """As simulate, orbit and continue do: the table and omega0 in the JSON; Omega = w_ex / omega0 = 0.8."""
    code, out, err, _ = in_process(*argv, "--dimensional", FORCED, "--json", cwd=tmp_path)
    assert code == 0, err
    report = json.loads(out)
    assert report["dimensional"]["omega0"] == pytest.approx(3.0, rel=1e-15)
    assert report["dimensional"]["w_ex"] == 2.4 and report["dimensional"]["l_0"] == 0.1
