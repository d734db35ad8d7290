"""Reading and changing one named parameter of a (model, friction law) pair."""

from __future__ import annotations

from dataclasses import replace

from ..friction.base import FrictionLaw
from ..friction.coulomb import Coulomb
from ..friction.karnopp import Karnopp
from ..friction.stribeck import SlipLaw, Stribeck
from ..params import BeltOscillator

MODEL_PARAMS = ("zeta", "vb")
LAW_PARAMS: dict[type, tuple[str, ...]] = {
    Karnopp: ("fd", "fs", "vd"),
    Coulomb: ("fd", "fs"),
    Stribeck: ("fd", "fs", "vs", "delta", "viscous"),
    SlipLaw: (),
}


def parameter_names(law: FrictionLaw) -> tuple[str, ...]:
    """The parameters that can be continued for this law."""
    return MODEL_PARAMS + LAW_PARAMS.get(type(law), ())


def _check(name: str, law: FrictionLaw) -> None:
    allowed = parameter_names(law)
    if name not in allowed:
        raise ValueError(f"param must be one of {', '.join(allowed)} for friction={law.name}, got {name!r}")


def get_param(model: BeltOscillator, law: FrictionLaw, name: str) -> float:
    """The current value of parameter ``name``."""
    _check(name, law)
    return float(getattr(model if name in MODEL_PARAMS else law, name))


def with_param(model: BeltOscillator, law: FrictionLaw, name: str, value: float) -> tuple[BeltOscillator, FrictionLaw]:
    """A copy of (model, law) with ``name`` set to ``value`` (validated by the constructors)."""
    _check(name, law)
    if name in MODEL_PARAMS:
        return replace(model, **{name: float(value)}), law
    kwargs = {k: v for k, v in law.as_dict().items() if k != "friction"}
    if hasattr(law, "rk4_band"):
        kwargs["rk4_band"] = law.rk4_band  # type: ignore[attr-defined]
    kwargs[name] = float(value)
    return model, type(law)(**kwargs)
