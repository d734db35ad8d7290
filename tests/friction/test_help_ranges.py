"""The range ``--help`` states for a law's parameter is the range the law takes.

For every registered law and each of its numeric parameters, the range is
read from the rendered help of the option (the law's own, where the help
lists one for it, else the shared one), and values at its closed ends, just
inside its open ends and in its middle must build the law -- with the other
parameters at their defaults, or moved (one or two of them) to a value that
satisfies the rules between parameters (F_s >= F_d, ...): a value the law
refuses whatever the others are is a range the help must not claim.  Values
just outside must be refused.
"""

from __future__ import annotations

import itertools
import re

import pytest
import typer

from frictionflow.cli import load_commands
from frictionflow.cli._app import app
from frictionflow.friction import law_class, law_names

#: just inside an open end at 0 (a value that is no subnormal), and relatively elsewhere
EPS = 1e-12
RANGE = re.compile(r"in ([\[(])([-+0-9.e]+), ([-+0-9.e]+)([\])])")


def _helps() -> dict[str, str]:
    load_commands()
    simulate = typer.main.get_command(app).commands["simulate"]
    return {o.opts[0]: " ".join(o.help.split()) for o in simulate.params if o.param_type_name == "option"}


HELPS = _helps()


def _stated(flag: str, law: str) -> tuple[float, float, bool, bool]:
    """(lower, upper, lower open, upper open) the help of ``flag`` states for ``law``."""
    text = re.sub(r"\s\[[^\[\]]*\]\.?$", "", HELPS[flag])  # the default (per law, with "for ...") ends the help
    ranges = text.split("; ")
    own = [r for r in ranges[1:] if re.search(rf"\bfor (?:[a-z_]+, )*{law}\b", r)]
    m = RANGE.search(own[0] if own else ranges[0])
    assert m, (flag, text)
    return float(m.group(2)), float(m.group(3)), m.group(1) == "(", m.group(4) == ")"


def _near(x: float, inward: float) -> float:
    return x + inward * (EPS if x == 0 else EPS * abs(x))


def _probes(lo: float, hi: float, lo_open: bool, hi_open: bool) -> tuple[list[float], list[float]]:
    inside = [_near(lo, 1) if lo_open else lo, _near(hi, -1) if hi_open else hi, 0.5 * (lo + hi)]
    outside = [lo if lo_open else _near(lo, -1), hi if hi_open else _near(hi, 1)]
    return inside, outside


def _candidates(p) -> list[float]:
    """Values of another parameter to satisfy a rule between parameters: its range's ends (or near them)."""
    lo, hi = p.lower, p.upper
    out = [lo if not p.lower_open else _near(lo, 1)] if lo is not None else []
    return out + ([hi if not p.upper_open else _near(hi, -1)] if hi is not None else [])


def _builds(cls, name: str, value: float) -> bool:
    """Whether the law takes ``name`` = ``value`` with its other parameters at their defaults, at ``value`` too,
    or with one or two of them at an end of their ranges."""
    others = [p for p in cls.parameters if p.name != name and p.kind == "real"]
    moves = [(p.name, v) for p in others for v in (*_candidates(p), value)]
    for change in itertools.chain([()], ((m,) for m in moves), itertools.combinations(moves, 2)):
        try:
            cls(**{name: value, **dict(change)})
            return True
        except ValueError:
            continue
    return False


CASES = [(law, p.name) for law in law_names() for p in law_class(law).parameters if p.kind == "real"]


@pytest.mark.parametrize("law, name", CASES)
def test_the_help_states_the_range_the_law_takes(law, name):
    cls = law_class(law)
    p = next(q for q in cls.parameters if q.name == name)
    stated = _stated(p.flag, law)
    inside, outside = _probes(*stated)
    refused = [v for v in inside if not _builds(cls, name, v)]
    assert not refused, f"--{name} help says {HELPS[p.flag]!r}; friction={law} refuses {refused}"
    for v in outside:
        with pytest.raises(ValueError):
            cls(**{name: v})


def test_a_law_narrows_a_shared_parameter_and_never_widens_it():
    # the shared declaration checks a config's value before its law is known: it must stay the widest
    shared = next(p for p in law_class("stribeck").parameters if p.name == "delta")
    assert (shared.lower, shared.lower_open) == (0.0, True)
    assert shared.narrowed(lower=1.0, lower_open=False).range_text == "in [1, 100]"
    for wider in (dict(lower=0.0, lower_open=False), dict(upper=200.0), dict(upper=None)):
        with pytest.raises(ValueError, match="^delta: .* is not inside in \\(0, 100\\]"):
            shared.narrowed(**wider)
