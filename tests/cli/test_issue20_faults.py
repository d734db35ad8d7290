"""Issue 20, "Why": each hostile command of the list, now a one-line error with exit code 2 (bad input, as the
README documents) or the right output -- run as typed, in its own process where the fault was in the exit.
"""

from __future__ import annotations

import json

import pytest

from frictionflow import Adaptive, BeltOscillator, Coulomb, Exact, analyze, simulate
from frictionflow.analysis import response as response_module
from frictionflow.analysis.lyapunov import lyapunov_exponents
from frictionflow.cli import main
from frictionflow.orbits.forced import continue_forced
from frictionflow.parameters import declared
from frictionflow.params import BeltOscillator
from frictionflow.friction import law_class
from frictionflow.solvers.exact import resonance_problem
from frictionflow.solvers.rk4 import RK4, step_count
from frictionflow.sweep import run_sweep
from tests.cli.processes import cli, one_line

SWEEP_TOML = "t_end = 50\n\n[grid]\nzeta = [0.0, 0.04]\n"




# -- tracebacks ------------------------------------------------------------------------------------

def test_response_with_a_subnormal_zeta_is_refused():
    code, out, err, _ = cli("response", "--omega", "0.5:1.5:3", "--fex", "0.01", "--zeta", "5e-324", "--periods", "20",
                            "--json")
    assert code == 2 and out == ""
    one_line(err, "zeta must be finite and in [0, 1000], got 5e-324", "subnormal")


@pytest.mark.parametrize("zeta", ["1e-300", "1e-160"])
def test_response_through_a_resonance_too_nearly_undamped_is_refused_before_any_run(zeta, capsys, monkeypatch):
    # normal zetas whose |1 - Omega^2 + 2i zeta Omega|^2 underflows at Omega = 1: the closed form divided by 0
    def tripwire(*args, **kwargs):
        raise AssertionError("ran before refusing the frequency it cannot force at")

    monkeypatch.setattr(response_module, "simulate", tripwire)
    code = main(["response", "--omega", "0.5:1.5:3", "--fex", "0.01", "--zeta", zeta, "--periods", "20", "--json"])
    assert code == 2
    one_line(capsys.readouterr().err, "resonance too nearly undamped", f"zeta={float(zeta):g}", "omega=1")


def test_response_with_a_subnormal_dense_dt_is_refused():
    code, out, err, _ = cli("response", "--omega", "0.5:1.5:3", "--fex", "0.01", "--zeta", "0.05", "--periods", "20",
                            "--dense-dt", "5e-324", "--json")
    assert code == 2 and out == ""
    one_line(err, "dense_dt must be finite and in [1e-09, 1000], got 5e-324")


def test_a_malformed_scheduler_address_is_one_line_at_once(tmp_path):
    pytest.importorskip("distributed")
    (tmp_path / "s.toml").write_text(SWEEP_TOML)
    code, out, err, seconds = cli("sweep", "s.toml", "--out", "r.zarr", "--scheduler", "notanaddress", cwd=tmp_path)
    assert code == 2 and out == ""
    one_line(err, "scheduler: bad address 'notanaddress'")  # no "Exception ignored in: Client.__del__" after it
    assert seconds < 9, seconds  # no 10 s wait for a half-made client to close
    assert not (tmp_path / "r.zarr").exists() and not list(tmp_path.glob("*.lock"))


@pytest.mark.parametrize("address, says", [
    ("tcp://host", "missing port number"),
    ("foo://host:1", "unknown address scheme 'foo'"),
    ("tcp://127.0.0.1:99999", "port 99999 is not in 1..65535"),
])
def test_other_malformed_addresses_are_bad_input(address, says, tmp_path, capsys):
    pytest.importorskip("distributed")
    config = tmp_path / "s.toml"
    config.write_text(SWEEP_TOML)
    assert main(["sweep", str(config), "--out", str(tmp_path / "r.zarr"), "--scheduler", address]) == 2
    one_line(capsys.readouterr().err, f"scheduler: bad address {address!r}", says)


