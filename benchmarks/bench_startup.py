"""Start-up: what a person waits for before the first answer (issue 18).

Each command runs as a fresh process, several times, best and median kept;
plain ``python -c pass`` and ``python -c "import numpy"`` run in the same
loop as references, since this machine is shared and its load changes.

* ``forceclosure --help`` and ``--version``: no numpy, no scipy, no kernels.
* ``import forceclosure``: names are imported on first use.
* ``forceclosure analyze`` on the bundled planar example (one JSON file):
  the first answer a new user sees, compiled kernels excluded (they are
  cached on disk after the first run; ``--no-quality`` and the default).

    uv run python benchmarks/bench_startup.py [--repeat 7]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path

from _tables import parse, table

BIN = Path(sys.executable).parent


def timed(cmd: list[str], repeat: int) -> tuple[float, float]:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parse(parser)
    example = str(resources.files("forceclosure") / "examples" / "planar.json")
    cli = [str(BIN / "forceclosure")]
    cases = [
        ("python -c pass (reference)", [sys.executable, "-c", "pass"]),
        ("python -c 'import numpy' (reference)", [sys.executable, "-c", "import numpy"]),
        ("forceclosure --help", [*cli, "--help"]),
        ("forceclosure --version", [*cli, "--version"]),
        ("python -c 'import forceclosure'", [sys.executable, "-c", "import forceclosure"]),
        ("forceclosure analyze planar.json --no-quality", [*cli, "analyze", example,
                                                           "--no-quality"]),
        ("forceclosure analyze planar.json", [*cli, "analyze", example]),
    ]
    rows = []
    for label, cmd in cases:
        best, median = timed(cmd, args.repeat)
        rows.append([f"`{label}`", f"{best:.2f} s", f"{median:.2f} s"])
    table("startup", ["command (a fresh process, wall time)", "best", "median"], rows)


if __name__ == "__main__":
    main()
