"""Test distance against wall time for each training method: the figure a user picks a
method by (docs/suite.md, "Time to a policy").

    python examples/python/time_to_policy.py docs/time_to_policy_hills.tsv \\
        -o docs/time_to_policy_hills.png            # needs matplotlib

The TSV holds one row per scored point: `method` (a name), `budget` (its evaluations or
environment steps), `wall_s` (wall seconds of training on these 2 cores, alone, from the
start of the open-loop search they share), `rapier_m` and `mujoco_m` (the mean distance
over the task's held-out test courses on each engine). Rows whose method is `(a)` draw
the tuned sine's curve, its final distance as a dashed line and 1.3 times it (the aim of
docs/suite.md) as a dotted one.
"""

from __future__ import annotations

import argparse
import csv
from collections import defaultdict


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("tsv")
    p.add_argument("-o", "--out", required=True)
    p.add_argument("--title", default="hills-medium, held-out test courses (60 s)")
    args = p.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves: dict[str, list[tuple[float, float, float]]] = defaultdict(list)
    with open(args.tsv) as f:
        for row in csv.DictReader((line for line in f if not line.startswith("#")),
                                  delimiter="\t"):
            curves[row["method"]].append(
                (float(row["wall_s"]) / 60.0, float(row["rapier_m"]), float(row["mujoco_m"]))
            )
    bar = curves.pop("(a)", None)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for k, (ax, engine) in enumerate(zip(axes, ("rapier", "MuJoCo"))):
        for method, points in curves.items():
            points.sort()
            ax.plot([p[0] for p in points], [p[1 + k] for p in points], "o-", label=method)
        if bar:
            bar.sort()
            ax.plot([p[0] for p in bar], [p[1 + k] for p in bar], "s-", color="grey",
                    label="(a) the sine, CMA-ES")
            final = bar[-1][1 + k]
            ax.axhline(final, color="grey", ls="--", lw=0.8)
            ax.axhline(1.3 * final, color="red", ls=":", lw=0.8, label="1.3x (a)")
        ax.set_title(engine)
        ax.set_xlabel("wall minutes of training (2 cores)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("mean distance on the test courses (m)")
    axes[1].legend(fontsize=8, loc="lower right")
    fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
