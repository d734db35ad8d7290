"""The command line's vocabulary: every option name with one meaning, one type, one default and one help panel.

A command takes its options from here -- the model's from the declared
parameters (:mod:`frictionflow.parameters`, through :mod:`.options`), its own
from :data:`TERMS` by :func:`option` -- so that an option name means the same
thing on every command.  A range is written ``FROM:TO:N`` everywhere
(:mod:`frictionflow._ranges`), ``NAME=FROM:TO:N`` where the option does not
name the parameter.  The friction law defaults by one rule
(:func:`default_law`).  Spellings of earlier releases are declared in
:data:`DEPRECATED`: :func:`rewrite` turns them into today's, with one line on
stderr, before the command line is parsed.

``tests/cli/test_grammar.py`` walks every command and holds them to this table.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable, Optional

import typer

from .._display import spoken
from ..analysis.response import PERIODS_RANGE
from ..friction.registry import law_class, law_names
from ..io import DEFAULT_DPI, DPI_RANGE, FIGURE_FORMATS
from ..orbits.settings import CONTINUATION_RANGES, DEFAULT_STEPS, FORCED_RANGES, MAX_POINTS
from ..parameters import Param, declared, positive_real
from ..sweep.runner import CHUNK_SIZE

#: the help panels, in the order --help shows them (options without one come last, under "Options")
PANELS = ("Model", "Forcing", "Friction", "Solver", "Window", "Study", "Run", "Output")
#: the oscillator's parameters of the external force (their panel is Forcing, not Model)
FORCING = ("fex", "omega", "phi")
#: panels of the run's own declared parameters (the rest by owner: oscillator Model, law Friction, solver Solver)
RUN_PANELS = {"x0": "Model", "v0": "Model", "dimensional": "Model", "friction": "Friction", "solver": "Solver",
              "max_memory": "Solver", "t_end": "Window", "window": "Window", "rtol": "Window"}
OWNER_PANELS = {"oscillator": "Model", "law": "Friction", "solver": "Solver", "run": "Run"}

#: how a path option shows in --help (as typer shows a ``Path`` option without a parser)
PATH_METAVAR = "<path>"


def path_text(text: str | Path) -> Path:
    """A path option's value: refuses an empty one, which ``Path`` would turn into ``.`` (this directory) and an
    error would then quote as ``'.'``, not as what was typed."""
    if isinstance(text, Path):
        return text
    if text == "":
        raise typer.BadParameter("an empty path: give a file name")
    return Path(text)


def panel_of(p: Param) -> str:
    """The help panel of a declared parameter's option."""
    if p.owner == "oscillator" and p.name in FORCING:
        return "Forcing"
    if p.owner == "run":
        return RUN_PANELS.get(p.name, "Run")
    return OWNER_PANELS[p.owner]


@dataclass(frozen=True)
class Term:
    """One option of the vocabulary: its flag, meaning (the help text), type, default and panel."""

    flag: str
    meaning: str
    annotation: Any
    default: Any = None
    panel: str = "Study"
    metavar: Optional[str] = None
    path: bool = False
    #: the declaration whose range the option's value must be in: stated in the help (:func:`ranged`) and, for a
    #: number, checked as the command line is read, in the line every check gives ("--X must be ..., got ...")
    limits: Optional[Param] = None

    @property
    def name(self) -> str:
        """The command function's parameter (``--json`` is ``as_json``: ``json`` is a module)."""
        return "as_json" if self.flag == "--json" else self.flag[2:].replace("-", "_")


def ranged(meaning: str, limits: Optional[Param]) -> str:
    """``meaning`` with the allowed range of ``limits`` said at its end, before the default it states if any, as a
    declared parameter's help says it ("Crossings of ... per period, in [1, 64]."; "Processes to use, >= 1 [up to
    2].")."""
    words = None if limits is None else limits.range_text
    if not words:
        return meaning
    text = meaning.removesuffix(".")
    head, bracket, default = text.rpartition(" [")
    if bracket and default.endswith("]"):
        return f"{head}, {words} [{default}."
    return f"{text}, {words}."


