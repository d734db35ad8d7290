"""Keep numba's on-disk cache of the kernels consistent with all their sources.

numba keys a cached kernel on its own source file only, but the kernels
inline functions and read constants from other modules (each law's slip force
in :mod:`frictionflow.friction`, the quantities table).  Editing one of those
would leave kernels compiled from the old code in the cache.  So the package
keeps a digest of every kernel source beside the cached kernels, and when it
differs from the sources', it removes the package's cached kernels before any
is loaded: they compile again, once.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent
#: every source a compiled kernel reads
SOURCE_DIRS = ("core", "friction")
SOURCE_FILES = ("quantities.py",)
STAMP = "frictionflow-kernels.sha256"


def kernel_sources() -> list[Path]:
    files = [p for d in SOURCE_DIRS for p in sorted((PACKAGE / d).rglob("*.py"))]  # core/structure/ too
    return files + [PACKAGE / f for f in SOURCE_FILES]


def sources_digest(files: list[Path]) -> str:
    h = hashlib.sha256()
    for f in files:
        h.update(f.name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()


def cache_dirs(files: list[Path]) -> set[Path]:
    """Where numba keeps the cached kernels of these sources: the first of its locators that applies, as numba picks."""
    from numba.core import caching

    def probe() -> None:  # numba's locators read only the line number of the function
        pass

    dirs = set()
    for f in files:
        for cls in caching.CacheImpl._locator_classes:
            try:
                loc = cls.from_function(probe, str(f))
            except Exception:  # a locator that does not apply to plain source files
                continue
            if loc is not None:
                dirs.add(Path(loc.get_cache_path()))
                break
    return dirs


def drop_stale(dirs: set[Path], stems: set[str], digest: str) -> int:
    """Remove cached kernels of modules ``stems`` from ``dirs`` whose stamp is not ``digest``; returns files removed."""
    removed = 0
    for d in dirs:
        stamp = d / STAMP
        try:
            if stamp.read_text() == digest:
                continue
        except OSError:
            pass
        if not d.is_dir():
            continue
        for f in d.iterdir():
            if f.suffix in (".nbi", ".nbc") and f.name.split(".", 1)[0] in stems:
                f.unlink(missing_ok=True)
                removed += 1
        try:
            stamp.write_text(digest)
        except OSError:  # a read-only cache: numba will not write there either
            pass
    return removed


def refresh() -> None:
    """Drop cached kernels compiled from other sources than these (cheap: one hash of the sources)."""
    files = kernel_sources()
    try:
        drop_stale(cache_dirs(files), {f.stem for f in files}, sources_digest(files))
    except OSError:
        pass  # never stop the package from importing over its cache
