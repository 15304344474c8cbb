"""Placeholder: the `mobman analyze` command lands with its issue (see the issue tracker)."""
