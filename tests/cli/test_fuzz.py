"""Property-based fuzz of every command and of configs: valid and invalid values and types.

Whatever is given, a command exits 0, or 2 with one line ``error: ...`` that
names what was wrong -- never a traceback -- and a failing command leaves no
file behind.  Runs in-process with the kernels warm; valid draws are kept in
cheap ranges (short runs) so that the whole file runs in well under a minute.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from frictionflow.cli import main
from frictionflow.parameters import declared

PARAMS = declared()
#: valid values drawn from ranges that keep a run short
CHEAP = {"t_end": (1.0, 30.0), "dt": (2e-3, 0.05), "dense_dt": (0.05, 1.0), "max_steps": (10**5, 10**7),
         "record_every": (1, 50), "ode_rtol": (1e-10, 1e-6), "x0": (-0.1, 0.1), "v0": (-0.1, 0.1),
         "zeta": (0.0, 0.5), "vb": (-0.2, 0.2), "fd": (0.0, 0.05), "fs": (0.0, 0.1), "vd": (1e-4, 1e-2),
         "vs": (1e-3, 0.1), "delta": (0.5, 3.0), "viscous": (0.0, 0.1), "k1": (0.0, 0.3), "k3": (5.0, 50.0),
         "rk4_band": (1e-5, 1e-3), "rtol": (1e-10, 1e-4), "max_memory": (0.5, 4.0)}
JUNK = st.sampled_from(["abc", "", "true", "1e", "--", "nan", "inf", "-inf", "1e999", "0x10", " "])


def _valid(name: str) -> st.SearchStrategy:
    p = PARAMS[name]
    if p.kind == "choice":
        return st.sampled_from(p.choices)
    lo, hi = CHEAP.get(name, (p.lower or -1.0, p.upper or 1.0))
    if p.kind == "int":
        return st.integers(int(lo), int(hi)).map(str)
    return st.floats(lo, hi).map(repr)


def _invalid(name: str) -> st.SearchStrategy:
    p = PARAMS[name]
    outside = []
    if p.lower is not None:
        outside.append(st.floats(-1e300, p.lower, exclude_max=not p.lower_open))
    if p.upper is not None:
        outside.append(st.floats(p.upper, 1e300, exclude_min=not p.upper_open))
    if p.kind == "int":
        outside.append(st.floats(0.1, 0.9))
    return st.one_of(JUNK, *(s.map(repr) for s in outside))


def _options(names: list[str]) -> st.SearchStrategy:
    """A few options, each valid or not."""
    return st.lists(st.sampled_from(names), min_size=1, max_size=4, unique=True).flatmap(
        lambda chosen: st.tuples(*(st.tuples(st.just(n), st.one_of(_valid(n), _invalid(n))) for n in chosen)))


def _check(code: int, err: str, given_names: list[str], out_dir: Path, before: set[str]) -> None:
    assert code in (0, 2), err
    assert "Traceback" not in err
    if code == 2:
        lines = [ln for ln in err.splitlines() if ln.startswith("error:")]
        assert len(lines) == 1, err
        named = [n for n in given_names if n in lines[0] or "--" + n.replace("_", "-") in lines[0]]
        assert named or "friction=" in lines[0] or "solver=" in lines[0], err
        assert set(os.listdir(out_dir)) == before, "a failing command left a file behind"


SIMULATE = [n for n in PARAMS if n not in ("dimensional", "window")]
FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))


@FUZZ
@given(opts=_options(SIMULATE), out=st.sampled_from([None, "t.csv", "t.nc", "t.txt"]))
def test_simulate(opts, out, tmp_path_factory, capsys):
    d = tmp_path_factory.mktemp("sim")
    argv = ["simulate", "--t-end", "20", "--json"]
    for name, value in opts:
        argv += [PARAMS[name].flag, value]
    if out:
        argv += ["--out", str(d / out)]
    code = main(argv)
    _check(code, capsys.readouterr().err, [n for n, _ in opts] + ["out"], d, set())


MODEL = [n for n, p in PARAMS.items() if p.owner in ("oscillator", "law") or n in ("x0", "v0", "friction")]


@FUZZ
@given(opts=_options(MODEL))
def test_orbit(opts, tmp_path_factory, capsys):
    d = tmp_path_factory.mktemp("orb")
    argv = ["orbit", "--t-end", "30", "--json"]
    for name, value in opts:
        argv += [PARAMS[name].flag, value]
    code = main(argv)
    err = capsys.readouterr().err
    if code == 1:  # no periodic orbit where these parameters lead: a result, said in one line
        assert err.startswith("error:") and "Traceback" not in err
        return
    _check(code, err, [n for n, _ in opts], d, set())


def _toml_value(value: str) -> str:
    """The option's text as a TOML value of a random-ish type (numbers stay numbers, junk becomes a string)."""
    try:
        x = float(value)
    except ValueError:
        return '"' + value.replace('"', "") + '"'
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


