"""Progress a person reads when no terminal shows a bar: a line at intervals.

A ``dataset`` run whose standard error is a terminal shows a progress bar;
piped or redirected (a log file, a batch job), it prints instead one line
every :data:`EVERY` seconds (``FORCECLOSURE_PROGRESS_SECONDS`` changes it)
as objects finish: how many of how many, the rate of this run and the time
left at that rate::

    forceclosure: 120/1000 objects (12%), 3.4 objects/s, about 4 min 19 s left
"""

from __future__ import annotations

import math
import os
import shutil
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ..errors import InputError

__all__ = ["ENVIRONMENT", "EVERY", "ProgressLines", "bar_size", "duration",
           "every_from_environment"]

#: Seconds between two progress lines, by default.
EVERY = 10.0
#: The environment variable that sets the seconds between two progress lines (``inf``: none).
ENVIRONMENT = "FORCECLOSURE_PROGRESS_SECONDS"


def every_from_environment() -> float:
    """The seconds between progress lines: ``FORCECLOSURE_PROGRESS_SECONDS`` if set (a
    number >= 0; ``inf`` for no lines), else :data:`EVERY`.

    Examples
    --------
    >>> every_from_environment() >= 0
    True
    """
    text = os.environ.get(ENVIRONMENT)
    if text is None or not text.strip():
        return EVERY
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not value >= 0:
        raise InputError(f"{ENVIRONMENT}: must be a number of seconds >= 0 (inf: no "
                         f"progress lines), got {text[:40]!r}")
    return value


def bar_size(stream: Any = None) -> dict[str, int]:
    """The size of a progress bar drawn on ``stream`` (standard error by default), as
    tqdm's keyword arguments: none when it is a terminal that says its size, or no
    terminal (tqdm measures the one, and draws nothing on the other); else -- a
    terminal of 0 columns and rows, as a pseudo-terminal nobody sized says --
    ``ncols`` and ``nrows`` from ``COLUMNS`` and ``LINES``, or 80 by 24.

    tqdm (``disable=None``) draws its bar when its file, standard error, is a
    terminal, whatever standard output is; on a terminal of size 0 it drew
    nothing but a line end: no progress at all.

    Examples
    --------
    >>> import io
    >>> bar_size(io.StringIO())   # not a terminal
    {}
    """
    stream = sys.stderr if stream is None else stream
    try:
        size = os.get_terminal_size(stream.fileno())
    except (AttributeError, OSError, ValueError):
        return {}
    if size.columns > 0 and size.lines > 0:
        return {}
    fallback = shutil.get_terminal_size((80, 24))
    return {"ncols": size.columns if size.columns > 0 else fallback.columns or 80,
            "nrows": size.lines if size.lines > 0 else fallback.lines or 24}


def duration(seconds: float) -> str:
    """A duration for people: ``42 s``, ``4 min 19 s``, ``2 h 05 min``.

    Examples
    --------
    >>> duration(42.4), duration(259), duration(7500), duration(0.2)
    ('42 s', '4 min 19 s', '2 h 05 min', '0 s')
    """
    s = round(seconds)
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60} min {s % 60} s"
    return f"{s // 3600} h {s // 60 % 60:02d} min"


@dataclass
class ProgressLines:
    """Count finished objects and say a progress line when ``every`` seconds have passed
    since the last line (or the start): ``every=0`` says one per update.

    ``clock`` gives the time in seconds (:func:`time.monotonic`; a test gives
    its own), read when the counter is made and at each update.

    Examples
    --------
    >>> ticks = iter([0.0, 5.0, 12.0, 13.0])
    >>> lines = ProgressLines(4, print, every=10.0, clock=lambda: next(ticks))
    >>> lines.update()          # at 5 s: too soon
    >>> lines.update()          # at 12 s: 2 done in 12 s
    forceclosure: 2/4 objects (50%), 0.167 objects/s, about 12 s left
    >>> lines.update()          # at 13 s: 1 s after the last line
    """

    total: int
    say: Callable[[str], object]
    every: float = EVERY
    clock: Callable[[], float] = time.monotonic
    what: str = "objects"
    done: int = 0
    start: float = field(init=False)
    last: float = field(init=False)

    def __post_init__(self) -> None:
        self.start = self.last = self.clock()

    def update(self, n: int = 1) -> None:
        """``n`` more objects finished; a line if it is time for one."""
        self.done += n
        now = self.clock()
        if now - self.last >= self.every:
            self.last = now
            self.say(self.line(now))

    def line(self, now: float) -> str:
        """The progress line at time ``now``."""
        share = 100.0 * self.done / self.total if self.total else 100.0
        text = f"forceclosure: {self.done}/{self.total} {self.what} ({share:.0f}%)"
        elapsed = now - self.start
        if elapsed <= 0 or self.done == 0:
            return text
        rate = self.done / elapsed
        text += f", {rate:.3g} {self.what}/s"
        left = self.total - self.done
        if left > 0:
            text += f", about {duration(left / rate)} left"
        return text
