"""Planar two-finger synthesis: maximal regions against Nguyen's Algorithm 1, and cost.

Over the bundled polygons, random convex polygons and random star-shaped
(non-convex) polygons, every edge pair whose cones counter-overlap gets both
constructions. The script reports how much larger the maximal regions' shorter
segment is than Nguyen's, how often Nguyen's trade-off region is empty while
maximal regions exist, and the cost per pair, against the paper's 0.05 s per
pair on a Symbolics machine.

    uv run python benchmarks/bench_planar.py [--random 30] [--edges 24]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import shapely
from _tables import parse, table

from forceclosure.objects import POLYGONS, Polygon, bundled
from forceclosure.synthesis import counter_overlapping_sector, maximal_regions, nguyen_regions


def random_polygons(count: int, edges: int, rng) -> list[Polygon]:
    out = []
    for k in range(count):
        if k % 2 == 0:
            hull = shapely.MultiPoint(rng.normal(size=(edges * 3, 2))).convex_hull
            out.append(Polygon.from_shapely(hull, name=f"convex {k}"))
        else:
            angles = np.sort(rng.uniform(0, 2 * np.pi, edges))
            radii = rng.uniform(0.4, 1.0, edges)
            pts = np.stack([radii * np.cos(angles), radii * np.sin(angles)], 1)
            out.append(Polygon.from_points(pts, name=f"star-shaped {k}"))
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--random", type=int, default=30)
    ap.add_argument("--edges", type=int, default=24)
    ap.add_argument("--mu", type=float, default=0.3)
    ap.add_argument("--whole", type=int, default=1000, help="edges of the whole polygon")
    args = parse(ap)
    rng = np.random.default_rng(0)
    polygons = [bundled(n) for n in POLYGONS] + random_polygons(args.random, args.edges, rng)
    ratios, nguyen_empty, pairs, candidates = [], 0, 0, 0
    t_max = t_ng = 0.0
    for poly in polygons:
        n = len(poly.edges)
        for i in range(n):
            for j in range(i + 1, n):
                pairs += 1
                e1, e2 = poly.edges[i], poly.edges[j]
                if counter_overlapping_sector(e1.normal, args.mu, e2.normal, args.mu) is None:
                    continue
                candidates += 1
                t = time.process_time()
                m = maximal_regions(poly, i, j, args.mu)
                t_max += time.process_time() - t
                t = time.process_time()
                g = nguyen_regions(poly, i, j, args.mu)
                t_ng += time.process_time() - t
                if m is None:
                    continue
                if g is None:
                    nguyen_empty += 1
                else:
                    ratios.append(m.min_length / g.min_length)
    r = np.array(ratios)
    print(f"{len(polygons)} polygons, {pairs} edge pairs, {candidates} with counter-overlapping "
          f"cones (the rest pruned by a test on the normals)")
    print(f"maximal / Nguyen shorter segment, over {len(r)} pairs where both exist: "
          f"median {np.median(r):.3f}, mean {r.mean():.3f}, 90th percentile "
          f"{np.percentile(r, 90):.3f}, max {r.max():.3f}; equal (within 0.1%) on "
          f"{np.mean(r < 1.001):.0%}")
    print(f"pairs with maximal regions where Nguyen's trade-off region is empty: "
          f"{nguyen_empty}")
    print(f"cost per candidate pair: maximal LP {t_max / candidates * 1e3:.2f} ms, Nguyen "
          f"{t_ng / candidates * 1e3:.2f} ms (paper: 50 ms per pair, Symbolics Zeta Lisp)")
    rows = [["one edge pair, maximal regions (an LP)", f"{t_max / candidates * 1e3:.2f} ms"],
            ["one edge pair, Nguyen's construction", f"{t_ng / candidates * 1e3:.2f} ms"],
            whole_polygon(args.whole, args.mu)]
    table("planar", ["planar two-finger synthesis", "CPU time"], rows)




def whole_polygon(edges: int = 1000, mu: float = 0.3) -> list[str]:
    """All edge pairs of a large polygon at once (the issue's 1000-edge case)."""
    from forceclosure.synthesis import synthesize

    theta = np.sort(np.random.default_rng(1).uniform(0, 2 * np.pi, edges))
    radius = 1 + 0.05 * np.sin(7 * theta)
    poly = Polygon.from_points(np.stack([radius * np.cos(theta), radius * np.sin(theta)], 1),
                               name=f"{edges}-gon")
    n = len(poly.edges)
    times = []
    for _ in range(3):
        t = time.process_time()
        synthesize(poly, 2, "hard", mu, top=5)
        times.append(time.process_time() - t)
    pairs = n * (n - 1) // 2
    print(f"whole polygon: {n} edges, {pairs} pairs, best 5 with maximal regions in "
          f"{min(times):.2f} s CPU ({min(times) / pairs * 1e6:.2f} us per pair; paper: 50 ms)")
    return [f"all {pairs:,} edge pairs of a {n}-edge polygon, best 5 with maximal regions "
            "certified (best of 3)",
            f"{min(times):.2f} s ({min(times) / pairs * 1e6:.1f} µs a pair)"]


if __name__ == "__main__":
    main()