def test_a_lyapunov_run_too_long_for_memory_is_refused_before_any_work():
    code, out, err, seconds = cli("lyapunov", "--t-end", "1e12", "--t-transient", "20", "--steps", "64", "--json")
    assert code == 2 and out == ""  # was: numpy's MemoryError traceback after trying to allocate 3.47 TiB
    one_line(err, "1.59e+11 blocks", "RK4 steps", "GiB", "max_memory=4 GiB", "shorten t_end or raise max_memory")
    # the same limit through the API, and a run within it still runs
    model, law = BeltOscillator(0.05, 0.2, fex=0.1, omega=0.8), Coulomb(0.3, 0.5)
    blocks = 8 * 2**30 / 40  # 8 GiB of 40-byte block records
    with pytest.raises(ValueError, match="max_memory=1 GiB"):
        lyapunov_exponents(model, law, t_transient=0.0, t_end=blocks * model.forcing_period, max_memory=1.0)
    assert lyapunov_exponents(model, law, t_transient=0.0, t_end=20 * model.forcing_period, steps_per_block=16,
                              max_memory=1e-3).exponents is not None


# -- the wrong output ------------------------------------------------------------------------------

def test_a_subnormal_end_time_is_refused_not_called_an_equilibrium():
    code, out, err, _ = cli("simulate", "--t-end", "5e-324", "--json")
    assert code == 2 and out == ""  # was: kind equilibrium, V_min = V_max = 0 although X'(0) = V_b = 0.01
    one_line(err, "t_end must be finite and in (0, 1e+12], got 5e-324", "subnormal", "degenerate")


@pytest.mark.parametrize("solver", [Exact(), Adaptive(), RK4(dt=1e-9)], ids=["exact", "adaptive", "rk4"])
def test_a_run_too_short_to_move_is_not_an_equilibrium(solver):
    """A mass carried at V_b for 1e-8 has not settled anywhere (it was called an equilibrium: X and X' barely
    spread over so short a tail, but X' is V_b, not 0)."""
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), solver, t_end=1e-8)
    assert analyze(traj).steady_state.kind == "not_settled"


@pytest.mark.parametrize("argv", [("--fex", "0.01", "--omega", "1e-3"), ("--friction", "stribeck", "--fex", "1.0", "--t-end", "1.0")])
def test_a_forced_run_shorter_than_its_section_needs_is_not_settled_over_the_whole_run(argv):
    """Fewer than two forcing periods leave no stroboscopic section to judge (it was: "window must satisfy ...")."""
    code, out, err, _ = cli("simulate", *argv, "--json")
    assert code == 0, err
    ss = json.loads(out)["steady_state"]
    assert ss["kind"] == "not_settled" and ss["window"][0] == 0.0 and ss["window"][1] > 0.0


# -- smaller ---------------------------------------------------------------------------------------

def test_forced_continue_checks_the_end_of_the_range_as_its_start(capsys):
    code = main(["forced-continue", "--fex", "0.01", "--from", "0.8", "--to", "1e300", "--json"])
    assert code == 2
    one_line(capsys.readouterr().err, "--vary TO: omega must be finite and in (0, 1000], got 1e+300")
    assert main(["forced-continue", "--parameter", "fex", "--from", "1e300", "--to", "0.02", "--json"]) == 2
    one_line(capsys.readouterr().err, "--vary FROM: fex must be finite and in [0, 1000], got 1e+300")


def test_continue_forced_checks_both_ends_by_the_declaration():
    model, law = BeltOscillator(fex=0.01, omega=0.8), law_class("coulomb")(0.02)
    with pytest.raises(ValueError, match=r"^stop: omega must be finite and in \(0, 1000\], got 1e\+300$"):
        continue_forced(model, law, "omega", 0.8, 1e300)
    with pytest.raises(ValueError, match=r"^start: fex must be > 0"):
        continue_forced(model, law, "fex", 0.0, 0.02)


