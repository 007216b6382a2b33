"""Stable-Baselines3 PPO on a locomotion-suite task's train courses: a residual over a sine
gait, exported into proleg's `Policy` module (the learned-control comparison's (d),
docs/suite.md).

    pip install ./python stable-baselines3      # torch is a large download: not in CI
    python examples/python/ppo_suite.py BASE.simulation.xml --task steps-medium \\
        --steps 1080000 --out results/ppo/steps-medium

BASE is the simulation whose modules the residual runs beside (scripts/learned-suite-
experiment writes `sine_quarter.simulation.xml`, the sine CMA-ES had after a quarter of
the budget, as (c) starts from). Each episode is one of the task's train courses (a seed
drawn per reset from the task's train list, never a test seed), `--duration` simulated
seconds; the reward is the metres gained along the course. `--engines rapier,mujoco`
splits the environments between the engines, so the policy learns both engines' contacts
(trained on rapier alone, a hills network lost half its distance on MuJoCo); `--randomize`
draws each episode's physics (friction, masses, servos, start pose, sensor noise) as
`proleg robustness` does. The policy's
outputs are
offsets of `--amplitude` degrees at 1 (the `Policy` module's `Amplitude`: the environment's
action scale is amplitude / 90, the robot's ±90° joints).

Writes OUT.safetensors (the action network with VecNormalize's observation statistics),
OUT.actuation.xml (BASE's modules and the `Policy` over the weights), OUT.tsv (mean
training return against environment steps and wall seconds) and OUT.json (the figures).
Every `--checkpoint` environment steps it also writes OUT.STEPS.safetensors, so the test
distance can be drawn against the budget and the wall time afterwards.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import time

import numpy as np

import proleg
from proleg.policy import save_sb3_policy
from proleg.sb3 import SB3VecEnv
from proleg.registration import SUITE


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("base", help="the simulation file the residual runs beside")
    p.add_argument("--task", default="steps-medium", help="a trainable suite task")
    p.add_argument("--steps", type=int, default=1_080_000)
    p.add_argument("--envs", type=int, default=16)
    p.add_argument("--engines", default="rapier",
                   help="comma-separated engines the environments are split between")
    p.add_argument("--randomize", action="store_true",
                   help="each episode's physics drawn as `proleg robustness` draws them")
    p.add_argument("--duration", type=float, default=30.0)
    p.add_argument("--amplitude", type=float, default=15.0)
    p.add_argument("--checkpoint", type=int, default=270_000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", default="results/ppo/task")
    args = p.parse_args()

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecMonitor, VecNormalize

    torch.set_num_threads(1)
    family, difficulty = args.task.rsplit("-", 1)
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    engines = args.engines.split(",")
    venv = SB3VecEnv(args.base, num_envs=args.envs, engines=engines,
                     duration=args.duration, mode="residual",
                     action_scale=args.amplitude / 90.0, terrain=family,
                     difficulty=difficulty, suite=proleg.scenario_path(SUITE), threads=2,
                     randomize=args.randomize)
    venv = VecNormalize(VecMonitor(venv), norm_obs=True, norm_reward=True, gamma=0.995)
    model = PPO("MlpPolicy", venv, n_steps=512, batch_size=2048, n_epochs=10,
                learning_rate=3e-4, gamma=0.995, gae_lambda=0.95, ent_coef=0.0,
                policy_kwargs={"net_arch": [64, 64], "log_std_init": -1.0},
                seed=args.seed, verbose=0, device="cpu")

    class Curve(BaseCallback):
        """The mean return of recent training episodes per rollout; checkpoints."""

        def __init__(self):
            super().__init__()
            self.points: list[tuple[int, float, float]] = []
            self.start = time.perf_counter()
            self.next_checkpoint = args.checkpoint

        def _on_rollout_end(self) -> None:
            wall = time.perf_counter() - self.start
            buf = [e["r"] for e in self.model.ep_info_buffer]
            if buf:
                self.points.append((self.num_timesteps, float(np.mean(buf)), wall))
            if args.checkpoint and self.num_timesteps >= self.next_checkpoint:
                save_sb3_policy(f"{args.out}.{self.num_timesteps}.safetensors", self.model,
                                venv.obs_rms)
                with open(f"{args.out}.{self.num_timesteps}.wall", "w") as f:
                    f.write(f"{wall:.1f}\n")
                self.next_checkpoint += args.checkpoint

        def _on_step(self) -> bool:
            return True

    curve = Curve()
    t = time.perf_counter()
    model.learn(total_timesteps=args.steps, callback=curve)
    wall = time.perf_counter() - t
    save_sb3_policy(args.out + ".safetensors", model, venv.obs_rms)
    write_actuation(args.base, args.out + ".actuation.xml",
                    os.path.abspath(args.out + ".safetensors"), args.amplitude)
    figures = {"task": args.task, "steps": args.steps, "envs": args.envs, "engines": engines,
               "randomize": args.randomize,
               "episode_s": args.duration, "wall_s": wall,
               "simulated_s": args.steps * 0.02,
               "last_training_return": curve.points[-1][1] if curve.points else None}
    with open(args.out + ".json", "w") as f:
        json.dump(figures, f, indent=2)
    with open(args.out + ".tsv", "w") as f:
        f.write("env_steps\tmean_return_m\twall_s\n")
        for s, r, w in curve.points:
            f.write(f"{s}\t{r}\t{w}\n")
    print(json.dumps(figures, indent=2))


def write_actuation(base: str, out: str, weights: str, amplitude: float) -> None:
    """BASE's actuation file with a `Policy` module over `weights` appended."""
    sim = open(base).read()
    path = re.search(r"<actuation>(.*?)</actuation>", sim).group(1).strip()
    if not os.path.isabs(path):
        path = os.path.join(os.path.dirname(os.path.abspath(base)), path)
    actuation = open(path).read()
    policy = (f'  <actuationModule name="Policy" weights="{weights}">\n'
              f'    <jointConfiguration joints="11111"/>\n'
              f'    <parameter name="Amplitude" value="{amplitude:g}"/>\n'
              f'    <parameter name="Period" value="0.02"/>\n'
              f'  </actuationModule>\n</actuation>')
    with open(out, "w") as f:
        f.write(actuation.replace("</actuation>", policy))


if __name__ == "__main__":
    main()
