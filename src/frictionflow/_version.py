"""The installed distribution's version, in the lowest layer: the CLI and sweep provenance read it too."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("frictionflow")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0+unknown"
