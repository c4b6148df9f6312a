"""Errors that growsim reports to the user as a clean message and exit code 2."""

from __future__ import annotations


class GrowsimError(Exception):
    """Base class for every error growsim reports to users.

    The command line catches it, prints ``growsim: error: <message>`` on stderr and exits
    with code 2; no traceback is shown.

    Examples
    --------
    >>> raise UserInputError("model.f: 1.5 is above the maximum 1.0")
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: model.f: 1.5 is above the maximum 1.0
    """

    exit_code = 2


class UserInputError(GrowsimError, ValueError):
    """Bad input: a config key, parameter value, image or path the user gave."""


class ConfigError(UserInputError):
    """A config that fails validation; the message names the key path."""


class ResourceError(GrowsimError):
    """A request that would need more memory or time than allowed (says how much)."""
