"""Every registered law through every solver it supports, every sweep axis it has, and the CLI.

Nothing here lists the laws: a new law is covered by registering it.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.cli import main
from frictionflow.friction import law_class, law_classes, law_names
from frictionflow.parameters import declared
from frictionflow.solvers.registry import solver_classes
from frictionflow.sweep.compute import compute_chunk
from frictionflow.sweep.config import parse_sweep

LAWS = law_names()
MODEL = BeltOscillator(zeta=0.05, vb=0.02)


def _law(name):
    return law_class(name)()


@pytest.mark.parametrize("name", LAWS)
def test_every_supported_solver_runs_the_law_with_a_closed_energy_balance(name):
    law = _law(name)
    solvers = [cls() for cls in solver_classes() if cls().supports(law)]
    assert solvers, f"no solver runs friction={name}"
    for solver in solvers:
        res = analyze(simulate(MODEL, law, solver, t_end=60.0))
        assert np.isfinite(res.energy_residual) and abs(res.energy_residual) < 1e-2, (name, solver.name)
        assert res.trajectory.friction == law


@pytest.mark.parametrize("name", LAWS)
def test_laws_declare_their_parameters_and_kernel_slots(name):
    cls = law_class(name)
    law = cls()
    names = [p.name for p in cls.parameters]
    assert len(names) == len(set(names)) and ("fs" in names or cls.internal_names)  # Dahl has no static peak
    assert ("stick_force" in names) != bool(cls.internal_names)  # a law with internal states holds by them
    assert all(p.owner == "law" for p in cls.parameters)
    assert set(cls.kernel_slots) <= set(names)
    assert law.kernel_params()[0] == cls.code
    assert sum(c.code == cls.code for c in law_classes() if c.configurable) == 1  # one compiled force per code
    # the law rebuilds from its own values
    assert cls.from_values(law.values()) == law


def _axis_values(p, law):
    v = getattr(law, p.name, None)
    if p.name == "x0":  # held just below kinetic friction: a start every law resolves (rate-and-state: V_r
        return [0.9 * law.fd, 0.95 * law.fd]  # far below it is out of the belt frame's reach, docs/guide/friction.md)
    if v is None:  # an oscillator or initial-state parameter
        v = {"zeta": 0.05, "vb": 0.02, "x0": 0.03, "v0": 0.0, "fex": 0.01, "omega": 1.0, "phi": 0.3,
             "vb_amplitude": 0.005, "vb_omega": 0.8, "vb_phi": 0.3}[p.name]
    return [float(v), float(v) * 1.1 + (1e-3 if v == 0 else 0.0)]


@pytest.mark.parametrize("name", LAWS)
def test_every_sweep_axis_of_the_law_changes_the_kernel_rows_and_computes(name):
    law = _law(name)
    axes = [p for p in declared().values() if p.sweepable and (p.owner != "law" or p in law.parameters)]
    for p in axes:
        values = _axis_values(p, law)
        if p.name == "fs" and hasattr(law, "fd") and "fd" in law.values():
            values = [law.fs, law.fs * 1.5]
        spec = {"friction": name, "t_end": 40.0, "solver": "rk4" if law.stick_rule == "band" else "auto",
                "grid": {p.name: values}}
        if p.name in ("fex", "omega", "phi", "vb_amplitude"):  # driven: damped, so that no point is the undamped resonance
            spec["zeta"] = 0.05
        cfg = parse_sweep(spec)
        out = compute_chunk(cfg.source, (0,), (2,))
        assert out.shape[1] == 2 and np.isfinite(out[2:5]).all(), (name, p.name)


@pytest.mark.parametrize("name", LAWS)
def test_cli_takes_every_parameter_of_the_law_by_its_declared_option(name, capsys):
    law = _law(name)
    args = ["simulate", "--friction", name, "--t-end", "30", "--json"]
    for p in law.parameters:
        value = getattr(law, p.name)
        args += [p.flag, str(value)]
    assert main(args) == 0, capsys.readouterr().err
    d = json.loads(capsys.readouterr().out)
    for p in law.parameters:
        if p.report:
            assert d["params"][p.name] == getattr(law, p.name)


def test_a_parameter_of_another_law_is_refused_by_name(capsys):
    assert main(["simulate", "--friction", "karnopp", "--vs", "0.02"]) == 2
    err = capsys.readouterr().err
    assert "vs is not a parameter of friction=karnopp" in err


def test_unknown_law_lists_the_registered_ones(capsys):
    assert main(["simulate", "--friction", "nope"]) == 2
    err = capsys.readouterr().err
    assert all(n in err for n in LAWS)