@FUZZ
@given(opts=_options(SIMULATE), boolean=st.sampled_from([None, *SIMULATE]))
def test_simulate_config(opts, boolean, tmp_path_factory, capsys):
    d = tmp_path_factory.mktemp("cfg")
    lines = ["t_end = 20.0"] + [f"{n} = {_toml_value(v)}" for n, v in opts if n != "t_end"]
    names = [n for n, _ in opts]
    if boolean and boolean not in names:
        lines.append(f"{boolean} = true")  # a TOML boolean is never a number
        names.append(boolean)
    cfg = d / "run.toml"
    cfg.write_text("\n".join(lines) + "\n")
    code = main(["simulate", "--config", str(cfg), "--json"])
    _check(code, capsys.readouterr().err, names + ["config"], d, {"run.toml"})


AXES = [n for n, p in PARAMS.items() if p.sweepable]


@FUZZ
@given(axis=st.sampled_from(AXES), values=st.lists(st.one_of(_valid("zeta"), JUNK), min_size=1, max_size=3),
       num=st.one_of(st.integers(-2, 4), st.just(1e9), st.just('"3"'), st.just("true")))
def test_sweep_config(axis, values, num, tmp_path_factory, capsys):
    d = tmp_path_factory.mktemp("swp")
    items = ", ".join(_toml_value(v) for v in values)
    text = f't_end = 10.0\nfriction = "coulomb"\nfs = 0.1\n[grid]\n{axis} = [{items}]\n'
    text += f"zeta = {{ start = 0.0, stop = 0.1, num = {num} }}\n" if axis != "zeta" else ""
    cfg = d / "s.toml"
    cfg.write_text(text)
    code = main(["sweep", str(cfg), "--out", str(d / "r.zarr")])
    err = capsys.readouterr().err
    assert code in (0, 2), err
    assert "Traceback" not in err
    if code == 2:
        assert err.startswith("error:") and not (d / "r.zarr").exists(), err


@pytest.mark.parametrize("argv, named", [
    (["simulate", "--x0", "1e300"], "x0"),
    (["simulate", "--x0", "1.8e308", "--friction", "coulomb"], "x0"),
    (["simulate", "--t-end", "1e9"], "t_end"),
    (["simulate", "--t-end", "1e300"], "t_end"),
    (["simulate", "--dense-dt", "1e-300"], "dense_dt"),
    (["simulate", "--solver", "rk4", "--dt", "1e-300"], "dt"),
    (["simulate", "--solver", "rk4", "--dt", "1.8e308"], "dt"),
    (["simulate", "--t-end", "1e8", "--friction", "coulomb", "--fs", "0.04", "--zeta", "0.05"], "t_end"),
    (["simulate", "--friction", "coulomb", "--vd", "-inf"], "vd"),
    (["simulate", "--ode-rtol", "-inf"], "ode_rtol"),
    (["simulate", "--ode-rtol", "-1"], "ode_rtol"),
    (["simulate", "--friction", "stribeck", "--viscous", "inf"], "viscous"),
    (["simulate", "--friction", "stribeck", "--vs", "0"], "vs"),
    (["simulate", "--friction", "stribeck", "--delta", "-0"], "delta"),
    (["orbit", "--vd", "inf"], "vd"),
    (["orbit", "--tol", "inf"], "tol"),
    (["orbit", "--zeta", "1e300"], "zeta"),
    (["continue", "--param", "vb", "--from", "0.01", "--to", "0.02", "--points", "100000000"], "points"),
])
def test_the_issue_examples_are_refused_naming_the_parameter(argv, named, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and named in err and err.count("\n") == 1, err
