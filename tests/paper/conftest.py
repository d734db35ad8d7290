"""One computation of every study, shared by the tests of the paper reproduction.

``Settings.quick()`` keeps the paper's method and run length (dt = 1e-3,
t_end = 600, V_d = 1e-3) and thins only the sweep grid and the auxiliary
runs, so every claim is tested on the numbers the report states.
"""

from __future__ import annotations

import pytest

from frictionflow.paper import Settings, compute


@pytest.fixture(scope="session")
def settings() -> Settings:
    return Settings.quick()


@pytest.fixture(scope="session")
def data(settings):
    return compute(settings)
