"""The command line names the option the user typed, states every enforced range in its help, and checks every
option before it writes anything (QA report C: --fs's default, old names in messages, reproduce's --dt/--t-end and
empty --out, --dpi, --fex on the forced commands, ranges missing from the help, map's ``sweep_out``)."""

from __future__ import annotations

import pytest
import typer

from frictionflow.cli import load_commands, main
from frictionflow.cli._app import app
from frictionflow.cli.vocabulary import TERMS
from frictionflow.friction.registry import law_class
from frictionflow.io import DPI_RANGE
from frictionflow.orbits.settings import CONTINUATION_RANGES
from frictionflow.parameters import declared


def run(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, *args):
    """The one ``error:`` line of a command refused as bad input (exit code 2), nothing on stdout."""
    code, out, err = run(capsys, *args)
    assert code == 2, err
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    return lines[0]


def option_help(command: str, flag: str) -> str:
    """The help text of ``flag`` on ``command``, as --help and the generated CLI reference show it."""
    load_commands([command])
    params = typer.main.get_command(app).commands[command].params
    return next(p.help for p in params if flag in p.opts)


def flat(text: str) -> str:
    return " ".join(text.split())


# -- 1. --fs: the default each law declares ---------------------------------------------------------------------------
def test_fs_help_gives_each_laws_default_from_their_declarations(capsys):
    def default(law: str) -> str:
        p = next(q for q in law_class(law).parameters if q.name == "fs")
        return p.default_text if p.default_text is not None else f"{p.default:g}"

    code, out, _ = run(capsys, "simulate", "--help")
    assert code == 0
    text = flat(out)
    assert f"[F_d; {default('stribeck')} for stribeck; {default('cubic')} for cubic]" in text
    assert "[F_d; 2 F_d for stribeck; 0.04 for cubic]" in text  # what docs/guide/friction.md says
    for command in ("orbit", "map", "forced-orbit"):
        assert option_help(command, "--fs").endswith("[F_d; 2 F_d for stribeck; 0.04 for cubic].")


# -- 2. messages name the option typed, not the API's argument or a deprecated spelling ---------------------------
@pytest.mark.parametrize("args, says, not_says", [
    (["continue", "--vary", "zeta=0.2:0.4", "--overlay", "-1"], "error: --overlay must be an integer and in [0, 10000]",
     "sweep"),
    (["forced-continue", "--fex", "0.3", "--vary", "omega=0.5:1", "--overlay", "-1"],
     "error: --overlay must be an integer and in [0, 10000]", "overlay must"),
    (["continue", "--vary", "foo=0.2:0.4"], "error: --vary: NAME must be one of zeta, vb,", "param"),
    (["map", "--x", "vb=0.004:0.03:27", "--y", "foo=0:1"], "error: --y: NAME must be one of zeta, vb,", "param"),
    (["map", "--x", "foo=0.004:0.03:27", "--y", "zeta=0:1"], "error: --x: NAME must be one of zeta, vb,", "param"),
    (["continue", "--vary", "zeta=0.2:0.4:1"],
     "error: --vary N (grid points of the equilibrium branch) must be an integer and in [2, 100000]", "_"),
    (["continue", "--vary", "zeta=0.2:0.4", "--max-points", "1"], "error: --max-points must", "max_points"),
    (["forced-continue", "--fex", "0.3", "--vary", "omega=0.5:1", "--max-points", "1"], "error: --max-points must",
     "max_points"),
    (["continue", "--vary", "zeta=0.2:0.4", "--max-period", "0"], "error: --max-period must", "max_period"),
    (["continue", "--vary", "zeta=0.2:0.4", "--step", "2"], "error: --step must", "step must"),
    (["orbit", "--returns", "0"], "error: --returns must", "returns must"),
    (["orbit", "--tol", "1"], "error: --tol must", " tol must"),
    (["forced-orbit", "--fex", "0.3", "--m", "0"], "error: --m must be an integer and in [1, 1000]", " m must"),
    (["forced-orbit", "--fex", "0.3", "--transient-periods", "-1"], "error: --transient-periods must", "_"),
    (["forced-orbit", "--fex", "0.3", "--steps-per-period", "2"], "error: --steps-per-period must", "_"),
    (["lyapunov", "--t-transient", "-1"], "error: --t-transient must", "t_transient"),
    (["lyapunov", "--block", "0"], "error: --block must", "block must"),
    (["map", "--x", "vb=0.004:0.03:27", "--y", "zeta=0:1", "--fold-every", "0"], "error: --fold-every must",
     "fold_every"),
    (["map", "--x", "vb=0.004:0.03:5", "--y", "zeta=0:1", "--overlay", "2x2", "--heat", "foo"],
     "error: --heat must be a sweep variable", "heat must"),
])
def test_a_message_names_the_option_typed(capsys, args, says, not_says):
    line = refused(capsys, *args)
    assert line.startswith(says), line
    assert not_says not in line.removeprefix(says)


# -- 3. reproduce: every option checked before --out is made; one range per option ------------------------------------
@pytest.mark.parametrize("flag, value", [("--dt", "5000"), ("--dt", "0"), ("--dt", "1e-12"), ("--t-end", "1e13"),
                                         ("--t-end", "10"), ("--workers", "0"), ("--dpi", "5")])
