"""``python -m forceclosure``: the command-line tool (see :mod:`forceclosure.cli`)."""

import sys

from .cli import main

sys.exit(main())
