"""The Gymnasium environments: every registered id passes Gymnasium's checker on both
engines, episodes are reproducible, the reward is the optimizers' fitness, and bad input
raises."""

import os

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import proleg


@pytest.mark.parametrize("env_id", sorted(proleg.SCENARIOS))
def test_check_env_passes_for_every_registered_id(env_id, engine):
    env = gym.make(env_id, engine=engine)
    check_env(env.unwrapped)
    env.close()


#: The suite's held-out families: their ids run test courses only.
HELD_OUT = ("channel", "rubble")


@pytest.mark.parametrize("env_id", sorted(proleg.TASKS))
def test_check_env_passes_for_every_task_id(env_id, engine):
    split = "test" if proleg.TASKS[env_id] in HELD_OUT else "train"
    env = gym.make(env_id, engine=engine, split=split)
    check_env(env.unwrapped)
    env.close()


def test_a_task_id_draws_train_courses_per_reset_and_keeps_a_given_one(engine):
    env = gym.make("proleg/Pegs-v0", engine=engine, difficulty="hard")
    assert env.unwrapped.max_steps == 3000, "the task's 60 s at 20 ms"
    drawn = []
    for seed in range(8):
        obs, info = env.reset(seed=seed)
        assert 1 <= info["terrain_seed"] <= 20, "a train seed, never a test one"
        drawn.append(info["terrain_seed"])
    assert len(set(drawn)) > 2, drawn
    first, info = env.reset(seed=3)
    again, info_again = env.reset(seed=3)
    assert info["terrain_seed"] == info_again["terrain_seed"] == drawn[3]
    np.testing.assert_array_equal(first, again)
    env.close()
    env = gym.make("proleg/Pegs-v0", engine=engine, terrain_seed=7)
    for seed in range(3):
        assert env.reset(seed=seed)[1]["terrain_seed"] == 7
    env.close()
    env = gym.make("proleg/Rubble-v0", engine=engine, split="test")
    assert 101 <= env.reset(seed=1)[1]["terrain_seed"] <= 105
    env.close()


def test_bad_task_options_raise_value_errors():
    with pytest.raises(ValueError, match="held out"):
        gym.make("proleg/Channel-v0")
    with pytest.raises(ValueError, match="no pegs task of difficulty 0.3"):
        gym.make("proleg/Pegs-v0", difficulty=0.3)
    with pytest.raises(ValueError, match="difficulty"):
        gym.make("proleg/Pegs-v0", difficulty=1.5)
    with pytest.raises(ValueError, match="terrain"):
        gym.make("proleg/FlatCrawl-v0", terrain="lava")
    with pytest.raises(ValueError, match="terrain_seed is an option of a terrain task"):
        gym.make("proleg/FlatCrawl-v0", terrain_seed=3)


def test_the_registered_ids_make_proleg_envs_on_the_engine_asked(engine):
    env = gym.make("proleg/FlatCrawl-v0", engine=engine)
    assert isinstance(env.unwrapped, proleg.ProlegEnv)
    assert env.unwrapped.engine == engine
    assert env.action_space.shape == (5,)
    names = env.unwrapped.observation_names
    assert env.observation_space.shape == (len(names),)
    assert names[:2] == ["angle[0]", "angle[1]"] and "com_velocity.forward" in names
    env.close()


def rollout(env, seed, steps):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    out = [obs]
    for _ in range(steps):
        obs, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        out.append(obs)
    return np.array(out)


def test_the_same_seed_and_actions_give_the_same_trajectory_bit_for_bit(demo, engine):
    a = rollout(proleg.ProlegEnv(demo, engine=engine), 7, 60)
    b = rollout(proleg.ProlegEnv(demo, engine=engine), 7, 60)
    assert np.array_equal(a, b)
    assert not np.array_equal(a[10], a[20]), "the robot moves"