def _states_default(t: Term) -> bool:
    """Whether ``t``'s meaning states its default itself ("[up to 2]"), apart from its range."""
    words = None if t.limits is None else t.limits.range_text
    return "[" in (t.meaning.replace(f", {words}", "") if words else t.meaning)


def _terms(*terms: Term) -> dict[str, Term]:
    return {t.flag: replace(t, meaning=ranged(t.meaning, t.limits)) for t in terms}


class _Seed(Param):
    """A seed's declaration: its upper end 2^63 said as such (``:g`` would round it to 9.22337e+18)."""

    @property
    def allowed(self) -> str:
        return f"an integer and in [{self.lower:g}, 2^{int(self.upper).bit_length() - 1})"


# -- the ranges of the commands' own numbers (each checked by its declaration here, its help saying the range) -----
#: the figures' resolution (the range is the writers', :data:`frictionflow.io.DPI_RANGE`)
DPI = Param("dpi", "", "resolution of the figures", "run", DEFAULT_DPI, lower=DPI_RANGE[0], upper=DPI_RANGE[1])
SCHEDULER_TIMEOUT = positive_real("scheduler_timeout", "", "seconds to wait for the scheduler", "run", 5.0)
#: --sample's seed: numpy's seeds (the range :func:`frictionflow.basins.basins` checks)
SEED = _Seed("seed", "", "seed of the sample", "run", 0, kind="int", lower=0, upper=2**63, upper_open=True)
#: an orbit's period in forcing periods, its RK4 steps per period and its transient (the API's ranges)
ORDER = FORCED_RANGES["m"]
STEPS_PER_PERIOD = FORCED_RANGES["steps"]
TRANSIENT_PERIODS = FORCED_RANGES["transient_periods"]
T_TRANSIENT = Param("t_transient", "", "transient before averaging", "run", 1000.0, lower=0.0, upper=1e9)
BLOCK = Param("block", "", "renormalisation interval of an unforced run", "run", None, lower=0.0, lower_open=True,
              upper=1e6)
#: processes of a command that spreads its work (reproduce): at least one
WORKERS = Param("workers", "", "processes to use", "run", None, kind="int", lower=1)
FOLD_EVERY = Param("fold_every", "", "x values between fold seeds", "run", 2, kind="int", lower=1, upper=10_000)


