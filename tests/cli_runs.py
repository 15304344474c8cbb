"""``mobman ARGS`` run in the test's own process (the command line's ``main``, as the console script calls it)."""

from __future__ import annotations

from mobman.cli import main


def run_cli(args: list[str], capsys) -> tuple[int, str, str]:
    """Exit status, standard output and standard error of ``mobman ARGS``."""
    try:
        main(args)
        code = 0
    except SystemExit as exc:
        code = exc.code
    captured = capsys.readouterr()
    return code, captured.out, captured.err
