"""The suite's own scheduling (:mod:`tests.scheduling`): the structure engine's files from one end, the rest from
the other, every file run once."""

from __future__ import annotations

from collections import OrderedDict

from xdist.scheduler import LoadFileScheduling

from .scheduling import TwoEnded, family_first, usable


def units(spec: dict[str, int]) -> OrderedDict:
    """xdist's work queue for files of ``spec`` (path -> number of tests), nothing run yet."""
    return OrderedDict((path, {f"{path}::t{i}": False for i in range(n)}) for path, n in spec.items())


class Node:
    """A worker as the scheduler sees it: what it was sent."""

    def __init__(self) -> None:
        self.sent: list[list[int]] = []

    def send_runtest_some(self, indices: list[int]) -> None:
        self.sent.append(indices)


def scheduler(queue: OrderedDict, nodes: list[Node]) -> TwoEnded:
    """A :class:`TwoEnded` with ``queue`` collected by ``nodes`` (built without a pytest config)."""
    sched = TwoEnded.__new__(TwoEnded)
    collection = [nodeid for unit in queue.values() for nodeid in unit]
    sched.workqueue, sched.assigned_work = OrderedDict(queue), {node: {} for node in nodes}
    sched.registered_collections = {node: collection for node in nodes}
    return sched


SPEC = {"tests/a.py": 5, "tests/structure/big.py": 9, "tests/test_docs.py": 2, "tests/b.py": 1,
        "tests/structure/small.py": 2, "tests/c.py": 3}


def test_the_family_comes_first_largest_first_and_the_rest_largest_last():
    order = list(family_first(units(SPEC)))
    assert order == ["tests/structure/big.py", "tests/structure/small.py", "tests/b.py", "tests/c.py", "tests/a.py",
                     "tests/test_docs.py"]


def test_two_workers_take_from_the_two_ends_and_every_file_runs_once():
    first, second = Node(), Node()
    sched = scheduler(units(SPEC), [first, second])
    taken = {first: [], second: []}
    while sched.workqueue:
        for node in (first, second):
            if sched.workqueue:
                before = set(sched.workqueue)
                sched._assign_work_unit(node)
                taken[node] += list(before - set(sched.workqueue))
    assert taken[first][:2] == ["tests/structure/big.py", "tests/structure/small.py"]
    assert taken[second][:2] == ["tests/test_docs.py", "tests/a.py"]
    assert sorted(taken[first] + taken[second]) == sorted(SPEC)
    sent = sorted(i for node in (first, second) for batch in node.sent for i in batch)
    assert sent == list(range(sum(SPEC.values())))  # each test of the collection sent once


def test_xdist_still_has_what_the_scheduler_replaces():
    assert usable() and issubclass(TwoEnded, LoadFileScheduling)