OPT_PATH = Optional[Path]
#: the commands' own options (the model's parameters are declared by their owners)
TERMS: dict[str, Term] = _terms(
    # -- output ---------------------------------------------------------------
    Term("--json", "Print one JSON object with the results to stdout instead of the table.", bool, False, "Output"),
    Term("--out", "Write the results (the format by the suffix).", OPT_PATH, None, "Output", PATH_METAVAR, True),
    Term("--plot", f"Draw the results ({', '.join(FIGURE_FORMATS)}).", OPT_PATH, None, "Output", PATH_METAVAR, True),
    # (the range is click's, from bounds; the format is the figure file's suffix, which --plot's help names)
    Term("--dpi", "Resolution of the figures in dots per inch.", float, DEFAULT_DPI, "Output", "<float>", limits=DPI),
    Term("--store", "Keep the sweep's resumable store here.", OPT_PATH, None, "Output", "PATH.zarr", True),
    Term("--config", "TOML file with any of the model's options (names with underscores).", OPT_PATH, None, "Model",
         PATH_METAVAR, True),
    Term("--model", "Model file (TOML) of a linear structure with friction contacts: dof, mass, springs, dampers, "
         "contacts, forces.", OPT_PATH, None, "Model", PATH_METAVAR, True),
    # -- running ----------------------------------------------------------------
    Term("--restart", "Discard an existing sweep output or store (needed when the settings changed).", bool, False, "Run"),
    Term("--scheduler", "Dask scheduler address tcp://HOST:PORT; default: this machine's cores.", Optional[str], None, "Run"),
    Term("--scheduler-timeout", "Seconds to wait for the scheduler to answer.", float, 5.0, "Run", "SECONDS",
         limits=SCHEDULER_TIMEOUT),
    Term("--chunk-size", "Points per chunk of a sweep (a task and a unit of commit).", Optional[int], None, "Run",
         limits=CHUNK_SIZE),
    Term("--verify", "Check the sweep output OUT without computing: each bad chunk, then a summary; exit code 1 if "
         "damaged.", Optional[str], None, "Run", "OUT"),
    Term("--repair", "With --verify: rebuild damaged metadata from the sweep's settings (recorded, or CONFIG) and keep "
         "every chunk that verifies; computes nothing.", bool, False, "Run"),
    Term("--workers", "Processes to use [up to 2].", Optional[int], None, "Run", limits=WORKERS),
    Term("--no-limit", "Run even when the work is estimated above an hour of computing or an output above the free "
         "space of its disk.", bool, False, "Run"),
    Term("--quick", "Reduced grids and shorter auxiliary runs: a smoke test, not the published figures.", bool, False),
    # -- what is varied ---------------------------------------------------------
    Term("--vary", "The parameter varied and its range, NAME=FROM:TO:N.", Optional[str], None, "Study", "NAME=FROM:TO[:N]"),
    Term("--x", "First parameter (horizontal axis) and its range, NAME=FROM:TO:N.", Optional[str], None, "Study",
         "NAME=FROM:TO[:N]"),
    Term("--y", "Second parameter (vertical axis) and its range, NAME=FROM:TO:N.", Optional[str], None, "Study",
         "NAME=FROM:TO[:N]"),
    Term("--x0-range", "Range of X(0): FROM:TO:N grid points, or FROM:TO with --sample.", Optional[str], None, "Study",
         "FROM:TO[:N]"),
    Term("--v0-range", "Range of X'(0), as --x0-range.", Optional[str], None, "Study", "FROM:TO[:N]"),
    Term("--sample", "N random initial states in the ranges instead of a grid.", Optional[int], None, "Study", "N"),
    Term("--seed", "Seed of --sample (the same points for a seed on every machine).", int, 0, limits=SEED),
    Term("--overlay", "Brute-force simulations drawn under the curves: N along the range, NXxNY over a plane (0: none).",
         str, "0", "Study", "N|NXxNY"),
    Term("--heat", "Sweep variable of the --overlay heat map (R_c, TR_B, P_fin, ...).", str, "R_c"),
    # -- the command's study ----------------------------------------------------
    Term("--attractor-tol", "Tolerance telling attractors apart: relative on period and amplitude, absolute on stick "
         "fraction [1e-3].", Optional[float], None),
    Term("--tol", "Newton tolerance on each orbit's X relative to max(F_s, |V_b|) [1e-12 exact, 1e-9 smooth laws].",
         Optional[float], None, "Solver", limits=CONTINUATION_RANGES["tol"]),
    Term("--periods", "Forcing periods simulated at each frequency, in [{}, {}].".format(*PERIODS_RANGE), int, 300,
         "Window"),
    Term("--direction", "Sweep up, down or both (jumps and hysteresis show with both).", str, "both"),
    Term("--t-transient", "Time before the averaging starts (rounded up to whole blocks).", float, 1000.0, "Window",
         limits=T_TRANSIENT),
    Term("--transient-periods", "Forcing periods run from (x0, v0) before shooting (0: shoot from them).", int, 200,
         "Window", limits=TRANSIENT_PERIODS),
    Term("--steps-per-period", "RK4 steps per forcing period (per block when unforced); switches are located "
         f"whatever it is [{DEFAULT_STEPS}, doubled while a step exceeds 2 pi/64: Omega < 1/8].",
         Optional[int], None, "Solver", limits=STEPS_PER_PERIOD),
    Term("--block", "Renormalisation interval when unforced [2 pi]; forced: the forcing period.", Optional[float], None,
         "Window", limits=BLOCK),
    Term("--guess", "Shoot from the start state itself, without a transient (to reach unstable orbits).", bool, False),
    Term("--returns", "Crossings of the section X'=0 per period (2: period-2 orbit); default 1, with --model the "
         "count of the cycle the transient settles on or nears (forced: forcing periods).", Optional[int], None,
         limits=CONTINUATION_RANGES["returns"]),
    Term("--fd-check", "Also report the monodromy matrix by finite differences of simulations.", bool, False),
    Term("--m", "Period of the orbit(s) in forcing periods (1 harmonic, > 1 subharmonic); comma-separated where a "
         "command follows several (map).", str, "1", "Study", "M[,M..]", limits=ORDER),
    Term("--seeds", "Where orbit branches start: hopf, start, stop (comma-separated).", str, "hopf,start,stop"),
    Term("--max-points", "Points per orbit branch at most.", int, MAX_POINTS, limits=CONTINUATION_RANGES["max_points"]),
    Term("--max-period", "A branch ends (period_blowup) once its period exceeds this.", float, 500.0,
         limits=CONTINUATION_RANGES["max_period"]),
    Term("--step", "First arclength step, relative to the interval.", float, 0.02, limits=CONTINUATION_RANGES["step"]),
    Term("--switch-pd", "Also continue the 2m branch born at the first period doubling.", bool, False),
    Term("--monitor", "Locate the extrema of these per-orbit quantities along the branches (comma-separated: P_fin, "
         "P_dv, P_df, R_c, R_f, P_belt, P_heat, TR_B, amplitude, stick_fraction, period).", str, ""),
    Term("--curves", "Curves to compute (comma-separated): hopf, grazing, fold [all]; forced (--x/--y omega, fex): "
         "fold, period_doubling, neimark_sacker, grazing [all].", Optional[str], None),
    Term("--fold-every", "A continuation in y seeds fold curves at every n-th x value.", int, 2, limits=FOLD_EVERY),
)

