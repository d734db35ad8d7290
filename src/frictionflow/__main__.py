"""``python -m frictionflow``."""

from .cli import run

run()
