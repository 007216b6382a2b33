"""An environment made with replay_fps records each episode as it is stepped: save_html
writes it as the self-contained 3D replay page (the one `proleg run --html` writes), on
either engine, the same bytes for the same seed and actions, two replays side by side."""

import json
import re

import numpy as np
import pytest

import proleg


def stepped(path, engine, seed, **options):
    env = proleg.ProlegEnv(path, engine=engine, replay_fps=25, duration=1.0, **options)
    env.reset(seed=seed)
    steps, done = 0, False
    while not done:
        action = np.sin(0.3 * steps + np.arange(env.action_space.shape[0]))
        _, _, terminated, truncated, _ = env.step(action)
        steps += 1
        done = terminated or truncated
    return env, steps


def streams_of(page: str) -> list:
    """The streams a page inlines (its one JSON array)."""
    found = re.search(r'<script id="replay-streams" type="application/json">(.*?)</script>', page, re.S)
    assert found, "the page inlines its streams"
    return json.loads(found.group(1))


def test_a_stepped_episode_saves_as_a_replay_page_on_either_engine(tmp_path, demo, engine):
    env, steps = stepped(demo, engine, seed=5)
    assert steps == 50
    replay = env.replay()
    assert replay.frames == 26 and replay.frame_seconds == pytest.approx(0.04)
    assert "episode 1 (seed 5)" in replay.label and "duration" in replay.end
    assert engine in replay.engine
    first, _ = replay.pose(0, 0)
    last, _ = replay.pose(replay.frames - 1, 0)
    assert np.linalg.norm(np.subtract(last, first)) > 1e-3, "the robot moved"
    with pytest.raises(ValueError, match="26 frames"):
        replay.pose(26, 0)

    path, size = env.save_html(tmp_path / "episode.html", label="a <b>bold</b> try")
    page = (tmp_path / "episode.html").read_text()
    assert path == str(tmp_path / "episode.html") and size == len(page.encode())
    (stream,) = streams_of(page)
    assert stream["frames"] == 26 and stream["label"] == "a <b>bold</b> try"
    assert "<b>" not in page, "markup in a label stays inside a JSON string"


def test_the_same_seed_and_actions_give_the_same_replay(demo):
    a, _ = stepped(demo, "rapier", seed=9)
    b, _ = stepped(demo, "rapier", seed=9)
    c, _ = stepped(demo, "rapier", seed=10)
    assert a.replay().to_json() == b.replay().to_json()
    assert a.replay().to_json() != c.replay().to_json()


def test_two_replays_play_side_by_side_and_bad_calls_say_why(tmp_path, demo):
    gait, _ = stepped(demo, "rapier", seed=1)
    other, _ = stepped(demo, "rapier", seed=2)
    _, size = proleg.save_html(tmp_path / "both.html", gait.replay("one"), other.replay("two"))
    streams = streams_of((tmp_path / "both.html").read_text())
    assert [s["label"] for s in streams] == ["one", "two"] and size > 0
    with pytest.raises(ValueError, match="one, or two"):
        proleg.save_html(tmp_path / "three.html", *[gait.replay()] * 3)
    with pytest.raises(TypeError, match="give replays"):
        proleg.save_html(tmp_path / "bad.html", "episode")

    # Mid-episode: the frames so far; a reset starts a new recording.
    gait.reset(seed=3)
    for _ in range(4):
        gait.step(np.zeros(gait.action_space.shape))
    so_far = gait.replay()
    assert so_far.frames == 3 and "goes on" in so_far.end and "episode 2" in so_far.label

    quiet = proleg.ProlegEnv(demo)
    quiet.reset(seed=0)
    with pytest.raises(RuntimeError, match="replay_fps"):
        quiet.save_html(tmp_path / "none.html")
    with pytest.raises(ValueError, match="replay_fps"):
        proleg.ProlegEnv(demo, replay_fps=-1)
    with pytest.raises(ValueError, match="ProlegEnv"):
        proleg.ProlegVectorEnv(demo, 2, replay_fps=30)
    assert not (tmp_path / "none.html").exists()