#: declared parameters whose default differs on a command, with the reason (shown in its help)
#: (None: no default on it, the reason says what to give)
PARAMETER_DEFAULTS: dict[tuple[str, str], tuple[Any, str]] = {
    ("lyapunov", "t_end"): (6000.0, "the averaging needs long runs; transient included, rounded up to whole blocks"),
    ("reproduce", "t_end"): (600.0, "the paper's run length; averages over the last cycle before it"),
    ("forced-orbit", "fex"): (None, "none: give it, > 0 (a forced orbit needs a forcing)"),
    ("response", "fex"): (None, "none: give it, > 0 (a frequency response needs a forcing)"),
    ("forced-continue", "fex"): (None, "none: give it, > 0, unless --vary fex (a forced orbit needs a forcing)"),
}


def option(flag: str, detail: str | None = None, *, required: bool = False) -> Any:
    """The ``typer.Option`` of vocabulary term ``flag``; ``detail`` says what it is on this command (appended to
    the meaning), ``required`` makes it one the command needs."""
    t = TERMS[flag]
    default = ... if required else t.default
    text = t.meaning if detail is None else f"{t.meaning} {detail}"
    if not required and default is not None and default is not False and default != "" and not _states_default(t):
        text += f" [{default}]"  # as the declared parameters show theirs
    extra: dict[str, Any] = {"parser": path_text} if t.path else {}
    if t.limits is not None and t.annotation in (int, float, Optional[int], Optional[float]):
        extra["callback"] = checked_by(flag, t.limits)
    return typer.Option(default, flag, help=text, metavar=t.metavar, rich_help_panel=t.panel, show_default=False,
                        **extra)


def checked_by(flag: str, limits: Param) -> Callable[[Any], Any]:
    """The click callback of a number option: its value (None: not given) checked by ``limits``, ValueError naming
    ``flag`` ("--returns must be an integer and in [1, 64], got 0") as the command line is read -- before anything
    is computed or written."""
    named = replace(limits, name=flag)
    return lambda value: None if value is None else named.check(value)


