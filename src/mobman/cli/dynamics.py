"""Placeholder: the `mobman dynamics` command lands with its issue (see the issue tracker)."""
