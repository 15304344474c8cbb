"""The Typer application of the ``mobman`` command, on which each command module registers its commands, and
the command's exit status."""

import typer

EXIT_CODES = {
    0: "success",
    1: "unexpected failure (one line naming the command; please report it)",
    2: "bad input: an option, a file or an output folder (one line naming the field)",
    3: "the run finished without reaching its goal (final error above the tolerance, not converged, outside the "
    "joint limits, no base, unbounded); results written",
    130: "interrupted (Ctrl-C); partial output removed",
}
"""Exit status of the ``mobman`` command."""

NOT_REACHED = 3
INTERRUPTED = 130

app = typer.Typer(
    name="mobman",
    help="Kinematics, manipulability, control, planning and dynamics of nonholonomic mobile manipulators.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
