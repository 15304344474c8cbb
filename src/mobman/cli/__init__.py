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
from mobman.cli import analyze, dynamics, ellipsoid, plan, reproduce, robots, simulate  # noqa: E402,F401


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
    except Exception as exc:  # click usage errors carry their own exit code
        import click

        if isinstance(exc, click.exceptions.ClickException):
            typer.echo(f"error: {exc.format_message()}", err=True)
            sys.exit(2)
        if isinstance(exc, click.exceptions.Exit):
            sys.exit(exc.exit_code)
        raise
