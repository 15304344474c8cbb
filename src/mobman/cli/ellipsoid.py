"""Placeholder: the `mobman ellipsoid` command lands with its issue."""
