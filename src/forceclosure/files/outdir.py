"""The results folder of a run: files written atomically, and one run at a time.

Every file a run writes goes through :func:`atomic_file`: a temporary file
of unpredictable name in the target's folder, synced, then renamed over the
target, so a reader (or a later run) sees the old file or the new one,
never a part, even when the run is killed or the disk fills up (the
temporary file is removed then). :func:`locked` holds the folder for one
run at a time (``flock``: the kernel releases it when its holder dies,
however it dies).
"""

from __future__ import annotations

import os
import socket
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import IO

from ..errors import InputError

__all__ = ["atomic_file", "locked", "remove_temporaries", "write_atomically"]


@contextmanager
def atomic_file(path: Path) -> Iterator[IO[bytes]]:
    """A binary file that becomes ``path`` only once fully written and synced.

    A temporary file ``.<name>.<random>.tmp`` in the same folder, renamed
    over ``path`` at the end; removed if anything fails (a full disk, say),
    leaving ``path`` as it was.

    Examples
    --------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_file(path) as f:
    ...     _ = f.write(b"whole")
    >>> path.read_text(), [p.name for p in path.parent.iterdir()]
    ('whole', ['a.txt'])
    """
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            os.fchmod(f.fileno(), 0o644)
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with suppress(OSError):
            os.unlink(tmp)
        raise


def write_atomically(path: Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` through :func:`atomic_file`.

    Examples
    --------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "r.json"
    >>> write_atomically(path, "{}")
    >>> path.read_text()
    '{}'
    """
    with atomic_file(path) as f:
        f.write(text.encode("utf-8"))


def remove_temporaries(folders: Iterable[Path]) -> None:
    """Remove the temporary files :func:`atomic_file` left in ``folders`` (a run killed
    while writing); call it only while holding the lock, when no run is writing.

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / ".r.json.x1y2.tmp").write_text("half")
    >>> remove_temporaries([folder]); list(folder.iterdir())
    []
    """
    for folder in folders:
        for tmp in folder.glob(".*.tmp"):
            with suppress(OSError):
                tmp.unlink()


@contextmanager
def locked(folder: Path, what: str = "--out") -> Iterator[None]:
    """Hold ``folder/.lock`` (``flock``, with this process's pid and host in it), or refuse
    in one line naming its holder.

    The kernel releases the lock when its holder dies, however it dies, so
    a killed run never leaves the folder locked. (``flock`` may not lock
    across machines on some network file systems.)

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> with locked(folder):
    ...     try:
    ...         with locked(folder):
    ...             pass
    ...     except InputError as e:
    ...         print(str(e).split(": ")[1].split(" (")[0])
    another run
    """
    import fcntl

    fd = os.open(folder / ".lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 200, 0).decode("utf-8", "replace").split()
            who = f" (pid {holder[0]} on {holder[1]})" if len(holder) >= 2 else ""
            raise InputError(f"{what} {folder}: another run{who} is writing there; wait for "
                             f"it to end, or use another {what}") from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()} {socket.gethostname()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)
