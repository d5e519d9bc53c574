"""Results written atomically, to a place checked before any work.

A results file is either the previous good one or the new complete one,
never a torn mixture: :func:`atomic_write` writes a temporary file in the
target's own folder (a hidden ``.NAME.XXXXXXXX.tmp``, an unpredictable name),
flushes it to disk, then renames it over
the target with :func:`os.replace`, which is atomic on one file system. On
any failure (a full disk, Ctrl-C, an exception) the temporary file is removed
and the target is untouched; only a SIGKILL or a power cut during the write
can leave a temporary file behind, and never a damaged target.

:func:`check_output` finds, before the work starts, what would stop the write
at its end: a missing or read-only folder, a target that is the input itself,
a directory, a device or a FIFO.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterable, Iterator
from typing import IO

from ..errors import OutputError, printable

__all__ = ["atomic_write", "check_output"]


def _reason(e: OSError) -> str:
    if e.strerror:
        return e.strerror
    return os.strerror(e.errno) if e.errno else (str(e) or type(e).__name__)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def check_output(path: str, inputs: Iterable[str] = ()) -> str:
    """Check that ``path`` can receive results, before any work; returns it unchanged.

    Raises :class:`~forceclosure.errors.OutputError` (one line) when its
    folder is missing, not a folder or not writable (tried by creating and
    removing a temporary file there), when it exists and is not a regular file
    (a directory, a device, a FIFO, a socket), or when it is one of ``inputs``
    (the same file, by :func:`os.path.samefile`, whatever the spelling), or when it is
    empty or ends with ``/`` (a folder's spelling, which ``abspath`` would silently drop).

    Examples
    --------
    >>> import os, tempfile
    >>> folder = tempfile.mkdtemp()
    >>> check_output(os.path.join(folder, "r.npz")) == os.path.join(folder, "r.npz")
    True
    >>> check_output(os.path.join(folder, "no", "r.npz"))
    Traceback (most recent call last):
    ...
    forceclosure.errors.OutputError: ...: the folder ... does not exist
    """
    shown = printable(path, 200)
    if not path:
        raise OutputError("the results file name is empty")
    if path.endswith(("/", os.sep)):  # abspath would drop the slash: x.npz/ is no file
        raise OutputError(f"{shown}: ends with '/', a folder; results go to a file")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        what = "is not a folder" if os.path.exists(folder) else "does not exist"
        raise OutputError(f"{shown}: the folder {printable(folder, 200)} {what}")
    try:
        target = os.stat(path)
    except FileNotFoundError:
        target = None
    except OSError as e:
        raise OutputError(f"{shown}: cannot use it for results: {_reason(e)}") from None
    if target is not None and not stat.S_ISREG(target.st_mode):
        kind = ("a folder" if stat.S_ISDIR(target.st_mode) else "a FIFO"
                if stat.S_ISFIFO(target.st_mode) else "a device"
                if stat.S_ISCHR(target.st_mode) or stat.S_ISBLK(target.st_mode) else "a socket"
                if stat.S_ISSOCK(target.st_mode) else "not a regular file")
        raise OutputError(f"{shown}: is {kind}; results go to a regular file")
    for source in inputs:
        if target is not None and os.path.exists(source) and os.path.samefile(path, source):
            raise OutputError(f"{shown}: is the input file; write the results elsewhere")
    try:
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".forceclosure-probe-")
    except OSError as e:
        raise OutputError(f"{shown}: cannot write in {printable(folder, 200)}: "
                          f"{_reason(e)}") from None
    os.close(fd)
    os.unlink(probe)
    return path


@contextlib.contextmanager
def atomic_write(path: str) -> Iterator[IO[bytes]]:
    """A binary file to write ``path`` through, atomically: the target is replaced only when
    the ``with`` block ends without an exception (including ``KeyboardInterrupt``).

    A full disk or any other ``OSError`` becomes one
    :class:`~forceclosure.errors.OutputError` line; the temporary file is
    removed and the previous ``path``, if any, is left as it was.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "out.bin")
    >>> with atomic_write(path) as f:
    ...     _ = f.write(b"complete")
    >>> open(path, "rb").read()
    b'complete'
    >>> with atomic_write(path) as f:
    ...     _ = f.write(b"torn")
    ...     raise RuntimeError("stopped half-way")
    Traceback (most recent call last):
    ...
    RuntimeError: stopped half-way
    >>> open(path, "rb").read(), os.listdir(os.path.dirname(path))
    (b'complete', ['out.bin'])
    """
    folder, name = os.path.split(os.path.abspath(path))
    shown = printable(path, 200)
    try:
        fd, temp = tempfile.mkstemp(dir=folder, prefix=f".{name[:100]}.", suffix=".tmp")
    except OSError as e:
        raise OutputError(f"{shown}: cannot write: {_reason(e)}") from None
    try:
        os.fchmod(fd, 0o666 & ~_umask())  # as an ordinary new file, not mkstemp's 0600
        with os.fdopen(fd, "wb") as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(temp, path)
    except BaseException as e:
        with contextlib.suppress(OSError):
            os.unlink(temp)
        if isinstance(e, OSError):
            raise OutputError(f"{shown}: cannot write: {_reason(e)}; the previous file, if "
                              "any, is unchanged") from None
        raise
