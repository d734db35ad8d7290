"""``frictionflow forced-orbit`` and ``frictionflow forced-continue``: periodic orbits of the forced oscillator.

Registered by importing this module in :mod:`frictionflow.cli` (``from . import forced_orbit``).
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Optional

import numpy as np

from .._json import jsonable
from .._ranges import parse_named_range
from ..io import check_output_path
from ..estimate import Estimate, enforce
from ..orbits.forced import (DEFAULT_TRANSIENT, PARAMETERS, branch_estimate, branch_steps, check_parameter, continue_forced,
                             find_forced_orbit, stroboscopic_estimate, stroboscopic_sweep, switch_period_doubling)
from ..orbits.settings import ForcedContinuationSettings
from ..orbits.forced_plot import plot_forced_branches, plot_forced_orbit
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ._app import app
from .options import (CONFIG_OPTION, check_option, command_config, parameter_names, refuse_fixed, start_state,
                      with_dimensional, with_options, with_parameters)
from .output import FLOW_MAP, print_summary, provenance, write_json
from .vocabulary import check_term, option, overlay_count, parameter_help

MODEL = parameter_names(("oscillator", "law"), run=("x0", "v0", "friction", "dimensional"))
#: forced-continue's --overlay N (the options' numbers, --m's included, are checked by their vocabulary terms)
OVERLAY = Param("overlay", "", "brute-force parameter values", "run", 0, kind="int", lower=0, upper=10_000)
SHORT_HELP_ORBIT = "Periodic orbit of the forced oscillator and its Floquet multipliers."
SHORT_HELP_CONTINUE = "Continue forced periodic orbits in Omega or F_ex, with bifurcations."
OUT_FORMATS = (".json",)


def _one_m(text: str) -> int:
    """``--m``: one period in forcing periods (these commands follow one orbit)."""
    try:
        m = int(text)
    except ValueError:
        raise ValueError(f"--m must be one integer here (the orbit's period in forcing periods), got {text!r}") from None
    return check_term("--m", m)


def _build(command: str, config: Optional[Path], params: dict[str, Any]):
    cfg = command_config(command, config, params)
    model, law, _ = cfg.build()
    return cfg, model, law


def _check_outputs(out: Optional[Path], plot: Optional[Path]) -> None:
    if out is not None:
        check_output_path(out, OUT_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")


def _report(report: dict[str, Any], out: Optional[Path], as_json: bool, results: list, caption: str) -> None:
    """The report to --out, then as JSON or as tables on stdout."""
    if out is not None:
        write_json(out, report)
    if as_json:
        print(json.dumps(report, allow_nan=False))
    else:
        for r in results:
            print_summary(r, caption)


@dataclass(frozen=True)
class ForcedOrbitOptions:
    """The forced-orbit command's own options (the model's come as ``params``)."""

    m: str = option("--m")
    transient_periods: int = option("--transient-periods")
    steps_per_period: int = option("--steps-per-period")
    as_json: bool = option("--json")
    out: Optional[Path] = option("--out", "Here: the JSON object, .json.")
    plot: Optional[Path] = option("--plot", "Here: the orbit's phase portrait and time history.")
    dpi: float = option("--dpi")
    config: Optional[Path] = CONFIG_OPTION


@app.command("forced-orbit", short_help=SHORT_HELP_ORBIT)
@with_parameters(MODEL, parameter_help("forced-orbit", MODEL))
@with_options(ForcedOrbitOptions)
def forced_orbit(params: dict[str, Any], opts: ForcedOrbitOptions) -> None:
    """Newton shooting for the orbit of period m 2 pi / Omega: state at tau = 0, multipliers, power and TR_B."""
    m = _one_m(opts.m)
    _check_outputs(opts.out, opts.plot)
    cfg, model, law = _build("forced-orbit", opts.config, params)
    x0, v0 = start_state(cfg, model, law)
    orbit = find_forced_orbit(model, law, m=m, x0=x0, v0=v0, transient_periods=opts.transient_periods,
                              steps=opts.steps_per_period)
    if opts.plot is not None:
        plot_forced_orbit(orbit, opts.plot, name="--plot", dpi=opts.dpi)
    _report(with_dimensional(orbit.as_dict(), cfg), opts.out, opts.as_json, [orbit], provenance(law, FLOW_MAP, cfg.dimensional))


def _job(model, parameter: str, interval: tuple[float, float], m: int, opts: "ForcedContinueOptions",  # noqa: ANN001
         overlay: int) -> Estimate:
    """The command's cost: the branch with its first orbit (found as forced-orbit finds it), then the overlay.

    Estimated here because the first orbit is found before the branch: its own estimate, accepted first, would
    otherwise stand for the whole command.
    """
    settings = ForcedContinuationSettings(steps=opts.steps_per_period, max_points=opts.max_points)
    job = branch_estimate(replace(model, **{parameter: interval[0]}), parameter, interval, m, settings, True)
    if overlay:
        job = job.then(stroboscopic_estimate(model, parameter, np.linspace(min(interval), max(interval), overlay)))
    return job


@dataclass(frozen=True)
class ForcedContinueOptions:
    """The forced-continue command's own options (the model's come as ``params``)."""

    vary: str = option("--vary", "Here: omega or fex, FROM:TO (the first orbit is found at FROM; the branch chooses "
                       "its points).", required=True)
    m: str = option("--m")
    steps_per_period: int = option("--steps-per-period")
    max_points: int = option("--max-points")
    switch_pd: bool = option("--switch-pd")
    overlay: str = option("--overlay", "Here: N parameter values swept up.")
    as_json: bool = option("--json")
    out: Optional[Path] = option("--out", "Here: the JSON object, .json.")
    plot: Optional[Path] = option("--plot", "Here: the bifurcation diagram.")
    dpi: float = option("--dpi")
    config: Optional[Path] = CONFIG_OPTION


@app.command("forced-continue", short_help=SHORT_HELP_CONTINUE)
@with_parameters(MODEL, parameter_help("forced-continue", MODEL))
@with_options(ForcedContinueOptions)
def forced_continue(params: dict[str, Any], opts: ForcedContinueOptions) -> None:
    """Pseudo-arclength continuation in Omega or F_ex: folds, period doublings, Neimark-Sacker, grazings."""
    parameter, span = parse_named_range("--vary", opts.vary, "none")
    start, stop = span.start, span.stop
    if parameter not in PARAMETERS:
        raise ValueError(f"--vary: forced-continue varies omega or fex, got {parameter!r}")
    for end, value in (("FROM", start), ("TO", stop)):
        check_parameter(parameter, value, f"--vary {end}")  # both ends by the parameter's declaration, as the API does
    if start == stop:
        raise ValueError(f"--vary: TO must differ from FROM ({start!r})")
    m, overlay = _one_m(opts.m), overlay_count(opts.overlay)
    check_option("--overlay", OVERLAY, overlay)
    _check_outputs(opts.out, opts.plot)
    refuse_fixed(parameter, "--vary", "along the branch", opts.config, params)
    # the model at FROM: the varied parameter is given by --vary alone (--fex has no default a forced model accepts)
    cfg, model, law = _build("forced-continue", opts.config, {**params, parameter: start})
    x0, v0 = start_state(cfg, model, law)
    enforce(_job(model, parameter, (start, stop), m, opts, overlay))  # the whole command, before its first run
    # the first orbit as forced-orbit finds it: DEFAULT_TRANSIENT forcing periods from the start, then Newton, on
    # the branch's grid
    steps = branch_steps(model, parameter, (start, stop), opts.steps_per_period)
    first = find_forced_orbit(replace(model, **{parameter: start}), law, m=m, x0=x0, v0=v0,
                              transient_periods=DEFAULT_TRANSIENT, steps=steps)
    branch = continue_forced(model, law, parameter, start, stop, m=m, orbit=first, steps=steps,
                             max_points=opts.max_points, progress=sys.stderr.isatty())
    branches = [branch]
    if opts.switch_pd and branch.events_of("period_doubling"):
        branches.append(switch_period_doubling(branch))
    brute = None
    if overlay:
        values = np.linspace(min(start, stop), max(start, stop), overlay)
        brute = stroboscopic_sweep(branch.model, law, parameter, values, x0=float(branch.points[0].state[0]) if start < stop else 0.0,
                                   v0=float(branch.points[0].state[1]) if start < stop else 0.0)
    if opts.plot is not None:
        plot_forced_branches(branches, opts.plot, sweep=brute, name="--plot", dpi=opts.dpi)
    report: dict[str, Any] = {"branches": [b.as_dict() for b in branches]}
    if brute is not None:
        report["brute_force"] = jsonable({"values": brute.values, "X": brute.x, "V": brute.v})
    _report(with_dimensional(report, cfg), opts.out, opts.as_json, branches, provenance(law, FLOW_MAP, cfg.dimensional))
