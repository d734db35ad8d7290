"""``frictionflow sweep``: registered by this module (under construction)."""
