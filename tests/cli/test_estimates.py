"""Issue 20, item 1: an estimate before any work; work above the limits refused in one line naming the estimate and
``--no-limit``; ordinary work (the README's commands) not refused.

The refusals run as typed, each in its own process, and must come back within a few seconds (an unbounded run
would take hours to days).  The README's commands are checked in-process up to the comparison only: the
comparison's verdict is recorded and the command stopped there, before any of its work.
"""

from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np
import pytest

from frictionflow import estimate
from frictionflow.cli import main
from frictionflow.sweep import VARIABLES
from frictionflow.cli.forced_orbit import ForcedContinueOptions
from frictionflow.cli.forced_orbit import _job as forced_job
from frictionflow.orbits.forced import stroboscopic_estimate
from frictionflow.params import BeltOscillator
from tests.cli.processes import cli, one_line
from frictionflow.cli import options as cli_options
from frictionflow.core import flowmap
from frictionflow.friction import Coulomb, Stribeck
from frictionflow.orbits import continuation, shooting
from frictionflow.orbits.continuation import continuation_estimate
from frictionflow.orbits.settings import ContinuationSettings
from frictionflow.orbits.flow_compiled import CompiledFlow
from frictionflow.orbits.flow_exact import ExactFlow
from frictionflow.orbits.shooting import shooting_estimate
from frictionflow.solvers.registry import auto_solver
from frictionflow.analysis.response import response_bytes
from tests.test_atomic_output import full_dir  # noqa: F401  (fixture: a directory on a 64 KiB tmpfs)

#: seconds a refusal may take, start-up and imports included (it does no work; a run it refuses takes hours)
QUICK = 20.0
BIG_GRID = 't_end = 50\n\n[grid]\nzeta = {start = 0.0, stop = 0.1, num = 100000}\nvb = {start = 0.01, stop = 0.1, num = 100000}\n'



def refused(argv: tuple[str, ...], *words: str, cwd: Path | None = None) -> str:
    """Run ``argv``: exit 2 at once, nothing on stdout, one ``error: ...`` line with the estimate and ``words``."""
    code, out, err, seconds = cli(*argv, cwd=cwd)
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 1, err
    assert lines[0].startswith("error: ") and "estimated " in lines[0] and all(w in lines[0] for w in words), err
    assert seconds < QUICK, seconds
    return lines[0]


# -- the hostile commands of the issue -------------------------------------------------------------

def test_a_sweep_of_1e10_points_is_refused_for_its_store_and_time(tmp_path):
    (tmp_path / "big.toml").write_text(BIG_GRID)
    line = refused(("sweep", "big.toml", "--out", "big.zarr"), "1e+10 points", "days", "TiB", "free",
                   "--no-limit", cwd=tmp_path)
    size = 1e10 * 8 * len(VARIABLES) / 2**40  # 8 bytes a variable a point (17 variables: 1.24 TiB)
    assert line.startswith(f"error: --out: 'big.zarr' would need about {size:.3g} TiB but its disk has ")
    assert not (tmp_path / "big.zarr").exists() and not list(tmp_path.glob("*.lock"))


def test_a_basins_grid_of_1e10_points_is_refused(tmp_path):
    refused(("basins", "--x0=-0.28:0.32:100000", "--v0=-0.3:0.3:100000", "--json"), "1e+10 points", "in memory",
            "--no-limit", cwd=tmp_path)
    assert not list(tmp_path.iterdir())


def test_basins_with_a_nanosecond_rk4_step_is_refused(tmp_path):
    line = refused(("basins", "--x0=-0.28:0.32:3", "--v0=-0.3:0.3:3", "--friction", "karnopp", "--solver", "rk4",
                    "--dt", "1e-9", "--t-end", "50", "--json"), "9 points of 5e+10 RK4 steps", "above the limit of 1 h",
                   "--no-limit", cwd=tmp_path)
    assert " h " in line or "days" in line


def test_a_forced_orbit_at_a_nanoscale_frequency_is_refused():
    # a transient of 10 forcing periods is 6.3e10 time units: its switches, not its 5120 grid steps, cost days
    refused(("forced-orbit", "--omega", "1e-9", "--fex", "0.1", "--transient", "10", "--json"), "switches", "days",
            "--no-limit")


def test_a_map_with_a_stribeck_curve_below_the_normal_floats_is_refused():
    # V_s^2 underflows: each grazing-margin flow runs to its step cap (2.7 s measured), 41 x 201 of them
    refused(("map", "--x", "vb", "--x-from", "0.1", "--x-to", "0.5", "--y", "zeta", "--y-from", "0.01", "--y-to", "0.1",
             "--friction", "stribeck", "--vs", "1e-300", "--json"), "orbit flows", " h", "--no-limit")


