"""What a controller file keeps on randomized worlds: the robustness check of `proleg
robustness` for any simulation file's own modules (a network exported by PPO among them),
on a suite task's course, through the environments' `randomize` option.

    python examples/python/robustness.py SIM.simulation.xml --task steps-medium \\
        --course 101 --episodes 20 --duration 30 --engines rapier,mujoco

Each episode runs the file's modules alone (a residual environment given zero actions
runs exactly the file's gait) on test course `--course` of the task: once in the nominal
world, then `--episodes` times with the physics drawn from `proleg robustness`'s ranges
(friction ±30 %, masses ±10 %, servo torque and gain ±20 %, heading ±20°, start ±0.1 m,
sensor noise), each from its own reset seed (`--seed`, `--seed` + 1, ...). Prints per
engine the nominal distance, the episodes' and the share kept.
"""

from __future__ import annotations

import argparse

import numpy as np

import proleg
from proleg.registration import SUITE


def distance(sim: str, engine: str, family: str, difficulty: str, course: int,
             duration: float, seed: int, randomize: bool) -> float:
    """The metres the file's gait goes along the course in one episode."""
    env = proleg.ProlegEnv(sim, engine=engine, mode="residual", terrain=family,
                           difficulty=difficulty, suite=proleg.scenario_path(SUITE),
                           split="test", terrain_seed=course, duration=duration,
                           randomize=randomize)
    env.reset(seed=seed)
    zero = np.zeros(env.action_space.shape)
    total, done = 0.0, False
    while not done:
        _, reward, terminated, truncated, _ = env.step(zero)
        total += reward
        done = terminated or truncated
    env.close()
    return total


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("sim")
    p.add_argument("--task", default="steps-medium")
    p.add_argument("--course", type=int, default=101, help="the course's terrain seed")
    p.add_argument("--episodes", type=int, default=20)
    p.add_argument("--duration", type=float, default=30.0)
    p.add_argument("--seed", type=int, default=1000)
    p.add_argument("--engines", default="rapier,mujoco")
    args = p.parse_args()
    family, difficulty = args.task.rsplit("-", 1)
    for engine in args.engines.split(","):
        run = lambda seed, randomize: distance(  # noqa: E731
            args.sim, engine, family, difficulty, args.course, args.duration, seed, randomize)
        nominal = run(1, False)
        scores = [run(args.seed + k, True) for k in range(args.episodes)]
        print(f"{engine}: nominal {nominal:.4f} m; randomized mean {np.mean(scores):.4f}, "
              f"lower quartile {np.quantile(scores, 0.25):.4f}, min {min(scores):.4f}; "
              f"kept {100 * np.mean(scores) / nominal:.1f} %")
        print("  episodes " + " ".join(f"{s:.3f}" for s in scores))


if __name__ == "__main__":
    main()
