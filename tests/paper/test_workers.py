"""``reproduce(workers=N)``: any positive count is accepted, and the pool never holds more processes than there
are independent computations (a huge count once crashed the process pool with an OverflowError)."""

from __future__ import annotations

import pytest

from frictionflow.paper import Settings, pipeline


class _Sized(Exception):
    """Raised by the stand-in executor with the pool size it was asked for."""


def _record(workers: int):
    raise _Sized(workers)


@pytest.mark.parametrize("workers", [3, 10**20])
def test_the_pool_has_at_most_one_process_per_computation(workers, tmp_path, monkeypatch):
    monkeypatch.setattr(pipeline, "_executor", _record)
    monkeypatch.setattr(pipeline, "_warm_up", lambda settings: None)
    jobs = len(pipeline.compute_jobs(Settings.quick()))
    with pytest.raises(_Sized) as sized:
        pipeline.reproduce(tmp_path / "out", Settings.quick(), workers=workers)
    assert sized.value.args[0] == min(workers, jobs)
    assert 1 < jobs < 10**3
