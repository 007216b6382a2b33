"""The native vector environment: the same arrays whatever the thread count, both
autoreset modes against a hand-written loop over single environments (a suite task's
courses among the infos), the
Stable-Baselines3 adapter's same-step reset, and bad input raising."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import proleg
from proleg.sb3 import SB3VecEnv

N = 3
STEPS = 14  # episodes of 5 steps: several resets in every mode


def actions(seed, n=N, steps=STEPS):
    return np.random.default_rng(seed).uniform(-1, 1, (steps, n, 5))


def run_vector(venv, acts, seed=10):
    obs, _ = venv.reset(seed=seed)
    out = [(obs, None, None, None, None)]
    for a in acts:
        out.append(venv.step(a))
    return out


def test_the_vector_env_gives_the_same_arrays_on_one_and_two_threads(demo, engine):
    acts = actions(1)
    one = proleg.ProlegVectorEnv(demo, N, threads=1, engine=engine, duration=0.1)
    two = proleg.ProlegVectorEnv(demo, N, threads=2, engine=engine, duration=0.1)
    assert (one.threads, two.threads) == (1, 2)
    for a, b in zip(run_vector(one, acts), run_vector(two, acts)):
        for x, y in zip(a[:4], b[:4]):
            if x is not None:
                assert np.array_equal(x, y)


def test_next_step_autoreset_matches_a_hand_written_loop(demo, engine):
    acts = actions(2)
    venv = proleg.ProlegVectorEnv(demo, N, engine=engine, duration=0.1)
    assert venv.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    got = run_vector(venv, acts)
    envs = [proleg.ProlegEnv(demo, engine=engine, duration=0.1) for _ in range(N)]
    first = np.array([e.reset(seed=10 + i)[0] for i, e in enumerate(envs)])
    assert np.array_equal(got[0][0], first)
    done = [False] * N
    resets = 0
    for k, a in enumerate(acts):
        obs, rew, term, trunc, info = got[k + 1]
        for i, e in enumerate(envs):
            if done[i]:
                o, _ = e.reset()
                r, te, tr = 0.0, False, False
                assert info["reset"][i]
                resets += 1
            else:
                o, r, te, tr, _ = e.step(a[i])
            assert np.array_equal(obs[i], o) and rew[i] == r
            assert (term[i], trunc[i]) == (te, tr)
            done[i] = te or tr
    assert resets == 2 * N


def test_same_step_autoreset_matches_a_hand_written_loop(demo):
    acts = actions(3)
    venv = proleg.ProlegVectorEnv(demo, N, autoreset_mode="same_step", duration=0.1)
    got = run_vector(venv, acts)
    envs = [proleg.ProlegEnv(demo, duration=0.1) for _ in range(N)]
    for i, e in enumerate(envs):
        e.reset(seed=10 + i)
    finals = 0
    for k, a in enumerate(acts):
        obs, rew, term, trunc, info = got[k + 1]
        for i, e in enumerate(envs):
            o, r, te, tr, step_info = e.step(a[i])
            assert rew[i] == r and (term[i], trunc[i]) == (te, tr)
            if te or tr:
                assert info["_final_obs"][i]
                assert np.array_equal(info["final_obs"][i], o)
                assert info["final_info"]["time"][i] == step_info["time"]
                o, _ = e.reset()
                finals += 1
            assert np.array_equal(obs[i], o)
    assert finals == 2 * N


def test_a_task_vector_env_names_each_episodes_course_like_single_envs(engine):
    venv = gym.make_vec(
        "proleg/Pegs-v0", num_envs=N, engine=engine, duration=0.1,
        vectorization_mode="vector_entry_point", autoreset_mode="same_step",
    )
    envs = [gym.make("proleg/Pegs-v0", engine=engine, duration=0.1) for _ in range(N)]
    _, info = venv.reset(seed=10)
    seeds = [e.reset(seed=10 + i)[1]["terrain_seed"] for i, e in enumerate(envs)]
    assert info["_terrain_seed"].all() and list(info["terrain_seed"]) == seeds
    finals = 0
    for a in actions(4):
        _, _, term, trunc, info = venv.step(a)
        for i, e in enumerate(envs):
            _, _, te, tr, step_info = e.step(a[i])
            if te or tr:
                ended = step_info["terrain_seed"]
                assert info["final_info"]["_terrain_seed"][i]
                assert info["final_info"]["terrain_seed"][i] == ended
                step_info = e.reset()[1]
                finals += 1
            assert info["terrain_seed"][i] == step_info["terrain_seed"]
    assert finals == 2 * N
    assert len(set(info["terrain_seed"]) | set(seeds)) > 1, "courses differ between episodes"
    venv.close()


def test_disabled_autoreset_resets_with_a_mask(demo):
    venv = proleg.ProlegVectorEnv(demo, 2, autoreset_mode="disabled", duration=0.04)
    venv.reset(seed=0)
    venv.step(np.zeros((2, 5)))
    _, _, _, trunc, _ = venv.step(np.zeros((2, 5)))
    assert trunc.all()
    with pytest.raises(RuntimeError, match="call reset"):
        venv.step(np.zeros((2, 5)))
    obs, info = venv.reset(options={"reset_mask": np.array([True, True])})
    assert info["reset"].all() and obs.shape == (2, venv.single_observation_space.shape[0])
    venv.step(np.zeros((2, 5)))


def test_make_vec_uses_the_native_vector_env(engine):
    venv = gym.make_vec("proleg/FlatCrawl-v0", num_envs=4, engine=engine)
    assert isinstance(venv, proleg.ProlegVectorEnv) and venv.num_envs == 4
    obs, info = venv.reset(seed=1)
    assert obs.shape == (4, venv.single_observation_space.shape[0])
    obs, rew, term, trunc, info = venv.step(venv.action_space.sample())
    assert obs.dtype == np.float64 and rew.shape == (4,) and term.dtype == np.bool_
    assert info["_time"].all() and np.allclose(info["time"], 0.02)
    venv.close()


def test_the_sb3_adapter_resets_on_the_same_step_with_the_terminal_observation(demo):
    vec = SB3VecEnv(demo, num_envs=2, duration=0.06)
    single = [proleg.ProlegEnv(demo, duration=0.06) for _ in range(2)]
    vec.seed(5)
    obs = vec.reset()
    expected = np.array([e.reset(seed=5 + i)[0] for i, e in enumerate(single)])
    assert obs.dtype == np.float32 and np.array_equal(obs, expected.astype(np.float32))
    a = np.full((2, 5), 0.3, dtype=np.float32)
    for k in range(3):
        vec.step_async(a)
        obs, rewards, dones, infos = vec.step_wait()
    assert dones.all()
    for i, e in enumerate(single):
        e.step(a[i])
        e.step(a[i])
        last, r, _, truncated, _ = e.step(a[i])
        assert truncated and infos[i]["TimeLimit.truncated"]
        assert np.array_equal(infos[i]["terminal_observation"], last.astype(np.float32))
        assert rewards[i] == np.float32(r)
        assert not np.array_equal(obs[i], last.astype(np.float32)), "a new episode began"


def test_the_sb3_adapter_splits_its_environments_between_the_engines(demo, engine):
    """engines=[rapier, ENGINE]: the first two environments step as rapier's adapter's,
    the last one as ENGINE's (its seed continuing the count)."""
    mixed = SB3VecEnv(demo, num_envs=3, engines=["rapier", engine], duration=0.06)
    front = SB3VecEnv(demo, num_envs=2, engine="rapier", duration=0.06)
    back = SB3VecEnv(demo, num_envs=1, engine=engine, duration=0.06)
    mixed.seed(7)
    front.seed(7)
    back.seed(9)
    assert np.array_equal(mixed.reset(), np.concatenate([front.reset(), back.reset()]))
    ended = False
    for step in np.random.default_rng(3).uniform(-1, 1, (4, 3, 5)).astype(np.float32):
        mixed.step_async(step)
        front.step_async(step[:2])
        back.step_async(step[2:])
        obs, rewards, dones, infos = mixed.step_wait()
        parts = [front.step_wait(), back.step_wait()]
        for got, k in zip((obs, rewards, dones), range(3)):
            assert np.array_equal(got, np.concatenate([p[k] for p in parts]))
        for i, j in zip(infos, parts[0][3] + parts[1][3]):
            assert i.keys() == j.keys()
            assert all(np.array_equal(i[key], j[key]) for key in i)
        ended |= bool(dones.any())
    assert ended, "an episode ended and restarted on the way"
    with pytest.raises(ValueError, match="engine= or engines="):
        SB3VecEnv(demo, num_envs=2, engines=["rapier"], engine="rapier")
    with pytest.raises(ValueError, match="engine names"):
        SB3VecEnv(demo, num_envs=1, engines=["rapier", "mujoco"])
    with pytest.raises(ValueError, match="engine = .*\"rapier\" or \"mujoco\""):
        SB3VecEnv(demo, num_envs=2, engines=["rapier", "bullet"])


def test_bad_input_to_the_vector_env_raises(demo):
    venv = proleg.ProlegVectorEnv(demo, 2)
    venv.reset(seed=0)
    with pytest.raises(ValueError, match="shape"):
        venv.step(np.zeros((3, 5)))
    bad = np.zeros((2, 5))
    bad[1, 2] = np.inf
    with pytest.raises(ValueError, match="finite"):
        venv.step(bad)
    with pytest.raises(ValueError, match="seeds"):
        venv.reset(seed=[1, 2, 3])
    with pytest.raises(ValueError, match="at least one"):
        proleg.ProlegVectorEnv(demo, 0)
    with pytest.raises(ValueError, match="autoreset"):
        proleg._native.VecEnv(demo, 2, autoreset="sometimes")
    venv.close()
    venv.close()
    with pytest.raises(RuntimeError, match="closed"):
        venv.step(np.zeros((2, 5)))
