"""``frictionflow reproduce``: registered by this module (under construction)."""
