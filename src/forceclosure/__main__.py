"""``python -m forceclosure``: the command-line tool (see :mod:`forceclosure.app.cli`)."""

import sys

from .app.cli import main

sys.exit(main())