def test_the_residual_with_zero_action_is_the_files_own_gait_and_the_return_its_score(
    demo, engine
):
    """As a residual, the policy is one more module the kernel sums: with zero action the
    world runs exactly as `proleg run` runs the file, and the episode's return is the
    fitness the optimizers would give that run (distance along the start heading)."""
    env = proleg.ProlegEnv(demo, engine=engine, mode="residual", duration=2.0)
    env.reset(seed=1)
    total, steps, truncated = 0.0, 0, False
    while not truncated:
        _, reward, terminated, truncated, info = env.step(np.zeros(5))
        assert not terminated
        total += reward
        steps += 1
    assert steps == 100 and info["time"] == pytest.approx(2.0)
    sim = proleg.load(demo, engine=engine, seed=1)
    start, heading = sim.com(), np.radians(sim.heading())
    sim.run(2.0)
    end = sim.com()
    distance = (end[0] - start[0]) * np.cos(heading) + (end[1] - start[1]) * np.sin(heading)
    assert total == pytest.approx(distance, abs=1e-9)
    assert info["score"] == pytest.approx(distance, abs=1e-9)
    assert distance > 0.1
    assert np.array_equal(env._env.com(), end)


def test_randomize_draws_each_resets_physics_from_its_seed(demo, engine):
    """randomize=True: the same reset seed gives the same drawn world (the same
    trajectory under the same actions), another seed another world, and neither is the
    nominal one."""
    acts = np.random.default_rng(0).uniform(-1, 1, (40, 5))

    def trajectory(seed, **options):
        env = proleg.ProlegEnv(demo, engine=engine, **options)
        out = [env.reset(seed=seed)[0]] + [env.step(a)[0] for a in acts]
        env.close()
        return np.array(out)

    a = trajectory(7, randomize=True)
    assert np.array_equal(a, trajectory(7, randomize=True))
    assert not np.array_equal(a, trajectory(8, randomize=True))
    assert not np.array_equal(a, trajectory(7))
    with pytest.raises(ValueError, match="randomize"):
        proleg.ProlegEnv(demo, randomize=0.5)


def test_residual_observations_carry_the_generators_phase(demo):
    env = proleg.ProlegEnv(demo, mode="residual")
    assert env.observation_names[-2:] == ["phase[0].sin", "phase[0].cos"]
    obs, _ = env.reset(seed=1)
    obs, *_ = env.step(np.zeros(5))
    assert obs[-2] ** 2 + obs[-1] ** 2 == pytest.approx(1.0)
    alone = proleg.ProlegEnv(demo)
    assert len(alone.observation_names) == len(env.observation_names) - 2


def test_the_energy_term_lowers_the_reward_by_its_joules(demo):
    plain = proleg.ProlegEnv(demo, duration=0.4)
    costly = proleg.ProlegEnv(demo, duration=0.4, energy_weight=0.5)
    plain.reset(seed=2)
    costly.reset(seed=2)
    action = np.linspace(-1, 1, 5)
    r0, *_, i0 = plain.step(action)[1:]
    r1, *_, i1 = costly.step(action)[1:]
    assert i0["energy"] > 0 and i0["energy"] == i1["energy"]
    assert r1 == pytest.approx(r0 - 0.5 * i0["energy"])


def test_an_episode_is_truncated_at_its_duration(demo):
    env = proleg.ProlegEnv(demo, duration=0.1)
    env.reset(seed=0)
    flags = [env.step(np.zeros(5))[3] for _ in range(5)]
    assert flags == [False, False, False, False, True]
    with pytest.raises(RuntimeError, match="call reset"):
        env.step(np.zeros(5))


PLATE = """<?xml version="1.0" encoding="utf-8"?>
<Environment>
  <physicsengine type="ode"><odeproperties><gravity>0 0 -9.81</gravity>
  <selfcollision>1</selfcollision></odeproperties></physicsengine>
  <KinBody name="plate">
    <Body type="static">
      <Translation>0 0 -0.003</Translation>
      <Geom type="box"><extents>0.4 0.4 0.003</extents><friction>0.5</friction></Geom>
    </Body>
  </KinBody>
</Environment>
"""


