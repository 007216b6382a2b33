"""``python -m proleg.bench``: the environments' throughput on this machine, in one run.

For each engine: the native vector environment (:class:`proleg.ProlegVectorEnv`, random
actions, the default 20-ms control period) with N = 1, 16 and 64 environments on 1 and 2
threads, as environment steps per second, physics robot-steps per second and simulated
seconds per wall second, beside ``proleg bench``'s one-core pipeline figure for the same
file and engine (one robot in one world, the file's own gait, best of three). Then, on one
core, the yardsticks: a plain Gymnasium ``MujocoEnv`` of the same robot (the MJCF
``proleg export mjcf`` writes: position servos, the same control period, a forward-progress
reward) under ``SyncVectorEnv``, and Gymnasium's ``Swimmer-v5``.

Every figure is the best of three runs (the machines here are shared VMs whose speed
varies from minute to minute, as ``proleg bench`` says); single-thread figures run pinned
to one core (the process's first allowed CPU).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time

import numpy as np

from . import _native
from .envs import scenario_path
from .vector import ProlegVectorEnv


def _pin(cores: set[int] | None) -> None:
    """Pins this thread (and threads it starts later) to ``cores`` (None: all allowed)."""
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, cores if cores is not None else _ALL)


_ALL = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else set()
_ONE = {min(_ALL)} if _ALL else None


REPEATS = 3


def _timed_steps(step, actions: np.ndarray, steps: int) -> float:
    """The fastest of :data:`REPEATS` runs of ``steps`` calls of ``step`` with the rows of
    ``actions`` in turn (wall seconds), after a warm-up."""
    for k in range(3):
        step(actions[k % len(actions)])
    best = float("inf")
    for _ in range(REPEATS):
        t = time.perf_counter()
        for k in range(steps):
            step(actions[k % len(actions)])
        best = min(best, time.perf_counter() - t)
    return best


def native(
    path: str, engine: str, n: int, threads: int, seconds: float, residual: bool = False
) -> dict:
    """The native vector environment: ``seconds`` simulated per environment (at least 25
    steps) per run; episodes end and reset as they would in training. Random actions, or
    with ``residual`` zero actions added to the file's gait (the pipeline's physics)."""
    _pin(_ONE if threads == 1 else None)
    mode = "residual" if residual else "alone"
    venv = ProlegVectorEnv(path, n, threads=threads, engine=engine, mode=mode)
    venv.reset(seed=0)
    steps = max(25, math.ceil(seconds / venv._venv.control_period))
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (64, n, venv.single_action_space.shape[0]))
    if residual:
        actions[:] = 0.0
    wall = _timed_steps(venv.step, actions, steps)
    env_rate = n * steps / wall
    physics = env_rate * venv.steps_per_action
    dt = venv._venv.control_period / venv.steps_per_action
    venv.close()
    _pin(None)
    return {
        "engine": engine,
        "envs": n,
        "threads": threads,
        "env_steps_per_s": env_rate,
        "robot_steps_per_s": physics,
        "sim_s_per_s": physics * dt,
    }


def exported_mujoco_env(path: str, control_period: float):
    """A plain Gymnasium ``MujocoEnv`` of ``path``'s robot as ``proleg export mjcf`` writes
    it; its reward is the root's progress along +y (the demo's heading) per second."""
    import mujoco
    from gymnasium import spaces
    from gymnasium.envs.mujoco import MujocoEnv

    xml = os.path.join(tempfile.mkdtemp(prefix="proleg-bench-"), "robot.mjcf.xml")
    _native.export_mjcf_file(path, xml)
    model = mujoco.MjModel.from_xml_path(xml)
    frame_skip = round(control_period / model.opt.timestep)
    fps = round(1.0 / (model.opt.timestep * frame_skip))
    obs_dim = model.nq - 2 + model.nv

    class ExportedRobotEnv(MujocoEnv):
        metadata = {
            "render_modes": ["human", "rgb_array", "depth_array", "rgbd_tuple"],
            "render_fps": fps,
        }

        def __init__(self, **kwargs):
            MujocoEnv.__init__(
                self,
                xml,
                frame_skip,
                observation_space=spaces.Box(-np.inf, np.inf, (obs_dim,), np.float64),
                **kwargs,
            )

        def _obs(self):
            return np.concatenate([self.data.qpos.flat[2:], self.data.qvel.flat])

        def step(self, action):
            y0 = self.data.qpos[1]
            self.do_simulation(action, self.frame_skip)
            reward = (self.data.qpos[1] - y0) / self.dt
            return self._obs(), reward, False, False, {}

        def reset_model(self):
            self.set_state(self.init_qpos, self.init_qvel)
            return self._obs()

    return ExportedRobotEnv, frame_skip


def gymnasium_sync(make_one, n: int, frame_skip: int, seconds_per_step: float, seconds: float) -> dict:
    """``SyncVectorEnv`` of ``n`` environments from ``make_one``, on one core."""
    import gymnasium

    _pin(_ONE)
    venv = gymnasium.vector.SyncVectorEnv([make_one for _ in range(n)])
    venv.reset(seed=0)
    venv.action_space.seed(0)
    actions = np.array([venv.action_space.sample() for _ in range(64)])
    steps = max(25, math.ceil(seconds / seconds_per_step))
    wall = _timed_steps(venv.step, actions, steps)
    venv.close()
    _pin(None)
    env_rate = n * steps / wall
    return {
        "envs": n,
        "env_steps_per_s": env_rate,
        "physics_steps_per_s": env_rate * frame_skip,
        "sim_s_per_s": env_rate * seconds_per_step,
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m proleg.bench", description=__doc__.split("\n\n")[0])
    p.add_argument("--config", default=scenario_path("demo.simulation.xml"))
    p.add_argument("--engines", nargs="+", default=["rapier", "mujoco"])
    p.add_argument("--envs", nargs="+", type=int, default=[1, 16, 64])
    p.add_argument("--threads", nargs="+", type=int, default=[1, 2])
    p.add_argument("--seconds", type=float, default=20.0,
                   help="simulated seconds per environment of each figure (at least 25 steps)")
    p.add_argument("--pipeline-seconds", type=float, default=10.0)
    p.add_argument("--peers", type=int, default=16,
                   help="environments of the Gymnasium yardsticks (0: skip them)")
    p.add_argument("--json", help="also write the figures to this file")
    args = p.parse_args(argv)
    out: dict = {"config": args.config, "native": [], "pipeline": {}}
    print(f"proleg.bench: {args.config}, control period 20 ms, random actions in [-1, 1]"
          f" (alone) unless marked")
    print(f"{'engine':<8}{'envs':>5}{'threads':>8}{'env-steps/s':>14}{'robot-steps/s':>15}"
          f"{'sim s/wall s':>14}{'vs pipeline':>13}")
    for engine in args.engines:
        # The machine's speed drifts over minutes: the pipeline is measured before each
        # figure and its best counts, so every ratio compares runs minutes apart at most.
        pipes = []
        rows = []
        configs = [(n, t, False) for n in args.envs for t in args.threads]
        configs.append((max(args.envs), 1, True))
        for n, t, residual in configs:
            _pin(_ONE)
            pipes.append(_native.pipeline_rate(args.config, engine, args.pipeline_seconds))
            _pin(None)
            rows.append(native(args.config, engine, n, t, args.seconds, residual))
        pipe = max(pipes)
        out["pipeline"][engine] = pipe
        for r, (n, t, residual) in zip(rows, configs):
            r["vs_pipeline"] = r["robot_steps_per_s"] / pipe
            r["residual_zero_actions"] = residual
            out["native"].append(r)
            what = "  (the file's gait: residual, zero actions)" if residual else ""
            print(f"{engine:<8}{n:>5}{t:>8}{r['env_steps_per_s']:>14.0f}"
                  f"{r['robot_steps_per_s']:>15.0f}{r['sim_s_per_s']:>13.1f}x"
                  f"{r['vs_pipeline']:>12.2f}x{what}")
        print(f"{engine:<8}{'proleg bench pipeline, 1 robot/world, 1 core:':>42}{pipe:>15.0f}"
              f"{pipe * 0.001:>13.1f}x")
    if args.peers > 0:
        try:
            import gymnasium

            env_cls, skip = exported_mujoco_env(args.config, 0.02)
            plain = gymnasium_sync(env_cls, args.peers, skip, 0.02, args.seconds)
            swimmer = gymnasium_sync(lambda: gymnasium.make("Swimmer-v5"), args.peers, 4, 0.04,
                                     args.seconds)
        except ImportError as e:
            print(f"yardsticks skipped: {e} (pip install gymnasium[mujoco])")
        else:
            out["gymnasium_mujoco_env"] = plain
            out["swimmer_v5"] = swimmer
            print(f"yardsticks, SyncVectorEnv of {args.peers}, 1 core:")
            for name, r in [("plain Gymnasium MujocoEnv, exported MJCF", plain),
                            ("Gymnasium Swimmer-v5 (no contacts)", swimmer)]:
                print(f"  {name:<42}{r['env_steps_per_s']:>10.0f} env-steps/s"
                      f"{r['physics_steps_per_s']:>10.0f} physics steps/s"
                      f"{r['sim_s_per_s']:>8.1f}x")
            ours = [r for r in out["native"]
                    if r["engine"] == "mujoco" and r["threads"] == 1
                    and r["envs"] == max(args.envs) and not r["residual_zero_actions"]]
            if ours:
                ratio = ours[0]["env_steps_per_s"] / plain["env_steps_per_s"]
                out["mujoco_vs_plain_gymnasium"] = ratio
                print(f"native MuJoCo vector env ({max(args.envs)} envs, 1 thread) vs the plain "
                      f"Gymnasium MujocoEnv: {ratio:.2f}x env-steps/s")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
