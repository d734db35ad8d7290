"""docs/guide/friction.md says what the code does: the laws by name are the registry's, the commands it says
refuse a law with internal state are the ones that do, and its rate-and-state command runs in the current
spelling and finds the Hopf point it promises (Rice and Ruina's critical stiffness, derived here)."""

from __future__ import annotations

import json
import math
import re
import shlex
from pathlib import Path

import pytest

from frictionflow import BeltOscillator, RateState
from frictionflow.cli import main
from frictionflow.cli.vocabulary import LAW_NEEDS, check_law
from frictionflow.friction import law_class, law_names

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "guide" / "friction.md"
#: the spelling of earlier releases (--param NAME --from A --to B), which the guide no longer shows
DEPRECATED = ("--param", "--from", "--to")


def _text() -> str:
    return GUIDE.read_text()


def _stateful() -> list[str]:
    return [name for name in law_names() if law_class(name).internal_names]


def _refuses(command: str, name: str) -> bool:
    try:
        check_law(command, name)
    except ValueError:
        return True
    return False


def _bash_commands() -> list[list[str]]:
    blocks = re.findall(r"```bash\n(.*?)```", _text(), re.S)
    return [shlex.split(line) for block in blocks for line in block.replace("\\\n", " ").splitlines() if line.strip()]


def test_laws_by_name_lists_every_registered_law():
    listed = re.search(r"`--friction ([a-z_|]+)`", _text().split("## Laws by name")[1]).group(1).split("|")
    assert listed == list(law_names())


def test_the_commands_the_guide_says_refuse_laws_with_internal_state_are_the_ones_that_do():
    refusing = {c for c in LAW_NEEDS if any(_refuses(c, name) for name in _stateful())}
    paragraph = _text().split("Sweeps take them")[1].split("```")[0]
    said = set(re.findall(r"`(?:frictionflow )?([a-z][a-z-]*)`", paragraph))
    accepting = {"orbit", "continue"}
    assert refusing and refusing <= said and accepting <= said
    assert not any(_refuses(c, name) for c in accepting for name in _stateful())
    assert "do not yet" not in " ".join(_text().split())


def test_the_guides_commands_use_the_current_spelling():
    commands = _bash_commands()
    assert commands and all(args[0] == "frictionflow" for args in commands)
    # and the commands quoted in the text (`frictionflow continue ...`)
    commands += [shlex.split(span) for span in re.findall(r"`(frictionflow [^`]*)`", _text())]
    assert not [args for args in commands if set(args) & set(DEPRECATED)]


def _critical_dc(model: BeltOscillator, law: RateState) -> float:
    """D_c where k = 1 equals Rice and Ruina's k_c = N (b - a) / D_c (1 + m V_b^2 / (N a D_c)), m = 1: the positive
    root of D_c^2 - N (b - a) D_c - (b - a) V_b^2 / a = 0."""
    p, q = law.normal * (law.b - law.a), (law.b - law.a) * model.vb**2 / law.a
    return 0.5 * (p + math.sqrt(p * p + 4.0 * q))


def test_the_rate_state_continuation_runs_and_finds_the_critical_stiffness(capsys):
    (args,) = [a for a in _bash_commands() if a[1] == "continue" and "rate_state" in a]
    assert main([*args[1:], "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    hopf = [b["value"] for b in out["bifurcations"] if b["type"] == "hopf"]
    expected = _critical_dc(BeltOscillator(), RateState())  # the command's defaults
    assert hopf == [pytest.approx(expected, rel=1e-3)]