def test_a_lyapunov_run_of_1e12_time_units_is_refused_by_memory_then_by_time(tmp_path):
    code, out, err, seconds = cli("lyapunov", "--t-end", "1e12", "--t-transient", "20", "--steps", "64", "--json")
    assert code == 2 and out == "" and seconds < QUICK
    assert err.count("\n") == 1 and "1.02e+13 RK4 steps" in err and "raise max_memory" in err, err
    # memory lifted by the config: the time limit still holds, and says how to lift it
    (tmp_path / "mem.toml").write_text("max_memory = 1e6\n")
    refused(("lyapunov", "--t-end", "1e12", "--t-transient", "20", "--steps", "64", "--json", "--config",
             str(tmp_path / "mem.toml")), "1.02e+13 RK4 steps", "days", "--no-limit")


def test_lyapunov_at_zeta_1000_ends_at_once():
    """Not a cost: 6000 time units are 5e5 tangent steps; RK4's default step is unstable there, refused at once."""
    code, out, err, seconds = cli("lyapunov", "--zeta", "1000", "--json")
    assert seconds < QUICK and out == "" and code in (1, 2)
    assert len(err.strip().splitlines()) == 1 and err.startswith("error: "), err


def test_reproducing_the_paper_with_a_microsecond_step_is_refused(tmp_path):
    refused(("reproduce", "--out", str(tmp_path / "out"), "--dt", "1e-6", "--t-end", "1e5"), "RK4 steps", "days",
            "--no-limit")
    assert not (tmp_path / "out").exists()


def test_simulate_rk4_above_the_limit_is_refused_and_no_limit_lifts_only_the_estimate():
    refused(("simulate", "--solver", "rk4", "--dt", "1e-9", "--t-end", "1e4", "--json"), "1e+13 rk4 steps", "days",
            "--no-limit")
    code, _, err, _ = cli("simulate", "--solver", "rk4", "--dt", "1e-9", "--t-end", "1e4", "--json", "--no-limit")
    assert code == 2 and "more than 1e+11" in err  # the solver's own cap still holds


def test_an_output_larger_than_its_disk_is_refused_before_any_work(tmp_path, full_dir, capsys):
    """A sweep store of megabytes on a 64 KiB disk: refused by its estimate, nothing computed or written."""
    (tmp_path / "s.toml").write_text("t_end = 50\n\n[grid]\nzeta = {start = 0.0, stop = 0.1, num = 50000}\n")
    out = full_dir / "r.zarr"
    assert main(["sweep", str(tmp_path / "s.toml"), "--out", str(out)]) == 2
    line = capsys.readouterr().err.strip()
    assert line.startswith(f"error: --out: {str(out)!r} would need about ") and "\n" not in line
    assert " MiB but its disk has " in line and " KiB free" in line
    assert "no space left on device (estimated 5e+04 points" in line and line.endswith("--no-limit")
    assert list(full_dir.iterdir()) == []


def test_a_response_file_larger_than_its_disk_is_refused_before_any_run(full_dir, capsys):
    out = full_dir / "r.nc"
    argv = ["response", "--vary", "omega=0.5:1.5:40", "--fex", "0.01", "--zeta", "0.05", "--periods", "20"]
    assert main([*argv, "--out", str(out)]) == 2
    line = capsys.readouterr().err.strip()
    assert line.startswith(f"error: --out: {str(out)!r} would need about ") and "\n" not in line
    assert "no space left on device (estimated 80 runs of 20 forcing periods" in line and line.endswith("--no-limit")
    assert list(full_dir.iterdir()) == []


@pytest.mark.parametrize("n", [3, 40])
def test_the_response_file_estimate_bounds_the_file(tmp_path, n):
    """The estimate is an upper bound of the file written, and not a loose one (within 4x once the data dominate)."""
    out = tmp_path / "r.nc"
    assert main(["response", "--vary", f"omega=0.5:1.5:{n}", "--fex", "0.01", "--zeta", "0.05", "--periods", "8",
                 "--out", str(out), "--json"]) == 0
    size, estimate = out.stat().st_size, response_bytes(2, n)
    assert size <= estimate <= 4 * max(size, 32 * 2**10), (size, estimate)


