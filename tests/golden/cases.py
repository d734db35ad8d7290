"""The golden cases: command lines whose JSON output was recorded before the architecture refactor (issue 9).

``python -m tests.golden.record`` writes ``data/*.json`` from the current code;
``tests/golden/test_golden.py`` compares today's output with them.  Record
again only for a change of behaviour that is intended and stated in the
CHANGELOG.
"""

from __future__ import annotations

CF = ["--friction", "coulomb", "--fd", "0.02", "--fs", "0.04"]
ST = ["--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.05"]

#: simulate --json: laws x solvers x stick rules, stick-slip, sliding, Case I/II of the paper
SIMULATE = {
    "karnopp_exact_case1": ["--fd", "0.02", "--vb", "0.01", "--zeta", "0", "--t-end", "300"],
    "karnopp_exact_case1_spring": ["--fd", "0.02", "--vb", "0.01", "--zeta", "0", "--stick-force", "spring", "--t-end", "300"],
    "karnopp_exact_case2": ["--fd", "0.02", "--vb", "0.01", "--zeta", "0.01", "--t-end", "300"],
    "karnopp_exact_case2_spring": ["--fd", "0.02", "--vb", "0.01", "--zeta", "0.01", "--stick-force", "spring", "--t-end", "300"],
    "karnopp_exact_fs": ["--fd", "0.02", "--fs", "0.04", "--vb", "0.01", "--zeta", "0.05", "--t-end", "300"],
    "karnopp_exact_fs_spring": ["--fd", "0.02", "--fs", "0.04", "--vb", "0.1", "--zeta", "0.02", "--stick-force", "spring", "--t-end", "300"],
    "karnopp_exact_vd": ["--fd", "0.03", "--fs", "0.05", "--vd", "0.005", "--vb", "0.02", "--zeta", "0.03", "--t-end", "300"],
    "karnopp_rk4_case1": ["--fd", "0.02", "--vb", "0.01", "--zeta", "0", "--solver", "rk4", "--t-end", "200", "--stick-force", "spring"],
    "karnopp_rk4_case2": ["--fd", "0.02", "--vb", "0.01", "--zeta", "0.01", "--solver", "rk4", "--t-end", "200"],
    "karnopp_rk4_fs": ["--fd", "0.02", "--fs", "0.04", "--vb", "0.01", "--zeta", "0.05", "--solver", "rk4", "--t-end", "200"],
    "karnopp_rk4_window": ["--fd", "0.02", "--vb", "0.1", "--zeta", "0.0", "--solver", "rk4", "--t-end", "100", "--window", "50:90"],
    "coulomb_exact": [*CF, "--vb", "0.01", "--zeta", "0.05", "--t-end", "300"],
    "coulomb_exact_spring": [*CF, "--vb", "0.01", "--zeta", "0.05", "--stick-force", "spring", "--t-end", "300"],
    "coulomb_exact_undamped": [*CF, "--vb", "0.05", "--zeta", "0", "--t-end", "300"],
    "coulomb_exact_sliding": ["--friction", "coulomb", "--fd", "0.02", "--vb", "0.01", "--zeta", "0.05", "--t-end", "300"],
    "coulomb_exact_x0v0": [*CF, "--vb", "0.02", "--zeta", "0.02", "--x0", "0.1", "--v0", "-0.05", "--t-end", "300"],
    "coulomb_exact_negative_vb": [*CF, "--vb", "-0.02", "--zeta", "0.02", "--t-end", "300"],
    "coulomb_adaptive": [*CF, "--vb", "0.01", "--zeta", "0.05", "--solver", "adaptive", "--t-end", "300"],
    "coulomb_adaptive_spring": [*CF, "--vb", "0.01", "--zeta", "0.05", "--solver", "adaptive", "--stick-force", "spring", "--t-end", "300"],
    "coulomb_rk4": [*CF, "--vb", "0.01", "--zeta", "0.05", "--solver", "rk4", "--t-end", "200"],
    "coulomb_exact_dense": [*CF, "--vb", "0.01", "--zeta", "0.05", "--dense-dt", "0.05", "--t-end", "100"],
    "stribeck_adaptive": [*ST, "--vb", "0.02", "--zeta", "0.05", "--t-end", "300"],
    "stribeck_adaptive_default_fs": ["--friction", "stribeck", "--fd", "0.02", "--vb", "0.01", "--zeta", "0.05", "--t-end", "300"],
    "stribeck_adaptive_delta1": [*ST, "--delta", "1", "--vb", "0.03", "--zeta", "0.02", "--t-end", "300"],
    "stribeck_adaptive_viscous": [*ST, "--viscous", "0.05", "--vb", "0.02", "--zeta", "0.05", "--t-end", "300"],
    "stribeck_adaptive_sliding": [*ST, "--vb", "0.3", "--zeta", "0.05", "--t-end", "300"],
    "stribeck_adaptive_spring": [*ST, "--vb", "0.02", "--zeta", "0.05", "--stick-force", "spring", "--t-end", "300"],
    "stribeck_rk4": [*ST, "--vb", "0.02", "--zeta", "0.05", "--solver", "rk4", "--t-end", "200"],
    "stribeck_adaptive_rtol": [*ST, "--vb", "0.02", "--zeta", "0.05", "--ode-rtol", "1e-8", "--t-end", "300"],
    "dimensional": ["--dimensional", "m=1,c=0.08,k=4,v_b=0.02,f_d=0.08", "--t-end", "300"],
    "issue11_stribeck": ["--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.05", "--delta", "1",
                          "--vb", "0.12", "--zeta", "0.05", "--t-end", "600"],
}

#: orbit / continue --json
ORBIT = {
    "orbit_coulomb": ["orbit", *CF, "--vb", "0.01", "--zeta", "0", "--t-end", "50"],
    "orbit_coulomb_damped": ["orbit", *CF, "--vb", "0.01", "--zeta", "0.05", "--t-end", "300"],
    "orbit_karnopp": ["orbit", "--fd", "0.02", "--fs", "0.04", "--vb", "0.01", "--zeta", "0.05", "--t-end", "300"],
    "orbit_stribeck_unstable": ["orbit", "--friction", "stribeck", "--zeta", "0.3", "--vb", "0.016",
                                "--x0", "0.031", "--v0", "0", "--guess"],
    "continue_stribeck_vb": ["continue", "--param", "vb", "--from", "0.005", "--to", "0.025", "--friction", "stribeck",
                             "--delta", "1", "--viscous", "0.05", "--zeta", "0.1", "--points", "21", "--seeds", "hopf",
                             "--sweep", "3", "--t-end", "200"],
}

#: a small sweep (one per solver), stored as the arrays of its dataset
SWEEPS = {
    "sweep_exact": {"friction": "coulomb", "fs": 0.04, "t_end": 300.0,
                    "grid": {"zeta": [0.0, 0.02, 0.05], "vb": [0.005, 0.01, 0.05, 0.2]}},
    "sweep_adaptive": {"friction": "stribeck", "fs": 0.04, "vs": 0.05, "t_end": 300.0,
                       "grid": {"zeta": [0.02, 0.05], "vb": [0.01, 0.02, 0.3]}},
    "sweep_rk4": {"friction": "karnopp", "solver": "rk4", "t_end": 200.0,
                  "grid": {"zeta": [0.0, 0.01], "fd": [0.02, 0.04]}},
}
