"""The Typer application of the ``mobman`` command, on which each command module registers its commands."""

import typer

app = typer.Typer(
    name="mobman",
    help="Kinematics, manipulability, control, planning and dynamics of nonholonomic mobile manipulators.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
