"""Errors raised by forceclosure.

Every error a user can cause is an :class:`InputError` whose message is one
line naming the problem and where it is (which grasp, which contact, which
field). The command-line tool prints that line and exits with status 2.
"""

from __future__ import annotations


class ForceClosureError(Exception):
    """Base class of the library's own errors."""


class InputError(ForceClosureError, ValueError):
    """Bad input: the message names the problem and where it is, in one line."""

    def within(self, where: str) -> InputError:
        """The same error, its message prefixed by a location such as ``grasp 2``."""
        return InputError(f"{where}: {self}")
