"""The ``mobman`` command: one Typer application, one module per command group.

Every :class:`mobman.MobmanError` (and a bad option value) ends as one line on standard error and exit
status 2, never a traceback.
"""

from __future__ import annotations

import sys

import typer

from mobman.errors import MobmanError

app = typer.Typer(
    name="mobman",
    help="Kinematics, manipulability, control, planning and dynamics of nonholonomic mobile manipulators.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

# Each module registers its commands on ``app`` when imported.
from mobman.cli import analyze, dynamics, ellipsoid, plan, reproduce, robots, simulate, view  # noqa: E402,F401


def main(argv: list[str] | None = None) -> None:
    """Entry point of the console script."""
    try:
        app(args=argv, standalone_mode=False)
    except MobmanError as exc:
        typer.echo(f"error: {exc}", err=True)
        sys.exit(2)
    except typer.Abort:
        typer.echo("aborted", err=True)
        sys.exit(1)
    except Exception as exc:
        # Usage errors of the CLI library (click, vendored by recent Typer) are recognised by their interface,
        # so that no particular click import path is assumed.
        format_message = getattr(exc, "format_message", None)
        if callable(format_message):
            typer.echo(f"error: {format_message()}", err=True)
            sys.exit(2)
        exit_code = getattr(exc, "exit_code", None)
        if isinstance(exit_code, int):
            sys.exit(exit_code)
        raise
