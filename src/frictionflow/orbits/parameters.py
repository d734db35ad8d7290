"""Reading and changing one named parameter of a (model, friction law) pair."""

from __future__ import annotations

from dataclasses import replace

from .. import _validate as check
from ..friction.base import FrictionLaw
from ..params import BeltOscillator

MODEL_PARAMS = tuple(p.name for p in BeltOscillator.parameters)


def parameter_names(law: FrictionLaw) -> tuple[str, ...]:
    """The parameters that can be continued for this law: the oscillator's and the law's real ones (a law with
    internal state: all of its real ones, the bristles' sigma0, sigma1, ... too, which sweeps do not batch yet).

    A ``law`` that is no :class:`FrictionLaw` is refused by a TypeError naming it."""
    check.instance("law", law, FrictionLaw, "a FrictionLaw")
    own = law.parameters if law.configurable else ()  # a user law is rebuilt only by its author
    stateful = law.stick_rule == "state"
    return tuple(p.name for p in (*BeltOscillator.parameters, *own)
                 if p.kind == "real" and (p.sweepable or (stateful and p in own)))


def _check(name: str, law: FrictionLaw) -> None:
    allowed = parameter_names(law)
    if name not in allowed:
        raise ValueError(f"param must be one of {', '.join(allowed)} for friction={law.name}, got {name!r}")


def get_param(model: BeltOscillator, law: FrictionLaw, name: str) -> float:
    """The current value of parameter ``name``."""
    _check(name, law)
    return float(getattr(model if name in MODEL_PARAMS else law, name))



def with_param(model: BeltOscillator, law: FrictionLaw, name: str, value: float) -> tuple[BeltOscillator, FrictionLaw]:
    """A copy of (model, law) with ``name`` set to ``value`` (validated by the constructors; a boolean, text or
    None refused by a ValueError naming ``value``)."""
    _check(name, law)
    value = check.real("value", value, f"a real number ({name})")
    if name in MODEL_PARAMS:
        return replace(model, **{name: value}), law
    return model, type(law).from_values({**law.values(), name: value})
