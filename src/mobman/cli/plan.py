"""Placeholder: the `mobman plan` command lands with its issue (see the issue tracker)."""
