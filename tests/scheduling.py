"""The order in which xdist's workers take the test files (``--dist loadfile``): two families from two ends.

On an empty numba cache most of the suite's time is compiling, and a kernel two workers need at about the same
time is compiled by both (neither finds it in the cache yet): the structure engine's largest kernels were
compiled twice that way, about 140 s of CPU in a run of 800 s.  Here the files of the structure engine
(``structure`` in their path) are queued first, largest first, and the others after them, largest last; the first
worker takes from the front and the second from the back.  Each worker compiles its own family's kernels and
finds the other's in the cache when the two ends meet, and the files still run dynamically (a worker takes the
next file when it has run out), so neither waits while the other has work.  Files are weighed by their number of
tests, as xdist does, except the few whose handful of tests build something long (:data:`LONG`): those go to the
back end, so that none of them is left for the end, where one worker would run it while the other waits.

With more than two workers, even-numbered ones take from the front and odd-numbered ones from the back.  Where
xdist's scheduler lacks what this relies on, its own is used.
"""

from __future__ import annotations

from xdist.scheduler import LoadFileScheduling

#: a file of this family has it in its path
FAMILY = "structure"
#: files of few tests and a long build (the documentation with its gallery: about a minute)
LONG = ("tests/test_docs.py",)


def family_first(units: dict) -> dict:
    """The work units (file -> its tests) reordered: the family's files, most tests first, then the others,
    most tests last, and the :data:`LONG` ones after them."""
    ours = sorted((s for s in units if FAMILY in s), key=lambda s: -len(units[s]))
    rest = sorted((s for s in units if FAMILY not in s), key=lambda s: (s in LONG, len(units[s])))
    return {s: units[s] for s in ours + rest}


class TwoEnded(LoadFileScheduling):
    """:class:`LoadFileScheduling` whose workers take their files from the two ends of :func:`family_first`'s queue."""

    ordered = False

    def _assign_work_unit(self, node) -> None:
        if not self.ordered:
            reordered = family_first(dict(self.workqueue))
            self.workqueue.clear()
            self.workqueue.update(reordered)
            self.ordered = True
        if self.nodes.index(node) % 2 == 1:  # xdist hands out the front: bring the back there
            self.workqueue.move_to_end(next(reversed(self.workqueue)), last=False)
        super()._assign_work_unit(node)


def usable() -> bool:
    """xdist's scheduler has the parts :class:`TwoEnded` replaces and reads."""
    needed = ("_assign_work_unit", "_reschedule", "schedule")
    return all(hasattr(LoadFileScheduling, name) for name in needed)
