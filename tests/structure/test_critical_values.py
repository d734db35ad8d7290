"""The stability scan's critical values on a structure with an unstable mode beside the ones that cross.

``stability_scan`` locates a crossing between two scan values by brentq on the crossing mode's real part, or,
for a pair that coalesces (mode coupling), on the pair's discriminant.  A mode already far in the right half
plane was taken for the crossing mode's coalescence partner: its frequency was nearer than the real parts'
difference (0.45 against 0.73), its real part falling while the other's rose.  The refinement then followed the
pair's largest real part, positive at both ends, and returned the scan value at the stable end: 6.4e-3 and 6.6e-3
before the true crossings (found by comparing the scans of random structures with the count of unstable
eigenvalues on a 40 times finer grid).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from frictionflow.analysis.stability import stability_scan, steady_sliding, zero_tolerance
from frictionflow.system import assemble, load_system

MODEL = Path(__file__).parent / "models" / "unstable_beside.toml"
ENTRY = "contact.0.fd"


@lru_cache(maxsize=1)
def system():
    return load_system(MODEL)


def at(value: float):
    """The structure's assembly with contact 0's F_d at ``value``."""
    return assemble(system().with_entry(ENTRY, value, start=False))


@pytest.fixture(scope="module")
def scan():
    return stability_scan(at, np.linspace(0.05, 0.7, 101), param=ENTRY)


def test_each_crossing_is_where_its_mode_s_real_part_is_zero(scan):
    crossings = [c for c in scan.critical if c.kind in ("mode_coupling", "negative_damping")]
    assert len(crossings) >= 4
    beside = 0
    for c in crossings:
        lam = steady_sliding(at(c.value)).eigenvalues
        mode = np.argmin(np.abs(lam - 1j * c.frequency))
        assert abs(lam[mode].real) <= zero_tolerance(lam)[mode]
        beside += bool(np.any(lam.real > 0.1))  # another mode far in the right half plane there
    assert beside >= 2  # the case is what the test is for


def test_the_unstable_count_changes_only_at_the_critical_values(scan):
    """On a grid 40 times finer than the scan's, the number of unstable eigenvalues changes only next to a
    critical value."""
    fine = np.linspace(0.05, 0.7, 4001)
    count = np.array([np.sum(steady_sliding(at(v)).eigenvalues.real > 0.0) for v in fine])
    changes = 0.5 * (fine[1:] + fine[:-1])[np.diff(count) != 0]
    values = np.array([c.value for c in scan.critical])
    step = fine[1] - fine[0]
    assert len(changes) == len(values)
    assert np.all(np.min(np.abs(changes[:, None] - values[None, :]), axis=1) <= step)
