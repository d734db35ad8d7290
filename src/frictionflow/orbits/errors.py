"""The orbits' own error: shooting found no periodic orbit (shared by the section-map and the whole-state shooting)."""

from __future__ import annotations


class ShootingError(RuntimeError):
    """Newton shooting did not find a periodic orbit from the given start."""