def check_term(flag: str, value: Any) -> Any:
    """``value`` checked by the range of option ``flag`` (:data:`TERMS`), in the line naming the option (for an
    option read as text, such as ``--m 1,2``, whose numbers are checked once parsed)."""
    return checked_by(flag, TERMS[flag].limits)(value)


def parameter_help(command: str, names: tuple[str, ...], detail: dict[str, str] | None = None) -> dict[str, str]:
    """The help of the declared parameters ``names`` on ``command``: the declared text with the command's default
    law and its declared defaults (:data:`PARAMETER_DEFAULTS`), and ``detail`` (what it is used for here) appended."""
    out = {}
    for name in names:
        p = declared()[name]
        if name == "friction":
            p = p.with_default(default_law(command))
        if (command, name) in PARAMETER_DEFAULTS:
            value, reason = PARAMETER_DEFAULTS[command, name]
            p = p.with_default(value, reason if value is None else f"{value:g}: {reason}")
        elif p.owner == "law":
            p = p.with_default(p.default, law_defaults(p))
        text = p.help()
        wants = LAW_NEEDS.get(command, ()) + LAW_WANTS.get(command, ())
        if name == "friction" and wants:
            text = text[:-1] + f" (the first law with {spoken(tuple(CAPABILITIES[c][0] for c in wants), 'and')})."
        if detail and name in detail:
            text += " " + detail[name]
        out[name] = text
    return out


def _default_text(p: Param) -> str | None:
    """How ``p``'s default reads in a help text (as :meth:`Param.help` says it)."""
    if p.default_text is not None:
        return p.default_text
    if p.default is None or callable(p.default):
        return None
    return f"{p.default:g}" if isinstance(p.default, float) else str(p.default)


def law_defaults(p: Param) -> str | None:
    """The default of the law parameter ``p`` as each registered law declares it: the shared declaration's, then
    every other one with the laws that have it ("F_d; 2 F_d for stribeck; 0.04 for cubic")."""
    first = _default_text(p)
    others: dict[str, list[str]] = {}
    for name in law_names():
        own = next((q for q in law_class(name).parameters if q.name == p.name), None)
        text = None if own is None else _default_text(own)
        if text is not None and text != first:
            others.setdefault(text, []).append(name)
    return "; ".join([*([first] if first is not None else []), *(f"{t} for {', '.join(n)}" for t, n in others.items())]) or None


def overlay_count(text: str) -> int:
    """``--overlay N`` along one parameter's range (0: none)."""
    try:
        return int(text)
    except ValueError:
        raise ValueError(f"--overlay must be a number N of simulations along the range (0: none), got {text!r}") from None


def overlay_shape(text: str) -> tuple[int, int] | None:
    """``--overlay NXxNY`` over a plane (e.g. 40x30), or 0 for none."""
    if text.strip() in ("", "0"):
        return None
    try:
        nx, ny = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"--overlay must be NXxNY (e.g. 40x30) or 0, got {text!r}") from None
    if not (2 <= nx <= 2000 and 2 <= ny <= 2000):
        raise ValueError(f"--overlay must have 2..2000 points per axis, got {text!r}")
    return nx, ny


# -- the friction law: one rule for the default, one line for a law a command cannot use -------------------------
#: what a command may need of a law: (words for messages, test on the law's class)
CAPABILITIES: dict[str, tuple[str, Callable[[type], bool]]] = {
    "switch": ("Coulomb's stick rule", lambda law: law.stick_rule == "switch"),
    "tangent": ("a tangent kernel", lambda law: law.has_tangent_kernel),
    "falling": ("a falling slip curve", lambda law: not law.piecewise_constant),
    "static": ("no internal state", lambda law: not law.internal_names),
}
#: what each command needs of a law (it refuses a law without them); commands not named take every law
LAW_NEEDS: dict[str, tuple[str, ...]] = {
    "forced-orbit": ("switch", "tangent"), "forced-continue": ("switch", "tangent"), "lyapunov": ("switch", "tangent"),
    "map": ("static",),
}
#: what a command's default law should also have to give all its results (map: a chart with every curve)
LAW_WANTS: dict[str, tuple[str, ...]] = {"map": ("switch", "falling")}


