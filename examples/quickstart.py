"""Is a grasp force-closure? A tour of the analysis API (Nguyen 1988, §2–§4).

Run: uv run python examples/quickstart.py
"""

from collections import Counter

import numpy as np

from forceclosure import analyze, point_contact
from forceclosure.analysis.batch import analyze_batch
from forceclosure.analysis.equilibrium import nonmarginal_equilibrium
from forceclosure.analysis.quality import epsilon, least_friction
from forceclosure.analysis.two_finger import two_finger_closure

# Two hard fingers squeezing a box across its faces x = -1 and x = +1.
hard = [point_contact([-1, 0.3, 0.2], [-1, 0, 0], "hard", mu=0.5),
        point_contact([1, 0.3, 0.2], [1, 0, 0], "hard", mu=0.5)]
print("two hard fingers:", analyze(hard).explain(), sep="\n")

# Soft fingers can twist about their normals: now the grasp holds.
soft = [point_contact(c.point, c.normal, "soft", mu=0.5) for c in hard]
result = analyze(soft)
print("\ntwo soft fingers:", result.explain(), sep="\n")
forces = result.contact_forces.round(3) + 0.0  # + 0.0 turns -0.0 into 0.0
print("contact forces in equilibrium (the certificate):", forces.tolist())
print("epsilon:", round(epsilon(soft).value, 4))

# A planar pinch: Corollary 3 in closed form, and the least friction it needs.
pinch = [point_contact([-1, 0], [-1, 0], "hard", 0.3), point_contact([1, 0.2], [1, 0], "hard", 0.3)]
print("\nplanar pinch:", analyze(pinch).verdict.value,
      "| least friction:", round(least_friction(pinch), 4))
f = np.array([2.0, 0.2])  # squeeze along PQ: equilibrium inside both cones
print("Corollary 4 certificate:", nonmarginal_equilibrium(pinch, [f, -f]).reason)

# Many pairs at once.
rng = np.random.default_rng(0)
p, q = rng.normal(size=(100_000, 2)), rng.normal(size=(100_000, 2))
pairs = two_finger_closure(p, p, q, q, mu_p=0.3)
print(f"\n{pairs.force_closure.mean():.1%} of 100000 random planar pairs are force-closure")

# Many general grasps at once, as arrays (N grasps x k contacts x d).
points = rng.uniform(-1, 1, (20, 3, 2))
batch = analyze_batch(points, points, mu=0.4, model="hard")
print("verdicts of 20 random three-finger grasps:", dict(Counter(batch.verdict.tolist())))
