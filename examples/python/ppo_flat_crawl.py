"""Stable-Baselines3 PPO on the natively vectorized flat crawl (experiment 1's snake).

    pip install ./python stable-baselines3      # torch is a large download: not in CI
    python examples/python/ppo_flat_crawl.py --steps 300000 --out docs/ppo_flat_crawl

Trains PPO on `proleg.sb3.SB3VecEnv` (the worlds stepped inside Rust, no DummyVecEnv),
evaluates the random policy, the file's own sine gait (the residual with zero action) and
the trained policy on the same seeds, and writes the learning curve (mean episode return
against environment steps) as PNG and TSV, the figures as JSON, the trained model (.zip)
and a video of one trained episode rendered off-screen (.mp4). Episodes last 10 s (500 steps of 20 ms); the return is the metres
travelled along the start heading (proleg's `distance` fitness).
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

import proleg
from proleg.sb3 import SB3VecEnv


def evaluate(policy, path: str, episodes: int, duration: float, seed: int, **kw) -> list[float]:
    """Returns of `episodes` episodes on seeds seed, seed+1, ...; `policy(obs)` gives the
    action (None: uniformly random actions)."""
    rng = np.random.default_rng(seed)
    returns = []
    for k in range(episodes):
        env = proleg.ProlegEnv(path, duration=duration, **kw)
        obs, _ = env.reset(seed=seed + k)
        total, done = 0.0, False
        while not done:
            a = rng.uniform(-1, 1, env.action_space.shape) if policy is None else policy(obs)
            obs, r, term, trunc, _ = env.step(a)
            total += r
            done = term or trunc
        returns.append(total)
        env.close()
    return returns


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=300_000)
    p.add_argument("--envs", type=int, default=16)
    p.add_argument("--duration", type=float, default=10.0)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--eval-episodes", type=int, default=10)
    p.add_argument("--out", default="out/ppo_flat_crawl")
    args = p.parse_args()

    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecMonitor

    torch.set_num_threads(1)
    path = proleg.scenario_path("demo.simulation.xml")
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)

    class Curve(BaseCallback):
        """Mean return of the episodes finished since the last rollout, per rollout."""

        def __init__(self):
            super().__init__()
            self.points: list[tuple[int, float, float]] = []
            self.start = time.perf_counter()

        def _on_rollout_end(self) -> None:
            buf = [e["r"] for e in self.model.ep_info_buffer]
            if buf:
                self.points.append(
                    (self.num_timesteps, float(np.mean(buf)), time.perf_counter() - self.start)
                )

        def _on_step(self) -> bool:
            return True

    random_returns = evaluate(None, path, args.eval_episodes, args.duration, 1000)
    venv = VecMonitor(SB3VecEnv(path, num_envs=args.envs, duration=args.duration))
    model = PPO("MlpPolicy", venv, n_steps=256, batch_size=1024, n_epochs=10,
                learning_rate=3e-4, gamma=0.99, seed=args.seed, verbose=0, device="cpu")
    curve = Curve()
    t = time.perf_counter()
    model.learn(total_timesteps=args.steps, callback=curve)
    wall = time.perf_counter() - t

    def act(obs):
        return model.predict(obs.astype(np.float32), deterministic=True)[0]

    trained_returns = evaluate(act, path, args.eval_episodes, args.duration, 1000)
    sine_returns = evaluate(
        lambda obs: np.zeros(5), path, 1, args.duration, 1000, mode="residual"
    )
    model.save(args.out + ".zip")
    env = proleg.ProlegEnv(path, duration=args.duration, render_mode="rgb_array")
    obs, _ = env.reset(seed=1000)
    frames, done = [env.render()], False
    while not done:
        obs, _, term, trunc, _ = env.step(act(obs))
        frames.append(env.render())
        done = term or trunc
    proleg.save_video(frames, args.out + ".mp4", fps=50)
    figures = {
        "steps": args.steps,
        "envs": args.envs,
        "wall_s": wall,
        "random_mean": float(np.mean(random_returns)),
        "random_std": float(np.std(random_returns)),
        "trained_mean": float(np.mean(trained_returns)),
        "trained_std": float(np.std(trained_returns)),
        "sine_gait": float(sine_returns[0]),
        "episode_s": args.duration,
    }
    with open(args.out + ".json", "w") as f:
        json.dump(figures, f, indent=2)
    with open(args.out + ".tsv", "w") as f:
        f.write("env_steps\tmean_return_m\twall_s\n")
        for s, r, w in curve.points:
            f.write(f"{s}\t{r}\t{w}\n")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        xs, ys = [c[0] for c in curve.points], [c[1] for c in curve.points]
        plt.figure(figsize=(8, 4.5))
        plt.plot(xs, ys, label="PPO (training episodes)")
        plt.axhline(figures["random_mean"], color="grey", ls="--", label="random policy")
        plt.axhline(figures["trained_mean"], color="C2", ls=":", label="PPO, deterministic")
        plt.axhline(figures["sine_gait"], color="C1", ls="-.", label="the file's sine gait")
        plt.xlabel("environment steps (20 ms each)")
        plt.ylabel(f"return: m along the heading in {args.duration:g} s")
        plt.title("proleg/FlatCrawl: PPO on the native vector env (16 worlds)")
        plt.legend()
        plt.tight_layout()
        plt.savefig(args.out + ".png", dpi=110)
    except ImportError:
        print("matplotlib not installed: the curve is in the TSV only")
    print(json.dumps(figures, indent=2))


if __name__ == "__main__":
    main()