def test_reproduce_refuses_a_bad_option_before_creating_out(capsys, tmp_path, flag, value):
    out = tmp_path / "r3"
    line = refused(capsys, "reproduce", "--out", str(out), flag, value)
    assert line.startswith(f"error: {flag} must be"), line
    assert not out.exists() and list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("flag, name", [("--dt", "dt"), ("--t-end", "t_end")])
def test_reproduce_states_and_enforces_one_range_per_option(capsys, tmp_path, flag, name):
    words = declared()[name].range_text
    assert f", {words} [" in option_help("reproduce", flag)  # the help states the range it enforces
    lines = {refused(capsys, "reproduce", "--out", str(tmp_path / "r"), flag, v).split(", got")[0]
             for v in ("0", "-1", "1e13", "inf")}
    assert lines == {f"error: {flag} must be finite and {words}"}  # the same range whatever the value


# -- 4. --dpi: checked and said as every other option --------------------------------------------------------------
@pytest.mark.parametrize("value", ["nan", "0", "5000", "inf"])
def test_dpi_is_refused_in_the_line_every_option_gives(capsys, tmp_path, value):
    line = refused(capsys, "simulate", "--t-end", "10", "--dpi", value, "--plot", str(tmp_path / "a.png"))
    lo, hi = DPI_RANGE
    assert line == f"error: --dpi must be finite and in [{lo:g}, {hi:g}], got {float(value)!r}"
    assert list(tmp_path.iterdir()) == []


def test_dpi_help_states_its_range_as_the_others_do():
    lo, hi = DPI_RANGE
    help_text = option_help("simulate", "--dpi")
    assert f"in [{lo:g}, {hi:g}]" in help_text and "<=x<=" not in help_text


# -- 5. --fex on the commands that need a forcing -------------------------------------------------------------------
@pytest.mark.parametrize("command", ["forced-orbit", "response", "forced-continue"])
def test_fex_help_says_it_is_needed_and_positive(command):
    text = option_help(command, "--fex")
    assert "> 0" in text and not text.endswith("[0].")
    assert text.startswith(declared()["fex"].with_default(None).help().rstrip("."))  # the declared help, then why
    assert "[0]" in option_help("simulate", "--fex")  # elsewhere 0 (unforced) stays the default


# -- 6. every enforced range is in the help, from the declaration that checks it --------------------------------------
RANGED = [
    ("sweep", "--chunk-size", "0"), ("basins", "--chunk-size", "0"), ("sweep", "--scheduler-timeout", "0"),
    ("reproduce", "--workers", "0"), ("orbit", "--tol", "1"), ("continue", "--tol", "1"), ("orbit", "--returns", "65"),
    ("continue", "--max-points", "1"), ("forced-continue", "--max-points", "100001"),
    ("continue", "--max-period", "0"), ("continue", "--step", "0"), ("basins", "--seed", "-1"),
    ("forced-orbit", "--m", "0"), ("map", "--m", "1001"), ("forced-orbit", "--steps-per-period", "3"),
    ("lyapunov", "--steps-per-period", "3"), ("forced-orbit", "--transient-periods", "-1"),
    ("map", "--fold-every", "0"), ("lyapunov", "--t-transient", "-1"), ("lyapunov", "--block", "0"),
]
REQUIRED = {"sweep": ["sweep.toml", "--out", "s.zarr"], "basins": ["--x0-range", "0:1", "--v0-range", "0:1",
            "--sample", "2"], "reproduce": ["--out", "r"], "continue": ["--vary", "zeta=0.2:0.4"],
            "forced-continue": ["--fex", "0.3", "--vary", "omega=0.5:1"], "forced-orbit": ["--fex", "0.3"],
            "map": ["--x", "omega=0.8:1.2:3", "--y", "fex=0.2:0.3:2", "--friction", "coulomb"]}


@pytest.mark.parametrize("command, flag, bad", RANGED)
def test_an_enforced_range_is_stated_in_the_help_and_the_message(capsys, tmp_path, monkeypatch, command, flag, bad):
    words = TERMS[flag].limits.range_text
    assert words and f", {words}" in option_help(command, flag)
    monkeypatch.chdir(tmp_path)
    line = refused(capsys, command, *REQUIRED.get(command, []), flag, bad)
    assert line.startswith(f"error: {flag} must be") and words in line, line
    assert list(tmp_path.iterdir()) == []


def test_the_ranges_are_the_checks_own_declarations():
    for flag, name in (("--tol", "tol"), ("--returns", "returns"), ("--max-points", "max_points"),
                       ("--max-period", "max_period"), ("--step", "step")):
        assert TERMS[flag].limits is CONTINUATION_RANGES[name]
    from frictionflow.sweep.runner import CHUNK_SIZE

    assert TERMS["--chunk-size"].limits is CHUNK_SIZE
    assert TERMS["--seed"].limits.range_text == "in [0, 2^63)"


# -- 7. the forced map's heat-map sweep names its store by --store -------------------------------------------------
def test_the_forced_maps_sweep_names_a_late_failure_by_store(capsys, tmp_path):
    store = tmp_path / "s.zarr"
    store.mkdir()
    (store / "junk").write_text("not a sweep")
    line = refused(capsys, "map", "--x", "omega=0.8:1.2:3", "--y", "fex=0.2:0.3:2", "--zeta", "0.1", "--friction",
                   "coulomb", "--overlay", "2x2", "--store", str(store), "--t-end", "50")
    assert line.startswith("error: --store: ") and "sweep_out" not in line and "give another --store" in line
    assert [p.name for p in store.iterdir()] == ["junk"]
