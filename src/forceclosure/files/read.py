"""A user's input file, checked before it is read.

Only regular files are read: a FIFO would block forever, a device such as
``/dev/zero`` never ends, a symlink loop never resolves. Each is refused in
one :class:`~forceclosure.errors.InputError` line, and text is read up to a
stated cap, so memory stays bounded by the data actually present. A file's
:func:`fingerprint` (its content hash) names the input results came from.
"""

from __future__ import annotations

import hashlib
import os
import stat
import sys

from ..errors import InputError, printable

__all__ = ["TEXT_CAP", "fingerprint", "read_text", "regular_file"]

#: The largest JSON grasp file read (64 MiB); larger grasp sets go in ``.npz`` files.
TEXT_CAP = 64 * 2**20


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def regular_file(path: str) -> int:
    """The size in bytes of ``path``, a regular file (symlinks followed); else one
    :class:`~forceclosure.errors.InputError` line saying what it is.

    Examples
    --------
    >>> regular_file("/dev/zero")
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: /dev/zero: is a device, not a file to read
    """
    shown = printable(path, 200)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"{shown}: no such file") from None
    except OSError as e:  # a symlink loop (ELOOP), a name too long, no permission
        raise InputError(f"{shown}: cannot read: {e.strerror or type(e).__name__}") from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(f"{shown}: is {_kind(info.st_mode)}, not a file to read")
    return info.st_size


def read_text(path: str, cap: int = TEXT_CAP, what: str = "a text file") -> str:
    """The UTF-8 text of a regular file (``-``: standard input), refused past ``cap`` bytes.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "g.json")
    >>> _ = open(path, "w").write("{}" + " " * 100)
    >>> read_text(path, cap=10)
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: ...g.json: larger than 10 bytes, the most read from a text file
    """
    shown = printable(path, 200)
    if path == "-":
        stdin = getattr(sys.stdin, "buffer", None)  # a text stream stands in for it in tests
        data = stdin.read(cap + 1) if stdin is not None else sys.stdin.read(cap + 1).encode(
            "utf-8", "surrogatepass")
    else:
        regular_file(path)
        try:
            with open(path, "rb") as f:
                if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):  # replaced since the check
                    raise InputError(f"{shown}: is not a regular file")
                data = f.read(cap + 1)
        except OSError as e:
            raise InputError(f"{shown}: cannot read: {e.strerror or type(e).__name__}") from None
    if len(data) > cap:
        size = f"{cap / 2**20:g} MiB" if cap >= 2**20 else f"{cap} bytes"
        raise InputError(f"{shown}: larger than {size}, the most read from {what}")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{shown}: not a text file (expected UTF-8)") from None


def fingerprint(path: str) -> str:
    """The content hash of a file, ``sha256:<hex>`` (about 1 GB/s): the identity of an
    input that results were computed from.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "empty")
    >>> _ = open(path, "wb").close()
    >>> fingerprint(path)[:20]
    'sha256:e3b0c44298fc1'
    """
    regular_file(path)
    try:
        with open(path, "rb") as f:
            return "sha256:" + hashlib.file_digest(f, "sha256").hexdigest()
    except OSError as e:
        raise InputError(f"{printable(path, 200)}: cannot read: "
                         f"{e.strerror or type(e).__name__}") from None
