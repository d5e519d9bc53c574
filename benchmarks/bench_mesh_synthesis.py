"""Synthesis on 100k-triangle meshes, as a user waits for it (issue 18).

Two meshes written as binary STL, as ``bench_objects.py`` writes them: an
icosphere of 81 920 triangles (curved: every triangle its own face, so
regions are grown over the mesh around sampled prototypes) and a box
subdivided into 98 304 triangles (6 faces: the paper's constructions on
faces). For each, the CPU time (user + system, of the process and its
children) of the command a user runs:

    forceclosure synthesize MESH --fingers 3 --contact hard --mu 0.5 --top 3 --json
    forceclosure synthesize MESH --fingers 2 --contact soft --json
    forceclosure inspect MESH

and, in this process, the stages of the first: loading, sampling the
prototypes (one ``epsilon_batch`` call), growing the regions, proving them.

``--against REV`` runs the same commands with the package as it was at git
revision ``REV`` (exported to a temporary folder, put first on PYTHONPATH)
in the same run, and prints the ratios and whether the JSON is the same
byte for byte. Its first command compiles that copy's kernels, so it is run
once before timing.

    uv run python benchmarks/bench_mesh_synthesis.py [--against c63d5e8]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import trimesh
from _tables import parse, table

COMMANDS = {
    "3 hard, mu 0.5, top 3": ["synthesize", "--fingers", "3", "--contact", "hard", "--mu",
                              "0.5", "--top", "3", "--json"],
    "2 soft": ["synthesize", "--fingers", "2", "--contact", "soft", "--json"],
    "inspect": ["inspect"],
}


def cpu_of(args: list[str], env: dict[str, str]) -> tuple[float, bytes]:
    """CPU seconds (user + system) of a child process, and its standard output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(args, env=env, check=True, capture_output=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def stages(path: Path) -> None:
    """Time the stages of three hard fingers on the mesh, in this process."""
    from forceclosure.objects.io import load_object
    from forceclosure.synthesis.best import synthesize
    from forceclosure.synthesis.regions import narrowed
    from forceclosure.synthesis.spatial.zones import prototype_grasps, zone_regions

    load_object(path)  # imports (trimesh's own) out of the way
    t = time.process_time()
    poly = load_object(path)
    loaded = time.process_time() - t
    synthesize(poly, 3, "hard", 0.5, top=1, samples=100)  # kernels loaded
    margin = 1e-3
    t = time.process_time()
    protos = prototype_grasps(poly, 3, "hard", narrowed(0.5, margin), count=3)
    sampled = time.process_time() - t
    t = time.process_time()
    found = [zone_regions(poly, p, "hard", 0.5, grow=True, margin=margin) for p in protos]
    grown = time.process_time() - t
    t = time.process_time()
    held = [r.certify().holds for r in found]
    proved = time.process_time() - t
    patches = sum(len(x) for r in found for x in r.regions)
    print(f"  stages (CPU): load {loaded:.2f} s, 20 000 prototypes sampled {sampled:.2f} s, "
          f"3 region sets grown ({patches} patches) {grown:.2f} s, proved {proved:.2f} s "
          f"(all hold: {all(held)})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", metavar="REV", help="git revision to compare with")
    parser.add_argument("--quick", action="store_true", help="small meshes: a smoke run")
    args = parse(parser)
    env = dict(os.environ)
    old_env = None
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        meshes = {
            "icosphere": trimesh.creation.icosphere(subdivisions=2 if args.quick else 6),
            "subdivided box": trimesh.creation.box(extents=(2, 2, 2)).subdivide_to_size(
                0.5 if args.quick else 0.035),
        }
        rows = []
        paths = {}
        for name, mesh in meshes.items():
            paths[name] = tmp / f"{name.replace(' ', '-')}.stl"
            mesh.export(paths[name])
        if args.against:
            root = Path(__file__).resolve().parents[1]
            archive = subprocess.run(["git", "-C", str(root), "archive", args.against, "src"],
                                     check=True, capture_output=True).stdout
            (tmp / "old").mkdir()
            subprocess.run(["tar", "-x", "-C", str(tmp / "old")], input=archive, check=True)
            old_env = dict(env, PYTHONPATH=str(tmp / "old" / "src"))
            cpu_of([sys.executable, "-m", "forceclosure", *COMMANDS["3 hard, mu 0.5, top 3"],
                    str(paths["subdivided box"])], old_env)  # compile that copy's kernels
        for name, path in paths.items():
            print(f"{name} ({len(meshes[name].faces)} triangles), CPU seconds:")
            for label, command in COMMANDS.items():
                run = [sys.executable, "-m", "forceclosure", *command, str(path)]
                now, out = cpu_of(run, env)
                line = f"  {label:24} {now:7.2f} s"
                rows.append([f"{name} ({len(meshes[name].faces):,} triangles)",
                             f"`{' '.join(command)}`", f"{now:.2f} s"])
                if old_env is not None:
                    then, old_out = cpu_of(run, old_env)
                    line += (f"   {args.against}: {then:7.2f} s   {then / now:5.1f}x   same "
                             f"output: {out == old_out}")
                    rows[-1] += [f"{then:.2f} s", f"{then / now:.1f}×",
                                 "yes" if out == old_out else "**no**"]
                print(line, flush=True)
            stages(path)
    table("mesh_synthesis", ["mesh", "command", "CPU"] + (
        [args.against, "ratio", "same output"] if args.against else []), rows)


if __name__ == "__main__":
    main()
