"""Errors raised by forceclosure.

Every error a user can cause is an :class:`InputError` whose message is one
line naming the problem and where it is (which grasp, which contact, which
field). The command-line tool prints that line and exits with status 2.
"""

from __future__ import annotations

import json
from typing import Any


class ForceClosureError(Exception):
    """Base class of the library's own errors."""


class InputError(ForceClosureError, ValueError):
    """Bad input: the message names the problem and where it is, in one line."""

    def within(self, where: str) -> InputError:
        """The same error, its message prefixed by a location such as ``grasp 2``."""
        return InputError(f"{where}: {self}")


def first_line(error: BaseException) -> str:
    """The first line of an exception's message (at most 200 characters), or its type's name.

    Examples
    --------
    >>> first_line(ValueError("bad number\\nmore detail"))
    'bad number'
    """
    text = str(error).strip().splitlines()
    return (text[0] if text else type(error).__name__)[:200]


def parse_json(text: str, source: str) -> Any:
    """``json.loads``, with a malformed document as one :class:`InputError` line."""
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise InputError(f"{source}: not valid JSON: {e.msg} at line {e.lineno}, "
                         f"column {e.colno}") from None
    except RecursionError:
        raise InputError(f"{source}: not valid JSON: nested too deeply") from None
