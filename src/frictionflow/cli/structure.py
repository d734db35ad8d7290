"""``frictionflow simulate --model FILE``: a structure described by a model file, run and reported.

The single-mass options describe the one-mass system; a model file describes
the whole structure, so they are refused beside it (one line naming them),
except the run's length and window.
"""

from __future__ import annotations

import json
import math
import sys
from contextlib import nullcontext
from pathlib import Path
from typing import Any, Optional

from ..analysis.structure import StructureAnalysis, analyze_structure
from ..config import parse_window
from ..io import atomic_write, check_input_path, check_output_path
from ..plotting import FIGURE_FORMATS
from ..estimate import enforce
from .._progress import progress_bar
from ..solvers import structure_precompile
from ..solvers.structure import (AUTO, HOW, NAME as EXACT, file_dense_dt, run_estimate, simulate_system,
                                 solver_settings, structure_parameters, structure_solver_for)
from ..structure_plot import plot_structure
from ..system import System, assemble, load_system
from .output import print_summary

#: the single-mass options that still mean something beside a model file
MODEL_KEEPS = ("t_end", "window", "rtol")
#: the run's end time when --t-end is not given
T_END = 300.0
#: a run estimated above so many seconds shows a bar with its time so far (the estimate bounds it from above,
#: ~100x at the example chains: the bar then shows for runs of a fraction of a second and more)
PROGRESS_AFTER = 30.0
#: the steady-state tolerance when --rtol is not given (the structure analysis's)
RTOL = 1e-6
#: ... and beside ``simulate --model``: the solver, the structure solvers' own settings and the memory bound too
SIMULATE_KEEPS = (*MODEL_KEEPS, "solver", *structure_parameters(), "max_memory")
#: ``simulate``'s own options that apply beside a model file (said when refusing the others)
SIMULATE_OPTIONS = ("--json", "--out", "--plot", "--dpi")
MODEL_FORMATS = (".nc",)


def refuse_single_mass(params: dict[str, Any], keeps: tuple[str, ...] = MODEL_KEEPS,
                       own: tuple[str, ...] = ()) -> None:
    """One line if a single-mass option other than ``keeps`` is given with ``--model``; the line names those
    that apply: ``keeps`` the command has and its ``own`` options (flags, e.g. ``--returns``)."""
    given = sorted(k for k, v in params.items() if v is not None and k not in keeps)
    if given:
        flags = ", ".join("--" + k.replace("_", "-") for k in given)
        taken = ", ".join(["--" + k.replace("_", "-") for k in keeps if k in params] + list(own))
        raise ValueError(f"--model describes the whole system: {flags} cannot be given with it (beside it only "
                         f"{taken} apply; the model's own entries are in its file)")


def run_model(path: Path, params: dict[str, Any], outputs: dict[str, Any]) -> StructureAnalysis:
    """Load, check the outputs, run and analyse the model file at ``path`` (``outputs``: out, plot, dpi)."""
    refuse_single_mass(params, SIMULATE_KEEPS, own=SIMULATE_OPTIONS)
    check_input_path(path, "--model")
    system = load_system(path)
    if outputs.get("out") is not None:
        check_output_path(outputs["out"], MODEL_FORMATS, "--out")
    if outputs.get("plot") is not None:
        check_output_path(outputs["plot"], FIGURE_FORMATS, "--plot")
    t_end = requested_t_end(params)
    if not (math.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"--t-end must be a finite time > 0, got {t_end!r}")
    requested = params.get("solver") or AUTO  # auto's own choice is the run's: it may change solver on the way
    solver = structure_solver_for(system, requested)
    settings = solver_settings(solver, params)
    _refuse_others(solver, params)
    asm = assemble(system)
    dense_dt = run_dense_dt(asm, params, outputs)
    estimate = run_estimate(asm, t_end, dense_dt, solver=solver)
    enforce(estimate)
    window = _window(params.get("window"))
    rtol = RTOL if params.get("rtol") is None else float(params["rtol"])
    memory = {} if params.get("max_memory") is None else {"max_memory": params["max_memory"]}
    shown = sys.stderr.isatty() and estimate.wall > PROGRESS_AFTER
    with structure_precompile.first_use() if solver == EXACT else nullcontext():
        with progress_bar(f"{solver} run", 1, enabled=shown) as advance:  # the run's time so far, as it goes
            motion = simulate_system(system, t_end, dense_dt=dense_dt, solver=requested, **memory, **settings)
            advance(1)
        return analyze_structure(motion, rtol=rtol, window=window)


