"""Cached kernels are dropped when any kernel source changes, not only their own file."""

from __future__ import annotations

from frictionflow.core import _cache


def _fill(d, names):
    d.mkdir(parents=True, exist_ok=True)
    for n in names:
        (d / n).write_bytes(b"x")


def test_stale_kernels_of_the_package_are_removed_and_others_kept(tmp_path):
    d = tmp_path / "__pycache__"
    _fill(d, ["dopri.run-95.py311.nbi", "dopri.run-95.py311.1.nbc", "stribeck.magnitude-20.py311.nbi",
              "theirs.f-1.py311.nbi", "dopri.cpython-311.pyc"])
    removed = _cache.drop_stale({d}, {"dopri", "stribeck"}, "digest-1")
    assert removed == 3
    assert sorted(p.name for p in d.iterdir()) == sorted(["theirs.f-1.py311.nbi", "dopri.cpython-311.pyc", _cache.STAMP])
    assert (d / _cache.STAMP).read_text() == "digest-1"


def test_kernels_compiled_from_the_same_sources_are_kept(tmp_path):
    d = tmp_path / "__pycache__"
    _fill(d, ["dopri.run-95.py311.nbi"])
    (d / _cache.STAMP).write_text("digest-1")
    assert _cache.drop_stale({d}, {"dopri"}, "digest-1") == 0
    assert (d / "dopri.run-95.py311.nbi").exists()
    assert _cache.drop_stale({d}, {"dopri"}, "digest-2") == 1  # one law module edited: everything recompiles


def test_the_digest_covers_the_law_modules_and_the_quantities_table():
    names = {p.name for p in _cache.kernel_sources()}
    assert {"stribeck.py", "cubic.py", "friction.py", "dopri.py", "quantities.py"} <= names
    files = _cache.kernel_sources()
    assert _cache.sources_digest(files) != _cache.sources_digest(files[:-1])


def test_every_kernel_source_is_stamped_subpackages_included():
    """A kernel in a subpackage of core (the structure engine) inlines its siblings: editing one must drop it too."""
    core = _cache.PACKAGE / "core"
    stamped = set(_cache.kernel_sources())
    assert set(core.rglob("*.py")) <= stamped
    assert core / "structure" / "phase.py" in stamped
