"""``frictionflow orbit --model FILE``: a structure's periodic orbit by shooting, its Floquet multipliers and powers.

As for ``simulate --model``, the single-mass options are refused beside the
model file (it describes the whole structure), except ``--t-end`` (here the
transient before shooting); so are ``--config`` and ``--plot``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, NamedTuple, Optional


from ..io import check_input_path, check_output_path
from ..orbits.structure import StructureOrbit, fd_deviation, fd_structure_monodromy, find_structure_orbit
from ..solvers.structure_precompile import first_use
from ..system import load_system
from .output import print_summary, write_json
from .structure import refuse_single_mass

#: the transient before shooting when --t-end is not given
DEFAULT_TRANSIENT = 300.0


class ModelOrbitOptions(NamedTuple):
    """The orbit command's options that apply to a model file."""

    guess: bool
    returns: Optional[int]
    tol: Optional[float]
    fd_check: bool
    as_json: bool
    out: Optional[Path]


#: the orbit command's own options that apply beside a model file (said when refusing the others)
MODEL_OPTIONS = ("--tol", "--returns", "--guess", "--fd-check", "--json", "--out")


def _refuse(params: dict[str, Any], config: Optional[Path], plot: Optional[Path]) -> None:
    refuse_single_mass(params, own=MODEL_OPTIONS)
    if config is not None:
        raise ValueError("--model describes the whole system: --config cannot be given with it")
    if plot is not None:
        raise ValueError("--plot is not available with --model (use simulate --model --plot for the structure's figure)")


def orbit_report(found: StructureOrbit, path: Path, transient: float, fd_check: bool) -> dict[str, Any]:
    """The ``--json`` object: the orbit's report, the model file and the settings (and the FD check)."""
    report = found.to_dict()
    system = found.system
    report["model"] = {"file": str(path), "dof": list(system.dof), "elements": list(system.element_names)}
    report["params"] = {"t_transient": transient}
    if fd_check:
        M = fd_structure_monodromy(system, found.state, found.period)
        report["fd_monodromy"] = M.tolist()
        report["fd_deviation"] = fd_deviation(system, found, M)  # along the stuck contacts' constraints
    return report


def orbit_model(path: Path, params: dict[str, Any], opts: ModelOrbitOptions, config: Optional[Path] = None,
                plot: Optional[Path] = None) -> None:
    """The whole ``orbit --model`` command after option parsing (``params``: the single-mass options given)."""
    _refuse(params, config, plot)
    check_input_path(path, "--model")
    system = load_system(path)
    if opts.out is not None:
        check_output_path(opts.out, (".json",), "--out")
    given = params.get("t_end")
    if given is not None and not (math.isfinite(given) and given > 0):  # the option's own name, not the API's
        raise ValueError(f"t_end must be a finite number > 0 (the transient before shooting), got {given!r}")
    transient = 0.0 if opts.guess else float(given or DEFAULT_TRANSIENT)
    with first_use():  # an empty cache: part of the engine compiles on another core meanwhile
        found = find_structure_orbit(system, t_transient=transient, tol=opts.tol, returns=opts.returns)
        report = orbit_report(found, path, transient, opts.fd_check)
    if opts.out is not None:
        write_json(opts.out, report)
    if opts.as_json:
        print(json.dumps(report, allow_nan=False))
    else:
        check = f"; max |M - M_fd| {report['fd_deviation']:.2e}" if opts.fd_check else ""
        where = "return map" if found.autonomous else "stroboscopic map"
        print_summary(found, f"model {path}: Newton shooting on the {where}, exact monodromy with saltation{check}")