def test_a_robot_that_crawls_off_the_world_terminates_its_episode(tmp_path):
    """The demo's snake on a plate 0.8 m wide: its own gait carries it over the edge, it
    falls, and the episode ends with exit "left_world" (the control window's rule)."""
    (tmp_path / "plate.env.xml").write_text(PLATE)
    configs = proleg.scenario_path("")
    sim = (tmp_path / "plate.simulation.xml")
    sim.write_text(
        f"""<?xml version="1.0" encoding="utf-8"?>
<simulation>
  <robot>{configs}/robots/snake5p.robot.xml</robot>
  <actuation>{configs}/actuation/snake5p_sine40.actuation.xml</actuation>
  <environment>plate.env.xml</environment>
  <simulationProperties><stepWidth>0.001</stepWidth><duration>30</duration><seed>1</seed>
  </simulationProperties>
</simulation>
"""
    )
    env = proleg.ProlegEnv(sim, mode="residual")
    env.reset(seed=1)
    for _ in range(env.max_steps):
        _, _, terminated, truncated, info = env.step(np.zeros(5))
        if terminated or truncated:
            break
    assert terminated and not truncated, info
    assert info["exit"] == "left_world"
    assert env._env.com()[2] < -1.0


def test_bad_actions_raise_and_the_env_lives_on(demo):
    env = proleg.ProlegEnv(demo)
    with pytest.raises(RuntimeError, match="before reset"):
        env.step(np.zeros(5))
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([0.0, np.nan, 0.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(4))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros((5, 1)))
    obs, *_ = env.step(np.zeros(5))
    assert np.all(np.isfinite(obs))
    env.close()
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros(5))


def test_bad_options_raise_value_errors(demo):
    with pytest.raises(ValueError, match="whole number"):
        proleg.ProlegEnv(demo, control_period=0.0025)
    with pytest.raises(ValueError, match="positive"):
        proleg.ProlegEnv(demo, control_period=-1)
    with pytest.raises(ValueError, match="alone"):
        proleg.ProlegEnv(demo, mode="sideways")
    with pytest.raises(ValueError, match="fitness"):
        proleg.ProlegEnv(demo, fitness="fastest")
    with pytest.raises(ValueError, match="energy_weight"):
        proleg.ProlegEnv(demo, energy_weight=float("nan"))
    with pytest.raises(proleg.ConfigError):
        proleg.ProlegEnv("no/such/file.simulation.xml")


def test_the_options_and_their_defaults_come_from_the_library(demo):
    options = {name: default for name, default, _ in proleg.ENV_OPTIONS}
    assert list(options) == [
        "engine", "control_period", "mode", "action_scale", "fitness",
        "energy_weight", "duration", "terrain", "difficulty", "suite", "split",
        "terrain_seed", "randomize", "replay_fps", "threads", "autoreset",
    ]
    for name, default, doc in proleg.ENV_OPTIONS:
        assert f"{name} = {default}: {doc}" in proleg.ProlegEnv.__doc__
        assert f"{name} = {default}" in proleg.ProlegVectorEnv.__doc__
    env = proleg.ProlegEnv(demo)
    assert env.control_period == float(options["control_period"])
    env.close()
    venv = proleg.ProlegVectorEnv(demo, 2)
    assert venv.threads == int(options["threads"]) == (os.cpu_count() or 1)
    assert venv.autoreset_mode.name.lower() == options["autoreset"].strip('"')
    venv.close()
    with pytest.raises(TypeError, match="wobble"):
        proleg.ProlegEnv(demo, wobble=1.0)
    with pytest.raises(ValueError, match="control_period"):
        proleg.ProlegEnv(demo, control_period="fast")
