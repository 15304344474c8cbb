"""The `mobman` command itself (mobman.cli.app): help, and bad usage as one line with exit status 2."""

import subprocess
import sys

import pytest

from mobman.cli import main


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["reproduce", "no-such-paper"], "unknown reproduction"),
        (["analyze"], "ROBOT"),
        (["no-such-command"], ""),
    ],
)
def test_bad_usage_is_one_line_and_exit_status_2(argv, needle, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and len(err.splitlines()) == 1 and needle in err


def test_help_lists_the_commands(capsys):
    try:
        main(["--help"])
    except SystemExit as exc:  # depending on the CLI library's version, help may exit with status 0
        assert exc.code == 0
    assert "reproduce" in capsys.readouterr().out


def test_starting_the_command_imports_no_optional_or_plotting_library():
    """Every `mobman` command imports mobman.cli: the libraries only some commands use (matplotlib for
    figures, the extras' viser, yourdfpy, Zarr and Dask, SymPy for --symbolic) are imported by those
    commands, so the others start without paying for them."""
    heavy = ("matplotlib", "sympy", "viser", "yourdfpy", "zarr", "dask", "pinocchio")
    code = f"import sys, mobman.cli; print(','.join(m for m in {heavy!r} if m in sys.modules))"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.strip() == ""
