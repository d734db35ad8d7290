"""One grammar for every command (issue 21, item 1).

Walks every command's options by click introspection and holds them to the
vocabulary (:mod:`frictionflow.cli.vocabulary`): one name, one meaning,
default, type and panel; one spelling per meaning; one range syntax; the law
and the start defaulting by one rule; ``--json`` and ``--out`` on every
command that computes; the deprecated spellings of the previous release still
accepted, with one line on stderr.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import typer

from frictionflow.cli import COMMAND_MODULES, load_commands, main
from frictionflow.cli._app import app
from frictionflow.cli.vocabulary import (DEPRECATED, LAW_NEEDS, PANELS, PARAMETER_DEFAULTS, TERMS, default_law,
                                         panel_of, rewrite)
from frictionflow.friction.registry import law_class, law_names
from frictionflow.orbits import settings as records
from frictionflow.parameters import declared

load_commands()
ROOT = typer.main.get_command(app)
COMMANDS = {name: ROOT.commands[name] for name in COMMAND_MODULES}
#: the commands that compute (every one: each prints a table or JSON and can write its results)
COMPUTING = tuple(COMMAND_MODULES)


def options(command):  # noqa: ANN001, ANN201 - typer's vendored click
    opts = [p for p in command.params if p.param_type_name == "option" and p.name != "help"]
    assert opts, f"{command.name}: no options found (the walk would check nothing)"
    return opts


def meaning(help_text: str) -> str:
    """The part of a help text that must read the same on every command: before the default and the command's
    ``Here:`` detail."""
    return help_text.split(" Here:")[0].split(" [")[0].rstrip(".")


def every_option():
    for name, command in COMMANDS.items():
        for opt in options(command):
            yield name, opt


def test_every_option_is_a_word_of_the_vocabulary():
    params = {p.flag: p for p in declared().values()}
    for command, opt in every_option():
        assert len(opt.opts) == 1 and not opt.secondary_opts, f"{command} {opt.opts}: one spelling per option"
        flag = opt.opts[0]
        assert flag in TERMS or flag in params, f"{command} {flag}: not in the vocabulary"
        if flag in TERMS:
            term = TERMS[flag]
            assert opt.help.startswith(term.meaning), f"{command} {flag}: its help is not the vocabulary's"
            assert opt.required or opt.default == term.default, f"{command} {flag}: default {opt.default!r}"
            assert opt.rich_help_panel == term.panel, f"{command} {flag}: panel"
        else:
            p = params[flag]
            stem = p.with_default(None).help().rstrip(".")
            assert opt.help.startswith(stem), f"{command} {flag}: {opt.help!r} is not the declared {stem!r}"
            assert opt.rich_help_panel == panel_of(p), f"{command} {flag}: panel"
        assert opt.rich_help_panel in PANELS


def test_one_name_has_one_meaning_default_type_and_panel_on_every_command():
    exceptions = {(c, "--" + n.replace("_", "-")) for c, n in PARAMETER_DEFAULTS}
    seen: dict[str, tuple] = {}
    where: dict[str, str] = {}
    for command, opt in every_option():
        flag = opt.opts[0]
        shown = opt.help.split(" Here:")[0]
        said_default = shown.rsplit(" [", 1)[1] if shown.endswith("].") else None
        if flag == "--friction" or (command, flag) in exceptions:
            said_default = None  # by one rule (checked below), or a declared exception with its reason
        key = (meaning(shown), said_default, None if opt.required else opt.default,
               repr(opt.type_descriptor.annotation), opt.is_flag, opt.rich_help_panel)
        if flag in seen:
            mask = (lambda k: k[:1] + k[2:]) if said_default is None or seen[flag][1] is None else (lambda k: k)
            assert mask(seen[flag]) == mask(key), f"{flag}: {seen[flag]} on {where[flag]} but {key} on {command}"
        seen.setdefault(flag, key)
        where.setdefault(flag, command)


def test_one_meaning_has_one_spelling():
    by_meaning: dict[str, set[str]] = {}
    for _, opt in every_option():
        by_meaning.setdefault(meaning(opt.help).lower(), set()).add(opt.opts[0])
    twice = {m: f for m, f in by_meaning.items() if len(f) > 1}
    assert not twice, f"one meaning spelled several ways: {twice}"
    # a deprecated spelling is not also a live option of the same command, and leads to one
    for dep in DEPRECATED:
        for command in dep.commands:
            live = {o.opts[0] for o in options(COMMANDS[command])}
            assert dep.new in live, f"{command}: {dep.old} lead to {dep.new}, which it does not take"
            assert not set(dep.old) & live, f"{command}: {set(dep.old) & live} are both deprecated and live"


def test_a_range_has_one_syntax():
    for command, opt in every_option():
        flag = opt.opts[0]
        assert not flag.endswith(("-from", "-to")) and flag not in ("--from", "--to", "--param", "--parameter", "--points"), \
            f"{command} {flag}: a range in pieces (write FROM:TO:N)"
        if opt.metavar and "FROM" in opt.metavar:
            assert opt.metavar in ("FROM:TO[:N]", "NAME=FROM:TO[:N]"), f"{command} {flag}: metavar {opt.metavar}"


def test_toml_grids_take_the_same_range_syntax():
    from frictionflow.sweep.config import parse_sweep

    table = parse_sweep({"grid": {"zeta": {"start": 0.0, "stop": 0.1, "num": 5}}})
    text = parse_sweep({"grid": {"zeta": "0:0.1:5"}})
    assert text.axes["zeta"].tolist() == table.axes["zeta"].tolist() == [0.0, 0.025, 0.05, 0.075, 0.1]  # (linspace: 0.07500000000000001)
    with pytest.raises(ValueError, match=r"grid\.zeta must be FROM:TO:N"):
        parse_sweep({"grid": {"zeta": "0:0.1"}})


@pytest.mark.parametrize("command", COMPUTING)
def test_every_command_that_computes_has_json_and_out(command):
    flags = {o.opts[0] for o in options(COMMANDS[command])}
    assert {"--json", "--out"} <= flags


def test_the_law_defaults_by_one_rule():
    names = law_names()
    for command, opt in every_option():
        if opt.opts[0] != "--friction":
            continue
        expected = default_law(command)
        assert f"[{expected}]" in opt.help, f"{command}: {opt.help}"
        # the rule, independently: the first registered law with what the command needs (map: and every curve)
        needs = LAW_NEEDS.get(command, ())
        first = [n for n in names if all((law_class(n).stick_rule == "switch") if c == "switch" else
                                         law_class(n).has_tangent_kernel for c in needs)][0]
        if command == "map":
            first = [n for n in names if law_class(n).stick_rule == "switch" and not law_class(n).piecewise_constant][0]
        assert expected == first, command
    assert default_law("simulate") == names[0] == "karnopp"


@pytest.mark.parametrize("command", ["forced-orbit", "forced-continue", "lyapunov"])
def test_a_command_that_cannot_use_a_law_says_so_in_one_line(command, capsys):
    assert main([command, "--friction", "karnopp", "--fex", "0.5", "--vary", "omega=0.9:1.1"][:5 if command != "forced-continue" else 7]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{command} cannot use karnopp" in err[0] and "coulomb" in err[0], err


def test_the_start_defaults_to_the_laws_on_every_command():
    for command, opt in every_option():
        if opt.opts[0] in ("--x0", "--v0"):
            want = "[the law's start, F_d for most]" if opt.opts[0] == "--x0" else "[the law's start, V_b for most]"
            assert want in " ".join(opt.help.split()), f"{command}: {opt.help}"


FORCED = ["--friction", "coulomb", "--zeta", "0.05", "--vb", "0.1", "--fex", "0.5", "--omega", "1.0", "--fd", "0.5",
          "--fs", "1.0", "--m", "3"]


def run_json(capsys, *args):
    assert main([*args, "--json"]) == 0
    out, err = capsys.readouterr()
    return json.loads(out), err


@pytest.mark.parametrize("args", [
    ["forced-orbit", *FORCED, "--steps-per-period", "128"],
    ["lyapunov", *FORCED[:-2], "--t-transient", "20", "--t-end", "100", "--steps-per-period", "64"],
])
def test_forced_commands_start_where_simulate_does(args, capsys):
    default, _ = run_json(capsys, *args)
    given, _ = run_json(capsys, *args, "--x0", "0.5", "--v0", "0.1")  # F_d and V_b
    assert default == given


#: each deprecated spelling as a user wrote it, and today's spelling (written out by hand)
OLD_SPELLINGS = [
    (["response", "--omega", "0.3:2.5:200"], ["response", "--vary=omega=0.3:2.5:200"]),
    (["basins", "--x0=-0.28:0.32:6", "--v0", "-0.3:0.3:6"], ["basins", "--x0-range=-0.28:0.32:6", "--v0-range=-0.3:0.3:6"]),
    (["basins", "--x0-range=0:1:3", "--v0-range=0:1:3", "--tol", "0.01"],
     ["basins", "--x0-range=0:1:3", "--v0-range=0:1:3", "--attractor-tol=0.01"]),
    (["continue", "--param", "vb", "--from", "0.005", "--to", "0.025", "--points", "21", "--sweep", "3"],
     ["continue", "--vary=vb=0.005:0.025:21", "--overlay=3"]),
    (["continue", "--param=zeta", "--from=0.2", "--to=0.4"], ["continue", "--vary=zeta=0.2:0.4"]),
    (["forced-continue", "--parameter", "fex", "--from", "0.1", "--to", "0.3", "--steps", "64", "--sweep", "5"],
     ["forced-continue", "--vary=fex=0.1:0.3", "--overlay=5", "--steps-per-period=64"]),
    (["forced-continue", "--from", "0.8", "--to", "1.2"], ["forced-continue", "--vary=omega=0.8:1.2"]),
    (["forced-orbit", "--transient", "50", "--steps", "128"], ["forced-orbit", "--transient-periods=50", "--steps-per-period=128"]),
    (["lyapunov", "--steps", "128"], ["lyapunov", "--steps-per-period=128"]),
    (["map", "--x", "vb", "--x-from", "0.008", "--x-to", "0.02", "--x-points", "5", "--y-from", "0", "--y-to", "1",
      "--scan", "41", "--sweep", "3x2", "--sweep-out", "s.zarr", "--dataset", "d.nc"],
     ["map", "--x=vb=0.008:0.02:5", "--y=zeta=0:1:41", "--overlay=3x2", "--store=s.zarr", "--out=d.nc"]),
    (["map", "--x", "omega", "--y", "fex", "--x-from", "1.5", "--x-to", "2", "--y-from", "0.2", "--y-to", "0.6",
      "--y-points", "3"], ["map", "--x=omega=1.5:2", "--y=fex=0.2:0.6:3"]),
    (["map", "--x", "vb=0.01:0.02:3", "--y", "zeta=0:1", "--scan", "11"], ["map", "--x", "vb=0.01:0.02:3", "--y=zeta=0:1:11"]),
]


def test_every_deprecated_spelling_has_a_case():
    covered = {(argv[0], flag.split("=")[0]) for argv, _ in OLD_SPELLINGS for flag in argv[1:] if flag.startswith("--")}
    missing = [(c, f) for dep in DEPRECATED for c in dep.commands for f in dep.old if (c, f) not in covered]
    assert not missing


@pytest.mark.parametrize("old, new", OLD_SPELLINGS, ids=[" ".join(o[:2]) for o, _ in OLD_SPELLINGS])
def test_deprecated_spellings_are_rewritten_with_one_line_each(old, new):
    argv, lines = rewrite(old)
    assert sorted(argv) == sorted(new)
    changed = [d for d in DEPRECATED if old[0] in d.commands and any(w.split("=")[0] in d.old for w in old[1:])]
    assert len(lines) == len(changed) and all("deprecated" in line and "write --" in line for line in lines)
    # today's spelling parses (only the required options it does not give are missing)
    command = COMMANDS[argv[0]]
    for opt in options(command):
        if opt.required and not any(w.split("=")[0] == opt.opts[0] for w in argv):
            argv += [opt.opts[0], {"--vary": "omega=1:2:2", "--x0-range": "0:1:2", "--v0-range": "0:1:2",
                                   "--y": "zeta=0:1", "--x": "vb=0.01:0.02"}[opt.opts[0]]]
    command.make_context(argv[0], argv[1:])


def test_old_and_new_spellings_give_the_same_results(capsys):
    args = ["--fex", "0.3", "--zeta", "0.05", "--vb", "0", "--friction", "coulomb", "--fd", "0.05", "--periods", "30"]
    new, new_err = run_json(capsys, "response", "--vary", "omega=0.6:1.2:3", *args)
    old, old_err = run_json(capsys, "response", "--omega", "0.6:1.2:3", *args)
    assert old == new and new_err == ""
    assert old_err.strip().splitlines() == ["warning: --omega is deprecated and will be removed in the next release: "
                                            "write --vary omega=0.6:1.2:3"]


def test_both_spellings_at_once_are_refused_in_one_line(capsys):
    assert main(["continue", "--vary", "zeta=0.1:0.2", "--param", "zeta", "--from", "0.1", "--to", "0.2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--vary" in err[0] and "not both" in err[0]


def test_help_is_grouped_in_panels_and_keeps_its_brackets(capsys):
    assert main(["simulate", "--help"]) == 0
    out = capsys.readouterr().out
    heads = [line.rstrip(":") for line in out.splitlines() if line.endswith(":") and not line.startswith(" ")]
    assert heads == ["Model", "Forcing", "Friction", "Solver", "Window", "Run", "Output", "Options"]  # Run: --no-limit
    assert "[rk4 1e-6, adaptive 1e-8, exact 1e-10]" in " ".join(out.split())


def test_tables_say_which_law_stick_rule_and_solver(capsys):
    assert main(["simulate", "--t-end", "50"]) == 0
    assert "law karnopp (a stick band |V_rel| < V_d), solver exact" in " ".join(capsys.readouterr().out.split())
    assert main(["forced-orbit", *FORCED, "--steps-per-period", "128"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "law coulomb (Coulomb's stick rule), solver RK4 flow map with located switches" in out


def test_response_prints_a_short_table(capsys):
    args = ["--fex", "0.3", "--zeta", "0.05", "--vb", "0", "--friction", "coulomb", "--fd", "0.05", "--periods", "10",
            "--direction", "up"]
    assert main(["response", "--vary", "omega=0.5:1.5:40", *args]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith("│") and " up " in line]
    assert len(rows) == 12 and "12 of 40 frequencies shown" in " ".join(out.split())


def test_out_writes_what_json_prints(tmp_path, capsys):
    path = tmp_path / "orbit.json"
    args = ["forced-orbit", *FORCED, "--steps-per-period", "128"]
    printed, _ = run_json(capsys, *args)
    assert main([*args, "--out", str(path)]) == 0
    assert json.loads(path.read_text()) == printed
    assert main([*args, "--out", str(tmp_path / "orbit.nc")]) == 2


def test_a_missing_option_error_names_every_missing_one(capsys):
    assert main(["map", "--fd", "0.1"]) == 2
    assert capsys.readouterr().err.strip() == "error: missing options --x, --y"
    assert main(["map", "--x", "vb=0.01:0.02"]) == 2
    assert "'--y'" in capsys.readouterr().err


@pytest.mark.parametrize("command, settings, pairs", [
    ("continue", "ContinuationSettings", {"--max-points": "max_points", "--max-period": "max_period",
                                          "--step": "step"}),
    ("forced-continue", "ForcedContinuationSettings", {"--max-points": "max_points",
                                                       "--steps-per-period": "steps"}),
])
def test_a_continuation_traces_the_same_branch_from_the_command_line_as_from_the_api(command, settings, pairs):
    """Each continuation option's default is the API record's (``continue`` stopped at 400 points, the API at 300)."""
    record = getattr(records, settings)()
    defaults = {opt.opts[0]: opt.default for opt in options(COMMANDS[command])}
    for flag, field in pairs.items():
        assert defaults[flag] == getattr(record, field), f"{command} {flag}: {defaults[flag]} against {field}"