def test_a_forced_branch_is_estimated_whole_before_its_first_orbit():
    """The first orbit is found before the branch; its small estimate must not stand for the branch."""
    refused(("forced-continue", "--vary", "omega=0.8:0.9", "--fex", "0.05", "--zeta", "0.05", "--max-points", "100000",
             "--steps-per-period", "100000", "--json"), "1e+11 RK4 steps", "--no-limit")


def test_the_brute_force_overlay_joins_the_forced_branch_estimate():
    model = BeltOscillator(zeta=0.05, vb=0.01, fex=0.05, omega=0.5)
    opts = ForcedContinueOptions(vary="omega=0.5:0.9", m="1", steps_per_period=64, max_points=5, switch_pd=False,
                                 overlay="0", as_json=True, out=None, plot=None, dpi=150.0, config=None)
    alone, with_overlay = (forced_job(model, "omega", (0.5, 0.9), 1, opts, n) for n in (0, 50))
    overlay = stroboscopic_estimate(model, "omega", np.linspace(0.5, 0.9, 50))
    assert with_overlay.seconds == pytest.approx(alone.seconds + overlay.seconds, rel=1e-12)
    # at the lowest frequency: 50 values x 340 forcing periods x 256 steps
    assert overlay.work == 50 * 340 * 256 and overlay.seconds > 0


# -- ordinary work is not refused ------------------------------------------------------------------

class Checked(Exception):
    """Raised in place of the work once the estimate has been compared with the limits."""


README = [
    "simulate --fd 0.02 --vb 0.01 --zeta 0",
    "simulate --fex 0.3 --omega 0.8 --zeta 0.05 --vb 0 --friction coulomb --fd 0.05 --json",
    "simulate --solver rk4 --t-end 2000",
    "response --omega 0.3:2.5:200 --fex 0.3 --zeta 0.05 --vb 0 --friction coulomb --fd 0.05",
    "lyapunov --fex 0.5 --omega 1 --zeta 0.01 --vb 0.1 --fd 0.5 --fs 1.0 --json",
    "orbit --friction coulomb --fs 0.04 --zeta 0.05 --json",
    "continue --param zeta --from 0.2 --to 0.4 --friction stribeck --vb 0.016 --sweep 11 --json",
    "map --friction stribeck --fd 0.02 --fs 0.04 --vs 0.01 --x vb --x-from 0.004 --x-to 0.03 --x-points 27 --y zeta "
    "--y-from 0 --y-to 1 --sweep 27x26 --t-end 300 --heat R_c",
    "map --friction coulomb --fd 0.5 --fs 1.0 --zeta 0.05 --vb 0.1 --x omega --x-from 1.5 --x-to 2.2 --y fex "
    "--y-from 0.4 --y-to 0.5 --y-points 5 --m 1,2 --sweep 8x5 --heat TR_B",
    "forced-orbit --fex 0.5 --omega 0.8 --json",
    "forced-continue --fex 0.01 --from 0.8 --to 1.2 --json",
    "basins --friction stribeck --fd 0.02 --fs 0.04 --vs 0.05 --delta 1 --zeta 0.03 --t-end 300 --vb 0.12 "
    "--x0=-0.28:0.32:121 --v0=-0.3:0.3:121",
    "basins --friction stribeck --fd 0.02 --fs 0.04 --vs 0.05 --delta 1 --zeta 0.03 --t-end 300 --x0=-0.28:0.32 "
    "--v0=-0.3:0.3 --sample 500 --vary vb=0.06:0.2:15",
    "sweep {sweep_toml} --out {out}",
    "reproduce --out {out_dir}",
]
SWEEP_TOML = ('friction = "coulomb"\nfs = 0.04\nt_end = 500.0\n\n[grid]\nzeta = { start = 0.0, stop = 0.1, num = 101 }\n'
              'vb = { start = 1e-3, stop = 0.1, num = 100, scale = "log" }\nfd = [0.01, 0.02, 0.03]\n')


@pytest.mark.parametrize("command", README, ids=[c.split()[0] + str(i) for i, c in enumerate(README)])
def test_the_readme_commands_are_within_the_limits(command, tmp_path, monkeypatch):
    (tmp_path / "sweep.toml").write_text(SWEEP_TOML)
    seen = []

    def verdict(est, limits):
        seen.append((est, estimate.refusal.__wrapped__(est, limits)))
        raise Checked

    verdict.__wrapped__ = estimate.refusal
    monkeypatch.setattr(estimate, "refusal", verdict)
    argv = shlex.split(command.format(sweep_toml=tmp_path / "sweep.toml", out=tmp_path / "results.zarr",
                                      out_dir=tmp_path / "repro"))
    with pytest.raises(Checked):
        main(argv)
    (est, why), = seen
    assert why is None, why
    assert est.wall < 0.25 * estimate.DEFAULT_SECONDS, est.text()  # well inside: an estimate is not a count