def test_a_config_value_of_the_wrong_type_is_refused_even_when_the_option_overrides_it(tmp_path, capsys):
    config = tmp_path / "bad.toml"
    config.write_text('t_end = "abc"\n')
    assert main(["simulate", "--config", str(config), "--t-end", "10", "--json"]) == 2
    one_line(capsys.readouterr().err, f"{config}: t_end must be finite and in (0, 1e+12], got 'abc'")


def test_a_chunk_size_beyond_the_declared_range_is_refused(tmp_path):
    (tmp_path / "s.toml").write_text(SWEEP_TOML)
    code, out, err, _ = cli("sweep", "s.toml", "--out", "r.zarr", "--chunk-size", "99999999999999999999", cwd=tmp_path)
    assert code == 2 and out == ""
    one_line(err, "--chunk-size must be an integer and in [1, 1e+07], got 99999999999999999999")
    assert not (tmp_path / "r.zarr").exists()
    with pytest.raises(ValueError, match=r"^chunk_size must be an integer and in \[1, 1e\+07\], got 0$"):
        run_sweep(str(tmp_path / "s.toml"), tmp_path / "r.zarr", chunk_size=0)


def test_an_empty_output_path_is_called_empty_not_dot(capsys):
    assert main(["simulate", "--out", ""]) == 2
    line = one_line(capsys.readouterr().err, "'--out'", "an empty path")
    assert "'.'" not in line


def test_rk4_ends_at_t_end_when_it_is_a_whole_number_of_steps_but_for_rounding(capsys):
    # t_end = 1000 forcing periods: t_end / dt = 16846000.000000004, counted 16846001 steps (one past t_end)
    model = BeltOscillator(zeta=0.05, fex=0.01, omega=0.373)
    t_end = 1000 * model.forcing_period
    dt, per = RK4().aligned_step(model)
    assert t_end / dt != 1000 * per and step_count(t_end, dt) == 1000 * per
    assert step_count(1.0, 0.3) == 4 and step_count(0.3, 0.1) == 3  # a fraction of a step still takes one
    code = main(["simulate", "--solver", "rk4", "--fex", "0.01", "--omega", "0.373", "--zeta", "0.05",
                 "--t-end", repr(t_end), "--json"])
    assert code == 0
    report = json.loads(capsys.readouterr().out)
    assert report["solver"]["steps"] == 1000 * per
    assert report["steady_state"]["window"][1] <= t_end * (1 + 1e-12)


@pytest.mark.parametrize("argv", [["simulate", "--omega", "5e-324", "--json"],
                                  ["simulate", "--omega", "5e-324", "--fex", "0.01", "--json"]])
def test_a_subnormal_forcing_frequency_is_refused_not_a_section_at_nan(argv):
    code, out, err, _ = cli(*argv)
    assert code == 2 and out == ""
    line = one_line(err, "omega must be finite and in (0, 1000], got 5e-324", "subnormal")
    assert "nan" not in line


# -- the declarations behind them --------------------------------------------------------------------

def test_every_real_parameter_but_the_state_refuses_a_subnormal_value():
    for name, p in declared().items():
        if p.kind != "real" or (p.lower is not None and p.lower > 0.0):
            continue  # (a range from above 0 refuses it anyway)
        if p.subnormal_ok:
            assert name in ("x0", "v0") and p.check(5e-324) == 5e-324, name
            continue
        with pytest.raises(ValueError, match="subnormal"):
            p.check(5e-324)
        assert p.check(1e-300) == 1e-300, name  # small but normal: a value


def test_the_resonance_check_refuses_only_what_the_closed_form_cannot_compute():
    assert resonance_problem(1e-150, 1.0, 0.01) is None  # |2i zeta|^2 = 4e-300: normal, the run is as before
    assert resonance_problem(1e-300, 1.0, 0.0) is None  # unforced: nothing to resonate
    assert "too nearly undamped" in resonance_problem(1e-160, 1.0, 0.01)
    assert resonance_problem(0.0, 1.0, 0.01).startswith("solver=exact: undamped resonance (zeta=0, omega=1")
