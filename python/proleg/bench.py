"""``python -m proleg.bench``: the environments' throughput on this machine, in one run.

For each engine: the native vector environment (:class:`proleg.ProlegVectorEnv`, random
actions, the default 20-ms control period) with N = 1, 16 and 64 environments on 1 and 2
threads, as environment steps per second, physics robot-steps per second and simulated
seconds per wall second, beside ``proleg bench``'s one-core pipeline figure for the same
file and engine (one robot in one world, the file's own gait, best of three). Then, on one
core, the yardsticks: a plain Gymnasium ``MujocoEnv`` of the same robot (the MJCF
``proleg export mjcf`` writes: position servos, the same control period, a forward-progress
reward) under ``SyncVectorEnv``, and Gymnasium's ``Swimmer-v5``.

Every figure is the best of three rounds, each round measuring every row once in turn (the
machines here are shared VMs whose speed drifts from minute to minute, as ``proleg bench``
says: interleaved rounds expose every row to the same drift, so the ratios compare like
with like); single-thread figures run pinned to one core (the process's first allowed
CPU). Every environment has the file's episode length (truncated at its duration and
reset, the plain Gymnasium one through ``TimeLimit`` as ``gymnasium.make`` would).
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


ROUNDS = 3


def _timed_steps(step, actions: np.ndarray, steps: int) -> float:
    """Wall seconds of ``steps`` calls of ``step`` with the rows of ``actions`` in turn,
    after a warm-up."""
    for k in range(3):
        step(actions[k % len(actions)])
    t = time.perf_counter()
    for k in range(steps):
        step(actions[k % len(actions)])
    return time.perf_counter() - t


def native(
    path: str, engine: str, n: int, threads: int, seconds: float, residual: bool = False,
    **course,
) -> dict:
    """The native vector environment, one run: ``seconds`` simulated per environment (at
    least 25 steps); episodes end and reset as they would in training. Random actions, or
    with ``residual`` zero actions added to the file's gait (the pipeline's physics).
    ``course``: a suite task's options (``terrain``, ``difficulty``, ``suite``,
    ``terrain_seed``), as the pipeline gets them."""
    _pin(_ONE if threads == 1 else None)
    mode = "residual" if residual else "alone"
    venv = ProlegVectorEnv(path, n, threads=threads, engine=engine, mode=mode, **course)
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
    it; its reward is the root's progress along +y (the demo's heading) per second. Returns
    its class, its frame skip and the episode length in steps (the file's duration)."""
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

    episode = round(_native.load(path).duration / control_period)
    return ExportedRobotEnv, frame_skip, episode


def gymnasium_sync(make_one, n: int, frame_skip: int, seconds_per_step: float, seconds: float) -> dict:
    """``SyncVectorEnv`` of ``n`` environments from ``make_one``, on one core, one run."""
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


def _args(argv: list[str] | None) -> argparse.Namespace:
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
    p.add_argument("--rounds", type=int, default=ROUNDS,
                   help="rounds over every row; each figure is its best round")
    p.add_argument("--json", help="also write the figures to this file")
    p.add_argument("--terrain", help="a suite family (pegs, hills, ...): every row on one of"
                   " its courses, the pipeline too (the Gymnasium yardsticks are skipped)")
    p.add_argument("--difficulty", default="medium", help="the task's tier (with --terrain)")
    p.add_argument("--terrain-seed", type=int, default=1,
                   help="the course every row runs on (with --terrain; default 1, a train course)")
    p.add_argument("--resets", action="store_true",
                   help="instead: what a reset costs on the suite's task ids (a new course, a seen one)")
    return p.parse_args(argv)


#: The ids whose resets ``--resets`` times: the flat demo, the largest height field, the
#: most bodies.
RESET_IDS = ("proleg/FlatCrawl-v0", "proleg/Rough-v0", "proleg/Pegs-v0")


def reset_costs(engines: list[str], resets: int = 40) -> list[dict]:
    """Wall milliseconds of a reset per id and engine: the median over resets that met a
    course for the first time (generated, its world's model built) and over those on a
    course met before (kept by the environment), one core."""
    import gymnasium

    _pin(_ONE)
    out = []
    for engine in engines:
        for env_id in RESET_IDS:
            env = gymnasium.make(env_id, engine=engine, difficulty="hard") \
                if env_id != "proleg/FlatCrawl-v0" else gymnasium.make(env_id, engine=engine)
            met: set = set()
            new, seen = [], []
            for seed in range(resets):
                t = time.perf_counter()
                _, info = env.reset(seed=seed)
                ms = (time.perf_counter() - t) * 1000.0
                course = info.get("terrain_seed")
                (seen if course is None or course in met else new).append(ms)
                met.add(course)
            env.close()
            out.append({"engine": engine, "id": env_id,
                        "new_course_ms": float(np.median(new)) if new else None,
                        "seen_course_ms": float(np.median(seen)) if seen else None,
                        "courses": len(met - {None})})
    _pin(None)
    return out


def _course(args: argparse.Namespace) -> dict:
    """The suite task's options every row and the pipeline get (none without --terrain)."""
    if not args.terrain:
        return {}
    from .registration import SUITE

    return {"terrain": args.terrain, "difficulty": args.difficulty,
            "suite": scenario_path(SUITE), "terrain_seed": args.terrain_seed}