def run_dense_dt(asm: Any, params: dict[str, Any], outputs: dict[str, Any]) -> Optional[float]:
    """The run's sample step: --dense-dt, else the file's default step when --out writes the curve, else None
    (the switches only)."""
    dense_dt = params.get("dense_dt")
    if dense_dt is None and outputs.get("out") is not None:  # a file wants the curve, not just its switches
        dense_dt = file_dense_dt(asm)
    return dense_dt


def _refuse_others(solver: str, params: dict[str, Any]) -> None:
    """One line if another structure solver's setting is given beside ``--model`` (it would go unused)."""
    own = structure_parameters(solver)
    stray = [name for name in structure_parameters() if params.get(name) is not None and name not in own]
    if stray:
        flags = ", ".join("--" + name.replace("_", "-") for name in stray)
        raise ValueError(f"{flags}: not a setting of solver={solver}, which runs this model")


def _window(text: Any) -> Optional[tuple[float, float]]:
    """``--window`` as the single mass reads it (one line for a bad one, naming the form)."""
    return None if text is None else parse_window(text)


def report_model(result: StructureAnalysis, system: System, path: Path, params: dict[str, Any],
                 dense_dt: Optional[float] = None) -> dict[str, Any]:
    """The ``--json`` object: the analysis, the model file and the run's settings (``solver``: its name and
    settings, as the single mass's report gives them; ``dense_dt`` the run's sample step)."""
    out = result.to_dict()
    out["model"] = {"file": str(path), "dof": list(system.dof), "elements": list(system.element_names)}
    out["params"] = {"t_end": requested_t_end(params)}  # a run that lost a contact ends before it (``lost``)
    motion = result.motion
    out["solver"] = {"name": motion.solver, **motion.settings, "dense_dt": dense_dt}
    return out


def model_dataset(result: StructureAnalysis, report: dict[str, Any]):
    """The run's dataset with what ``--json`` says of it: the model file, t_end, the solver, the steady state's
    kind and window and the window's energy residual (the dataset's own ``energy_residual`` is the whole run's)."""
    ds = result.motion.to_xarray()
    ss = report["steady_state"]
    ds.attrs.update(model_file=report["model"]["file"], t_end=report["params"]["t_end"], solver=result.motion.solver,
                    steady_state=ss["kind"], window_energy_residual=report["energy_residual"])
    if ss.get("window") is not None:
        ds.attrs["window"] = list(ss["window"])
    return ds


def requested_t_end(params: dict[str, Any]) -> float:
    """The run's end time asked for: --t-end, or :data:`T_END`."""
    return T_END if params.get("t_end") is None else float(params["t_end"])


def simulate_model(path: Path, params: dict[str, Any], as_json: bool, outputs: dict[str, Any]) -> None:
    """The whole ``simulate --model`` command after option parsing."""
    result = run_model(path, params, outputs)
    system = result.motion.system
    report = report_model(result, system, path, params, run_dense_dt(result.motion.assembly, params, outputs))
    if outputs.get("out") is not None:
        with atomic_write(outputs["out"], "--out") as tmp:
            model_dataset(result, report).to_netcdf(tmp)
    if outputs.get("plot") is not None:
        plot_structure(result, outputs["plot"], name="--plot", dpi=outputs.get("dpi", 150.0))
    if as_json:
        print(json.dumps(report, allow_nan=False))
    else:
        print_summary(result, f"model {path}, solver {result.motion.solver} ({HOW[result.motion.solver]})")
