"""Errors raised by forceclosure.

Every error a user can cause is an :class:`InputError` whose message is one
line naming the problem and where it is (which grasp, which contact, which
field). The command-line tool prints that line and exits with status 2.
"""

from __future__ import annotations

import json
import re
from typing import Any

__all__ = ["SHOWN", "ForceClosureError", "InputError", "OutputError", "clip", "first_line",
           "parse_json", "printable", "shown"]

#: How much of an offending value an error line shows.
SHOWN = 200


class ForceClosureError(Exception):
    """Base class of the library's own errors."""


class InputError(ForceClosureError, ValueError):
    """Bad input: the message names the problem and where it is, in one line."""

    def within(self, where: str) -> InputError:
        """The same error, its message prefixed by a location such as ``grasp 2``."""
        return type(self)(f"{where}: {self}")


class OutputError(InputError):
    """The results cannot be written where asked (a missing or read-only folder, the input
    itself, a device, a full disk): one line, exit status 2, earlier results untouched."""


def clip(text: str, limit: int = SHOWN) -> str:
    """``text``, cut to ``limit`` characters with a note of how long it was.

    Examples
    --------
    >>> clip("x" * 1000, 10)
    'xxxxxxxxxx... (1,000 characters)'
    >>> clip("short")
    'short'
    """
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text):,} characters)"


def shown(value: Any, limit: int = SHOWN) -> str:
    """A bad value as an error line shows it: its JSON text, cut to ``limit`` characters.

    Examples
    --------
    >>> shown([1, "a"])
    '[1, "a"]'
    >>> shown(list(range(1000)), 12)
    '[0, 1, 2, 3,... (4,890 characters)'
    """
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return clip(text, limit)


# C0 and C1 controls (newline, ESC of ANSI sequences, DEL), line and paragraph separators,
# bidirectional overrides, and lone surrogates (which UTF-8 cannot encode)
_UNPRINTABLE = re.compile(r"[\x00-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069"
                          r"\ud800-\udfff]")


def printable(text: str, limit: int | None = None) -> str:
    """``text`` safe for a terminal line: control characters, ANSI escapes, separators,
    bidirectional overrides and lone surrogates written as ``\\xNN`` / ``\\uNNNN``; cut to
    ``limit`` characters if given. The one rule for every line forceclosure prints or logs
    with a user's text in it (the CLI's messages, the dataset's log lines), so that no file
    name can forge, colour or reorder a line.

    Examples
    --------
    >>> printable("evil\\nforged \\x1b[31mred\\ud800")
    'evil\\\\nforged \\\\x1b[31mred\\\\ud800'
    >>> print(printable("a\\tb"))
    a\\x09b
    """
    def escape(m: re.Match[str]) -> str:
        c = ord(m.group())
        return "\\n" if c == 10 else f"\\x{c:02x}" if c < 0x100 else f"\\u{c:04x}"

    text = text if limit is None else clip(text, limit)
    return _UNPRINTABLE.sub(escape, text)


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
        return json.loads(text, parse_int=_parse_int)
    except json.JSONDecodeError as e:
        raise InputError(f"{source}: not valid JSON: {e.msg} at line {e.lineno}, "
                         f"column {e.colno}") from None
    except RecursionError:
        raise InputError(f"{source}: not valid JSON: nested too deeply") from None


def _parse_int(digits: str) -> int | float:
    """A JSON integer: exact up to 300 digits, else as a float (``inf`` beyond the largest),
    which the fields' own checks then refuse; never Python's error for 4,300 digits, nor an
    ``OverflowError`` where a float is made of it."""
    return int(digits) if len(digits) <= 300 else float(digits)