def _has(law: type, capabilities: tuple[str, ...]) -> bool:
    return all(CAPABILITIES[c][1](law) for c in capabilities)


def default_law(command: str) -> str:
    """The default law of ``command``: the first registered law it can use that gives all its results."""
    names = law_names()
    needs = LAW_NEEDS.get(command, ())
    for wants in (needs + LAW_WANTS.get(command, ()), needs):
        usable = [n for n in names if _has(law_class(n), wants)]
        if usable:
            return usable[0]
    raise ValueError(f"no registered law has what {command} needs")


def check_law(command: str, name: str) -> None:
    """One line (ValueError) when ``command`` cannot use the law ``name``."""
    needs = LAW_NEEDS.get(command, ())
    law = law_class(name)
    missing = [CAPABILITIES[c][0] for c in needs if not CAPABILITIES[c][1](law)]
    if missing:
        usable = tuple(n for n in law_names() if _has(law_class(n), needs))
        raise ValueError(f"--friction: {command} cannot use {name} (stick rule: {law.stick_rule}): it needs "
                         f"{spoken(tuple(missing), 'and')}; use {spoken(usable)}")


# -- spellings of earlier releases -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Deprecated:
    """Old option spellings of ``commands`` and how they are written today.

    ``build`` makes the new option's value from the old options' values (by flag; with ``joins``, the current
    options whose old-style value belongs with them, such as map's ``--x NAME``).
    """

    commands: tuple[str, ...]
    old: tuple[str, ...]
    new: str
    build: Callable[[dict[str, str]], str] = lambda given: next(iter(given.values()))
    joins: tuple[str, ...] = ()


def _need(given: dict[str, str], flags: tuple[str, ...], new: str) -> None:
    missing = [f for f in flags if f not in given]
    if missing:
        raise ValueError(f"{'/'.join(flags)} are deprecated and go together (missing {', '.join(missing)}): write {new}")


def _continue_vary(given: dict[str, str]) -> str:
    _need(given, ("--param", "--from", "--to"), "--vary NAME=FROM:TO[:N]")
    n = f":{given['--points']}" if "--points" in given else ""
    return f"{given['--param']}={given['--from']}:{given['--to']}{n}"


def _entry_vary(given: dict[str, str]) -> str:
    """``--param ENTRY --from A --to B [--points N]`` -> ``ENTRY=A:B[:N]`` (not deprecated: see :data:`PIECES`)."""
    missing = [f for f in ("--param", "--from", "--to") if f not in given]
    if missing:
        raise ValueError(f"--param, --from and --to go together (missing {', '.join(missing)}), or write "
                         "--vary ENTRY=FROM:TO[:N]")
    return _continue_vary(given)


def _forced_vary(given: dict[str, str]) -> str:
    _need(given, ("--from", "--to"), "--vary NAME=FROM:TO")
    return f"{given.get('--parameter', 'omega')}={given['--from']}:{given['--to']}"


def _axis(axis: str, default: str, counts: tuple[str, ...]) -> Callable[[dict[str, str]], str]:
    """Map's ``--AXIS NAME --AXIS-from A --AXIS-to B`` (and a count) -> ``NAME=A:B[:N]``."""
    flag = f"--{axis}"

    def build(given: dict[str, str]) -> str:
        n = [given[c] for c in counts if c in given]
        if len(n) > 1:
            raise ValueError(f"{' and '.join(counts)} are deprecated and both set N of {flag} NAME=FROM:TO:N: give one")
        tail = f":{n[0]}" if n else ""
        if "=" in given.get(flag, ""):  # today's --AXIS with only a deprecated count beside it
            if f"{flag}-from" in given or f"{flag}-to" in given:
                raise ValueError(f"give {flag} NAME=FROM:TO:N or the deprecated {flag}-from/{flag}-to, not both")
            return given[flag] + tail if given[flag].count(":") == 1 else given[flag]
        _need(given, (f"{flag}-from", f"{flag}-to"), f"{flag} NAME=FROM:TO:N")
        return f"{given.get(flag, default)}={given[f'{flag}-from']}:{given[f'{flag}-to']}{tail}"

    return build