def test_every_model_command_takes_no_limit():
    from frictionflow.cli import COMMAND_MODULES, load_commands
    from frictionflow.cli._app import app
    import typer

    load_commands(None)
    group = typer.main.get_command(app)
    lacking = [name for name in COMMAND_MODULES if "--no-limit" not in {o for p in group.commands[name].params for o in p.opts}]
    assert not lacking


# -- the Newton shooting after a transient, estimated once the transient has found its period ----------------------

#: a time limit between the estimates of a Coulomb orbit's transient and of its shooting (see the tests' premises)
LOW_LIMIT = 2e-3
ORBIT = ("orbit", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--zeta", "0.05", "--vb", "0.01")


def low_limit(monkeypatch) -> None:
    """The commands' limits lowered to :data:`LOW_LIMIT` seconds, and Newton made to fail the test if it starts."""
    monkeypatch.setattr(cli_options, "Limits", lambda lift: estimate.Limits(seconds=LOW_LIMIT, lift=lift))

    def tripwire(*args, **kwargs):
        raise AssertionError("the shooting started")

    monkeypatch.setattr(shooting, "newton", tripwire)


def test_an_orbit_whose_shooting_is_above_the_limit_is_refused_after_its_transient(tmp_path, monkeypatch, capsys):
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Coulomb(fd=0.02, fs=0.04)
    assert auto_solver(law).cost(model, law, 500.0).wall < LOW_LIMIT  # premise: the transient is within the limit
    low_limit(monkeypatch)
    out = tmp_path / "o.json"
    assert main([*ORBIT, "--json", "--out", str(out)]) == 2
    captured = capsys.readouterr()
    line = one_line(captured.err, "estimated 84 orbit flows of up to ", "above the limit", "--no-limit")
    # the span: twice the period the transient found (7.63: test_no_limit_lifts_the_shooting_limit finds the orbit)
    span = float(line.split("of up to ")[1].split(" time units")[0])
    assert 14 < span < 16, line
    assert captured.out == "" and not out.exists()


def test_an_orbit_guess_is_estimated_before_any_work(monkeypatch, capsys):
    """No transient, no period: each flow is bounded by where every flow stops (1e4 time units)."""
    low_limit(monkeypatch)
    flows = Flows(monkeypatch)
    assert main([*ORBIT, "--guess", "--json"]) == 2
    one_line(capsys.readouterr().err, "estimated 84 orbit flows of up to 1e+04 time units", "--no-limit")
    assert not flows.durations


def test_no_limit_lifts_the_shooting_limit(monkeypatch, capsys):
    monkeypatch.setattr(cli_options, "Limits", lambda lift: estimate.Limits(seconds=LOW_LIMIT, lift=lift))
    assert main([*ORBIT, "--json", "--no-limit"]) == 0
    assert '"period": 7.63' in capsys.readouterr().out


def test_a_study_s_estimate_covers_the_shootings_of_its_runs():
    """Inside a study (an estimate accepted that leaves nothing open) a run's shooting is not estimated again; only the
    stage the accepted estimate left open is, and once."""
    small, big = estimate.Estimate(1, "steps", 1.0), estimate.Estimate(1, "flows", 1e9)
    with estimate.limited(estimate.Limits()):
        estimate.enforce(small)
        estimate.enforce_stage("shooting", big)  # not left open: the study's estimate stands
    with estimate.limited(estimate.Limits()):
        estimate.enforce(small, open_stage="shooting")
        estimate.enforce_stage("other", big)
        with pytest.raises(ValueError, match="estimated 1 flows, about 31.7 years, above the limit of 1 h"):
            estimate.enforce_stage("shooting", big)
    with estimate.limited(estimate.Limits()):
        estimate.enforce(small, open_stage="shooting")
        estimate.enforce_stage("shooting", small)
        estimate.enforce_stage("shooting", big)  # estimated once: the stage is no longer open
    with estimate.limited(None):  # no limits: shown, never refused
        estimate.enforce(small, open_stage="shooting")
        estimate.enforce_stage("shooting", big)


class Flows:
    """The length of every flow an orbit engine runs (the closed-form engine's runs, the compiled engine's kernel)."""

    def __init__(self, monkeypatch) -> None:
        self.durations: list[float] = []
        run, raw = ExactFlow.run, CompiledFlow.raw

        def exact_run(flow, *args, **kwargs):
            seg = run(flow, *args, **kwargs)
            self.durations.append(seg.duration)
            return seg

        def compiled_raw(flow, *args, **kwargs):
            status = raw(flow, *args, **kwargs)
            self.durations.append(float(flow.tot[flowmap.T_TIME]))
            return status

        monkeypatch.setattr(ExactFlow, "run", exact_run)
        monkeypatch.setattr(CompiledFlow, "raw", compiled_raw)


@pytest.mark.parametrize("law, zeta, vb, returns", [
    (Coulomb(fd=0.02, fs=0.04), 0.05, 0.01, 1),  # the closed-form engine
    (Stribeck(fd=0.02, fs=0.04, vs=0.01), 0.05, 0.016, 1),  # the compiled one
    (Stribeck(fd=0.02, fs=0.04, vs=0.01), 0.05, 0.016, 2),
], ids=["coulomb", "stribeck", "stribeck-2-returns"])
def test_the_shooting_estimate_bounds_its_flows(monkeypatch, law, zeta, vb, returns):
    """Every flow of the shooting is within the estimate's span, there are no more than it counts, and their total
    length is within 100x of the bound (it counts all 40 of Newton's iterations with a halving each, over twice the
    period; these converge at the first)."""
    model = BeltOscillator(zeta=zeta, vb=vb)
    seen = []

    def recorded(shoot, span):
        seen.append((span, shooting_estimate(shoot, span)))
        return seen[-1][1]

    monkeypatch.setattr(shooting, "shooting_estimate", recorded)
    with estimate.limited(estimate.Limits()):
        flows = Flows(monkeypatch)
        found = shooting.find_orbit(model, law, returns=returns)
    (span, est), = seen
    bound = est.work * span
    assert len(flows.durations) <= est.work and max(flows.durations) <= span
    assert sum(flows.durations) <= bound <= 100 * sum(flows.durations), (flows.durations, span, est.text())
    assert found.period <= span <= 2 * found.period * (1 + 1e-6)  # twice the period, as found by the transient


CONTINUE = ("continue", "--vary", "vb=0.01:0.3", "--friction", "stribeck", "--zeta", "0.05", "--json")


def test_a_branch_whose_orbits_may_reach_a_long_max_period_is_refused_before_any_work():
    """The orbits' periods are found only as a branch is traced; ``--max-period``, where a branch ends, bounds them
    before any work: 3 seeds x 2000 points x 10 flows of up to 1e4 time units are hours."""
    refused((*CONTINUE, "--max-points", "2000", "--max-period", "1e5"), "6e+04 orbit flows of up to 1e+04 time units",
            " h", "--no-limit")


def test_the_same_branch_at_the_default_max_period_is_within_the_limit(monkeypatch):
    seen = []

    def verdict(est, limits):
        seen.append((est, estimate.refusal.__wrapped__(est, limits)))
        raise Checked

    verdict.__wrapped__ = estimate.refusal
    monkeypatch.setattr(estimate, "refusal", verdict)
    with pytest.raises(Checked):
        main([*CONTINUE, "--max-points", "2000"])
    (est, why), = seen
    assert why is None and "6e+04 orbit flows of up to 500 time units" in est.text(), (why, est.text())


def test_the_branch_estimate_bounds_its_flows(monkeypatch):
    """A small continuation (a Hopf branch and the seeds' simulations): no more flows than estimated, none longer than
    the estimate's span (--max-period, where a branch ends); a loose bound (about 450x here in flow time: every seed is
    counted at max_points points of 10 flows each, every flow at max_period)."""
    model, law = BeltOscillator(zeta=0.1, vb=0.016), Stribeck(fd=0.02, fs=0.04, vs=0.01, delta=1.0, viscous=0.05)
    settings = ContinuationSettings(max_points=20)
    est = continuation_estimate(model, law, settings)
    flows = Flows(monkeypatch)
    result = continuation(model, law, "vb", 0.005, 0.025, settings=settings)
    assert len(result.branches) > 1  # orbits were traced, not only the equilibria
    assert len(flows.durations) <= est.work and max(flows.durations) <= settings.max_period
    assert sum(flows.durations) <= est.work * settings.max_period <= 1000 * sum(flows.durations)
    assert f"{est.work:.3g} orbit flows of up to {settings.max_period:.3g} time units" in est.text()
