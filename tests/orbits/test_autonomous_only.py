"""The autonomous paths (orbits on the section X' = 0, their continuation, the sliding equilibrium and its chart)
refuse an external force in one line that names the forced ones: they ran it before and answered for the system
without it (``continue --fex 0.1`` gave a motionless stable equilibrium where simulate finds a 2 pi cycle of amplitude
0.745, ``orbit --fex 0.1`` a slope at X = 5.9e14)."""

from __future__ import annotations

import pytest

from frictionflow import BeltOscillator, Coulomb, Stribeck
from frictionflow.orbits import continuation, find_orbit, stability_map

from ..cli.processes import in_process, one_line

FORCED = BeltOscillator(zeta=0.05, vb=0.01, fex=0.1, omega=1.0)
WORDS = "fex must be 0 for"


@pytest.mark.parametrize("law", [Coulomb(0.02, 0.04), Stribeck(0.02, 0.04, vs=0.01)], ids=["coulomb", "stribeck"])
def test_orbits_and_their_continuation_refuse_a_forced_system(law):
    with pytest.raises(ValueError, match=f"^{WORDS} periodic orbits .* got 0.1; .*forced-orbit"):
        find_orbit(FORCED, law)
    with pytest.raises(ValueError, match=WORDS):
        continuation(FORCED, law, "zeta", 0.04, 0.06)


def test_the_sliding_equilibrium_chart_refuses_a_forced_system():
    """(A law with internal state is shot on the stroboscopic map when forced: find_stateful_orbit takes it.)"""
    with pytest.raises(ValueError, match=f"^{WORDS} the sliding equilibrium"):
        stability_map(FORCED, Stribeck(0.02, 0.04, vs=0.01), "vb", [0.01, 0.02], "zeta", (0.0, 0.5))


@pytest.mark.parametrize("argv", [
    ("continue", "--friction", "coulomb", "--fs", "0.04", "--vary", "zeta=0.04:0.06", "--fex", "0.1"),
    ("orbit", "--friction", "coulomb", "--fs", "0.04", "--zeta", "0.05", "--fex", "0.1"),
    ("map", "--friction", "stribeck", "--x", "vb=0.01:0.03", "--y", "zeta=0:0.5", "--fex", "0.01"),
])
def test_the_commands_refuse_it_in_one_line(argv):
    code, out, err, _ = in_process(*argv, "--json")
    assert code == 2 and out == ""
    one_line(err, WORDS, "forced-orbit and forced-continue")
