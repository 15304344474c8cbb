"""The exception family of mobman.

Every error that mobman raises on purpose is a :class:`MobmanError`; the command line turns
one into a single line on standard error and exit status 2.
"""

from __future__ import annotations

from typing import Any


class MobmanError(Exception):
    """Base class of every error mobman raises on purpose."""


class ModelError(MobmanError, ValueError):
    """An invalid robot, task or parameter description (names the field and the allowed range)."""


class InputError(MobmanError, ValueError):
    """Invalid user input: a configuration of the wrong size, a NaN, an unreadable file."""


class SingularConfigurationError(MobmanError):
    """A computation that needs a regular configuration met a singular one."""


class InfeasibleTaskError(MobmanError):
    """An operational velocity that no admissible generalized velocity realises (inconsistent ξ̇)."""


class ConvergenceError(MobmanError):
    """An iterative algorithm did not converge; ``history`` holds what it did."""

    def __init__(self, message: str, history: Any = None):
        super().__init__(message)
        self.history = history
