"""Placeholder: the `mobman simulate` command lands with its issue (see the issue tracker)."""
