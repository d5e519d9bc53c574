"""The ``forceclosure`` command.

``forceclosure analyze FILE`` reads a grasp file (one grasp or many; see
``forceclosure/schemas/grasp-file.schema.json``) and says, for each grasp, whether it is
force-closure, what failed, and which motion nothing resists;
``--json`` prints the same for machines. ``forceclosure demo`` analyses the
bundled examples.

Exit status: 0 when every grasp was analysed, 2 when the input (or one grasp
of it) was bad, or the results could not be written — each problem reported
in one line, the good grasps still analysed — 130 when interrupted (Ctrl-C;
``analyze FILE.npz --out`` then saves the grasps done, to be resumed), and 1
on an internal error.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from typing import NoReturn

from .. import __version__
from ..errors import InputError, clip, printable
from ..tolerance import TOLERANCE
from . import (
    cmd_analyze,
    cmd_constructions,
    cmd_dataset,
    cmd_demo,
    cmd_grasps,
    cmd_inspect,
    cmd_objects,
    cmd_synthesize,
    cmd_warmup,
    export_cmd,
)
from .cmd_analyze import ANY_POSITIVE
from .common import error
from .dataset_options import DEFAULT_F_MAX

__all__ = ["ANY_POSITIVE", "COMMANDS", "DEFAULT_F_MAX", "FLAGS", "SWITCHES", "as_flags",
           "build_parser", "main"]

#: The command modules, in the order ``forceclosure --help`` lists them: each registers its
#: subcommand (``add_parser``) and runs it (``run``). Modules import numpy, scipy and the
#: library where a command needs them, so that ``forceclosure --help`` answers at once.
COMMANDS = (cmd_analyze, cmd_demo, cmd_warmup, cmd_objects, cmd_constructions, cmd_inspect,
            cmd_synthesize, cmd_dataset, cmd_grasps, export_cmd)

#: The library's errors name its parameters (``fingers=2, contact='hard': ...``, ``mu must
#: be ...``); the command line says them as its flags. The one table from the one to the
#: other, applied by :func:`as_flags` to every input error :func:`main` prints.
FLAGS = {"fingers": "--fingers", "contact": "--contact", "mu": "--mu", "top": "--top",
         "method": "--method", "construction": "--construction", "margin": "--margin",
         "samples": "--samples", "seed": "--seed"}

#: Parameters that a ``--no-...`` flag turns off: ``least_friction=False`` is
#: ``--no-least-friction``.
SWITCHES = {"least_friction": "--no-least-friction", "epsilon": "--no-epsilon"}

_NAMES = "|".join(FLAGS)

_ASSIGNED = re.compile(rf"(?<![-\w.])({_NAMES})=('[^']*'|[^\s,:;()']+)(, (?=(?:{_NAMES})=))?")

_SWITCHED = re.compile(rf"(?<![-\w.])({'|'.join(SWITCHES)})=False\b")

_SUBJECT = re.compile(rf"({_NAMES}) must ")


def as_flags(message: str) -> str:
    """A library error message as the command line says it: parameters as flags.

    Examples
    --------
    >>> as_flags("fingers=2, contact='hard': a spatial grasp needs at least 3 hard fingers")
    '--fingers 2 --contact hard: a spatial grasp needs at least 3 hard fingers'
    >>> as_flags("mu must be a positive number, got -1")
    '--mu must be a positive number, got -1'
    >>> as_flags("method='faces': not 4 soft; use method='mesh'")
    '--method faces: not 4 soft; use --method mesh'
    >>> as_flags("the least friction was not computed (least_friction=False)")
    'the least friction was not computed (--no-least-friction)'
    >>> as_flags("--mu must be finite")   # a message already in flags is left as it is
    '--mu must be finite'
    """
    def flag(match: re.Match[str]) -> str:
        value = match.group(2)
        if len(value) >= 2 and value[0] == value[-1] == "'":
            value = value[1:-1]
        return f"{FLAGS[match.group(1)]} {value}" + (" " if match.group(3) else "")

    message = _ASSIGNED.sub(flag, message)
    message = _SWITCHED.sub(lambda m: SWITCHES[m.group(1)], message)
    subject = _SUBJECT.match(message)
    if subject:
        message = FLAGS[subject.group(1)] + message[len(subject.group(1)):]
    return message


class _Parser(argparse.ArgumentParser):
    """argparse, with a bad command line answered in one line (and where to look) instead
    of the usage block, exit status 2 as before."""

    def error(self, message: str) -> NoReturn:
        error(f"{message} (see '{self.prog} --help')")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``forceclosure`` command: one subcommand per module."""
    parser = _Parser(
        prog="forceclosure",
        description="Analyse force-closure grasps (V.-D. Nguyen, IJRR 1988).")
    parser.add_argument("--version", action="version", version=f"forceclosure {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(sub)
    parser.epilog = f"Verdicts within {TOLERANCE:g} of the boundary are 'marginal'."
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        from .limits import check_options

        check_options(args)  # every option's range, before any work (app/limits.py)
        from .interrupt import run_interruptible

        # the command in a thread: Ctrl-C ends it within seconds, even in compiled code
        return run_interruptible(lambda: args.run(args))
    except InputError as e:
        error(as_flags(str(e)))
        return 2
    except KeyboardInterrupt:
        print("forceclosure: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader (e.g. `head`) closed the pipe: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as e:  # an internal error: one line unless debugging
        if os.environ.get("FORCECLOSURE_DEBUG"):
            raise
        print(f"forceclosure: internal error: {type(e).__name__}: {printable(clip(str(e)))} "
              "(set FORCECLOSURE_DEBUG=1 for the traceback)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