def _yardsticks(args: argparse.Namespace) -> dict:
    """The plain Gymnasium ``MujocoEnv`` of the file's robot and ``Swimmer-v5``, as
    callables measuring one run each (none without Gymnasium's MuJoCo extra, none on a
    suite task's course: they know no terrain)."""
    if args.peers <= 0 or "mujoco" not in args.engines or args.terrain:
        return {}
    try:
        import gymnasium
        from gymnasium.wrappers import TimeLimit

        env_cls, skip, episode = exported_mujoco_env(args.config, 0.02)
    except ImportError as e:
        print(f"yardsticks skipped: {e} (pip install gymnasium[mujoco])")
        return {}
    return {
        "gymnasium_mujoco_env": lambda: gymnasium_sync(
            lambda: TimeLimit(env_cls(), episode), args.peers, skip, 0.02, args.seconds),
        "swimmer_v5": lambda: gymnasium_sync(
            lambda: gymnasium.make("Swimmer-v5"), args.peers, 4, 0.04, args.seconds),
    }


def _measure(args: argparse.Namespace) -> dict:
    """Every row, ``args.rounds`` times in turn; each row's best round."""
    rows = [(e, n, t, False) for e in args.engines for n in args.envs for t in args.threads]
    rows += [(e, max(args.envs), 1, True) for e in args.engines]
    yardsticks = _yardsticks(args)
    course = _course(args)
    best: dict = {}

    def keep(key, figure, rate_key):
        if key not in best or figure[rate_key] > best[key][rate_key]:
            best[key] = figure

    for _ in range(max(1, args.rounds)):
        for engine in args.engines:
            _pin(_ONE)
            rate = _native.pipeline_rate(args.config, engine, args.pipeline_seconds, **course)
            _pin(None)
            keep(("pipeline", engine), {"robot_steps_per_s": rate}, "robot_steps_per_s")
        for row in rows:
            keep(row, native(args.config, *row[:3], args.seconds, row[3], **course),
                 "robot_steps_per_s")
        for name, run in yardsticks.items():
            keep(name, run(), "env_steps_per_s")
    return {"rows": rows, "best": best}


def main(argv: list[str] | None = None) -> int:
    args = _args(argv)
    if args.resets:
        print("proleg.bench --resets: median wall ms of a reset, one core")
        print(f"{'engine':<8}{'id':<24}{'new course':>12}{'seen course':>13}{'courses':>9}")
        rows = reset_costs(args.engines)
        for r in rows:
            fmt = lambda v: "-" if v is None else f"{v:.1f}"  # noqa: E731
            print(f"{r['engine']:<8}{r['id']:<24}{fmt(r['new_course_ms']):>12}"
                  f"{fmt(r['seen_course_ms']):>13}{r['courses']:>9}")
        if args.json:
            with open(args.json, "w") as f:
                json.dump(rows, f, indent=1)
        return 0
    measured = _measure(args)
    best = measured["best"]
    course = _course(args)
    out: dict = {"config": args.config, "rounds": args.rounds, "native": [], "pipeline": {},
                 "course": {k: v for k, v in course.items() if k != "suite"}}
    where = (f" on {args.terrain}-{args.difficulty} course {args.terrain_seed}"
             if course else "")
    print(f"proleg.bench: {args.config}{where}, control period 20 ms, random actions in"
          f" [-1, 1] (alone) unless marked; best of {args.rounds} interleaved rounds")
    print(f"{'engine':<8}{'envs':>5}{'threads':>8}{'env-steps/s':>14}{'robot-steps/s':>15}"
          f"{'sim s/wall s':>14}{'vs pipeline':>13}")
    for engine in args.engines:
        pipe = best[("pipeline", engine)]["robot_steps_per_s"]
        out["pipeline"][engine] = pipe
        for row in [r for r in measured["rows"] if r[0] == engine]:
            _, n, t, residual = row
            r = dict(best[row])
            r["vs_pipeline"] = r["robot_steps_per_s"] / pipe
            r["residual_zero_actions"] = residual
            out["native"].append(r)
            what = "  (the file's gait: residual, zero actions)" if residual else ""
            print(f"{engine:<8}{n:>5}{t:>8}{r['env_steps_per_s']:>14.0f}"
                  f"{r['robot_steps_per_s']:>15.0f}{r['sim_s_per_s']:>13.1f}x"
                  f"{r['vs_pipeline']:>12.2f}x{what}")
        print(f"{engine:<8}{'proleg bench pipeline, 1 robot/world, 1 core:':>42}{pipe:>15.0f}"
              f"{pipe * 0.001:>13.1f}x")
    if "gymnasium_mujoco_env" in best:
        plain, swimmer = best["gymnasium_mujoco_env"], best["swimmer_v5"]
        out["gymnasium_mujoco_env"], out["swimmer_v5"] = plain, swimmer
        print(f"yardsticks, SyncVectorEnv of {args.peers}, 1 core, episodes of the file's"
              f" duration:")
        for name, r in [("plain Gymnasium MujocoEnv, exported MJCF", plain),
                        ("Gymnasium Swimmer-v5 (no contacts)", swimmer)]:
            print(f"  {name:<42}{r['env_steps_per_s']:>10.0f} env-steps/s"
                  f"{r['physics_steps_per_s']:>10.0f} physics steps/s"
                  f"{r['sim_s_per_s']:>8.1f}x")
        ratios = {}
        for n in sorted({args.peers, max(args.envs)}):
            ours = best.get(("mujoco", n, 1, False))
            if ours:
                ratios[n] = ours["env_steps_per_s"] / plain["env_steps_per_s"]
                print(f"native MuJoCo vector env ({n} envs, 1 thread) vs the plain Gymnasium "
                      f"MujocoEnv ({args.peers} envs): {ratios[n]:.2f}x env-steps/s")
        out["mujoco_vs_plain_gymnasium"] = {str(n): r for n, r in ratios.items()}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
