"""The ``mobman`` command: one Typer application, one module per command group.

Every :class:`mobman.MobmanError` (and a bad option value) ends as one line on standard error and exit
status 2, never a traceback; see :data:`mobman.cli.app.EXIT_CODES` for the others. The command keeps its
compiled programs between runs (:mod:`mobman.engine.compilation_cache`, ``MOBMAN_CACHE_DIR``).
"""

from __future__ import annotations

import os
import sys

import typer

# Each module registers its commands on ``app`` when imported.
from mobman.cli import (  # noqa: F401
    analyze,
    distance,
    dynamics,
    ellipsoid,
    export_mjcf,
    maps,
    place,
    plan,
    reproduce,
    robots,
    simulate,
    sweep,
    view,
)
from mobman.cli.app import INTERRUPTED, app
from mobman.engine import compilation_cache, exported
from mobman.errors import MobmanError
from mobman.io import urdf_cache


def _one_line(text: str) -> str:
    """``text`` on one line: every line break (also those of a file's odd key names) becomes a space."""
    return " ".join(text.split())


def _command(argv: list[str] | None) -> str:
    words = sys.argv[1:] if argv is None else argv
    return next((w for w in words if not w.startswith("-")), "")


def main(argv: list[str] | None = None) -> None:
    """Entry point of the console script; the exit status is that of :data:`EXIT_CODES`. The command keeps its
    compiled and exported programs and its URDF readings between runs (:mod:`mobman.engine.exported`,
    :mod:`mobman.io.urdf_cache`), for its own calls only."""
    command = _command(argv)
    try:
        folder = compilation_cache.enable()
        exported.enable(None if os.environ.get(exported.ENVIRONMENT, "").strip().lower() == "off" else folder)
        urdf_cache.enable(folder)
    except MobmanError as exc:  # the command still runs, compiling every program
        typer.echo(f"warning: {_one_line(str(exc))}", err=True)
    try:
        _run(argv, command)
    finally:
        exported.disable()
        urdf_cache.disable()


def _run(argv: list[str] | None, command: str) -> None:
    try:
        code = app(args=argv, standalone_mode=False)
    except MobmanError as exc:
        typer.echo(f"error: {_one_line(str(exc))}", err=True)
        sys.exit(2)
    except typer.Abort:
        typer.echo("aborted", err=True)
        sys.exit(1)
    except KeyboardInterrupt:
        code = INTERRUPTED
    except Exception as exc:
        # Usage errors of the CLI library (click, vendored by recent Typer) are recognised by their interface,
        # so that no particular click import path is assumed.
        format_message = getattr(exc, "format_message", None)
        if callable(format_message):
            typer.echo(f"error: {_one_line(format_message())}", err=True)
            sys.exit(2)
        exit_code = getattr(exc, "exit_code", None)
        if isinstance(exit_code, int):
            sys.exit(exit_code)
        text = _one_line(str(exc)) or "(no message)"
        typer.echo(
            f"error: mobman {command} failed unexpectedly ({type(exc).__name__}: {text[:300]}); please report "
            "this with the command line that produced it",
            err=True,
        )
        sys.exit(1)
    if code == INTERRUPTED:
        typer.echo(f"interrupted: mobman {command} stopped; partial output removed", err=True)
    if isinstance(code, int) and code:
        sys.exit(code)
