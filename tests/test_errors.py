"""The exception family of mobman.errors: every error is a MobmanError, the invalid-description and
invalid-input errors are also ValueErrors, ConvergenceError carries its history, and the command line turns
any of them into one line on standard error and exit status 2."""

from __future__ import annotations

import pytest

import mobman
from mobman import errors
from mobman.dynamics.load_capacity import InfeasibleMotionError

ALL = (
    errors.ModelError,
    errors.InputError,
    errors.SingularConfigurationError,
    errors.InfeasibleTaskError,
    errors.ConvergenceError,
    InfeasibleMotionError,
)
VALUE_ERRORS = (errors.ModelError, errors.InputError, InfeasibleMotionError)
NOT_VALUE_ERRORS = (errors.SingularConfigurationError, errors.InfeasibleTaskError, errors.ConvergenceError)


def test_the_base_class_is_an_exception_and_not_a_value_error():
    assert issubclass(errors.MobmanError, Exception)
    assert not issubclass(errors.MobmanError, ValueError)


@pytest.mark.parametrize("cls", ALL, ids=lambda c: c.__name__)
def test_every_error_is_a_mobman_error(cls):
    assert issubclass(cls, errors.MobmanError)
    with pytest.raises(errors.MobmanError, match="the message"):
        raise cls("the message")


@pytest.mark.parametrize("cls", VALUE_ERRORS, ids=lambda c: c.__name__)
def test_invalid_descriptions_and_inputs_are_value_errors(cls):
    with pytest.raises(ValueError):
        raise cls("bad")


@pytest.mark.parametrize("cls", NOT_VALUE_ERRORS, ids=lambda c: c.__name__)
def test_computational_failures_are_not_value_errors(cls):
    assert not issubclass(cls, ValueError)


def test_model_and_input_errors_are_distinct():
    assert not issubclass(errors.ModelError, errors.InputError)
    assert not issubclass(errors.InputError, errors.ModelError)
    assert issubclass(InfeasibleMotionError, errors.ModelError)


def test_convergence_error_keeps_its_history():
    history = {"errors": [1.0, 0.1, 0.01]}
    exc = errors.ConvergenceError("no convergence after 3 iterations", history)
    assert str(exc) == "no convergence after 3 iterations"
    assert exc.history is history
    assert errors.ConvergenceError("stopped").history is None
    assert errors.ConvergenceError("stopped", history=[2.0]).history == [2.0]


@pytest.mark.parametrize(
    "name",
    [
        "MobmanError",
        "ModelError",
        "InputError",
        "SingularConfigurationError",
        "InfeasibleTaskError",
        "ConvergenceError",
    ],
)
def test_the_package_exports_the_same_classes(name):
    assert getattr(mobman, name) is getattr(errors, name)
    assert name in mobman.__all__


@pytest.mark.parametrize("cls", ALL, ids=lambda c: c.__name__)
def test_the_command_line_prints_one_line_and_exits_2(cls, monkeypatch, capsys):
    import mobman.cli

    def failing(**_):
        raise cls("robot r: length must be > 0,\ngot -1")

    monkeypatch.setattr(mobman.cli, "app", failing)
    with pytest.raises(SystemExit) as info:
        mobman.cli.main(["analyze"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.splitlines() == ["error: robot r: length must be > 0, got -1"]


def test_an_unexpected_exception_is_not_exit_2(monkeypatch, capsys):
    """Only mobman's own errors are bad input: any other exception is exit 1 and asks for a report."""
    import mobman.cli

    def failing(**_):
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr(mobman.cli, "app", failing)
    with pytest.raises(SystemExit) as info:
        mobman.cli.main(["analyze"])
    assert info.value.code == 1
    assert "please report" in capsys.readouterr().err