#: every deprecated spelling, kept for one release
DEPRECATED: tuple[Deprecated, ...] = (
    Deprecated(("response",), ("--omega",), "--vary", lambda given: f"omega={given['--omega']}"),
    Deprecated(("basins",), ("--x0",), "--x0-range"),
    Deprecated(("basins",), ("--v0",), "--v0-range"),
    Deprecated(("basins",), ("--tol",), "--attractor-tol"),
    Deprecated(("continue",), ("--param", "--from", "--to", "--points"), "--vary", _continue_vary),
    Deprecated(("forced-continue",), ("--parameter", "--from", "--to"), "--vary", _forced_vary),
    Deprecated(("continue", "forced-continue", "map"), ("--sweep",), "--overlay"),
    Deprecated(("forced-orbit",), ("--transient",), "--transient-periods"),
    Deprecated(("forced-orbit", "forced-continue", "lyapunov"), ("--steps",), "--steps-per-period"),
    Deprecated(("map",), ("--x-from", "--x-to", "--x-points"), "--x", _axis("x", "vb", ("--x-points",)), ("--x",)),
    Deprecated(("map",), ("--y-from", "--y-to", "--y-points", "--scan"), "--y",
               _axis("y", "zeta", ("--y-points", "--scan")), ("--y",)),
    Deprecated(("map",), ("--sweep-out",), "--store"),
    Deprecated(("map",), ("--dataset",), "--out"),
)


#: a range in pieces that a command accepts for good beside its --vary (the spelling its issue gives), rewritten
#: to --vary before parsing without a warning; the grammar's one option stays --vary
PIECES: tuple[Deprecated, ...] = (
    Deprecated(("stability",), ("--param", "--from", "--to", "--points"), "--vary", _entry_vary),
)


def _take(argv: list[str], flags: tuple[str, ...]) -> tuple[dict[str, str], list[str]]:
    """The values of ``flags`` in ``argv`` (``--flag V`` or ``--flag=V``) and ``argv`` without them."""
    given: dict[str, str] = {}
    rest: list[str] = []
    i = 0
    while i < len(argv):
        word = argv[i]
        if word == "--":
            rest.extend(argv[i:])
            break
        flag, eq, value = word.partition("=")
        if flag in flags:
            if not eq:
                if i + 1 >= len(argv):
                    raise ValueError(f"{flag} needs a value")
                i += 1
                value = argv[i]
            given[flag] = value
        else:
            rest.append(word)
        i += 1
    return given, rest


def rewrite(argv: list[str]) -> tuple[list[str], list[str]]:
    """``argv`` with the deprecated spellings of its command written today's way, and one line for each; the
    ranges in pieces of :data:`PIECES` rewritten too, without a line."""
    command = next((a for a in argv if not a.startswith("-")), None)
    lines = []
    for dep in (*DEPRECATED, *PIECES):
        if command not in dep.commands:
            continue
        given, rest = _take(argv, dep.old + dep.joins)
        old = [f for f in dep.old if f in given]
        if not old:
            continue
        value = dep.build(given)
        if dep.new not in dep.joins and any(w == dep.new or w.startswith(dep.new + "=") for w in rest):
            spelling = "" if dep in PIECES else "the deprecated "
            raise ValueError(f"give {dep.new} or {spelling}{'/'.join(old)}, not both")
        cut = rest.index("--") if "--" in rest else len(rest)
        argv = [*rest[:cut], f"{dep.new}={value}", *rest[cut:]]  # one word: a value may start with '-'
        if dep in PIECES:
            continue
        lines.append(f"{'/'.join(old)} {'is' if len(old) == 1 else 'are'} deprecated and will be removed in the next "
                     f"release: write {dep.new} {value}")
    return argv, lines
