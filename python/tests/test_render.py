"""render_mode="rgb_array" draws the world through the off-screen renderer of `proleg run
--video`, and save_video writes an episode's frames as a video."""

import shutil

import numpy as np
import pytest

import proleg


def colours(frame):
    return len(np.unique(frame.reshape(-1, 3), axis=0))


def test_rgb_array_frames_show_the_moving_robot_and_save_as_a_video(tmp_path, demo, capfd, monkeypatch):
    # No desktop session, as on a cluster node: the renderer prints no error that is none.
    monkeypatch.delenv("XDG_RUNTIME_DIR", raising=False)
    env = proleg.ProlegEnv(demo, render_mode="rgb_array", render_size=(320, 240))
    env.reset(seed=1)
    first = env.render()
    assert first.shape == (240, 320, 3) and first.dtype == np.uint8
    assert colours(first) > 50, "a lit scene, not a blank picture"
    assert "error" not in capfd.readouterr().err.lower()
    frames = [first]
    for _ in range(25):
        env.step(np.sin(np.arange(5) + len(frames)))
        frames.append(env.render())
    assert not np.array_equal(frames[0], frames[-1]), "the robot moved"
    before = env._env.com()
    env.step(np.zeros(5))
    after_step = env._env.com()
    env.render()
    assert np.array_equal(env._env.com(), after_step) and not np.array_equal(before, after_step)
    env.reset(seed=2)
    assert colours(env.render()) > 50, "a reset world is drawn too"
    out = tmp_path / ("episode.mp4" if shutil.which("ffmpeg") else "episode")
    path, count = proleg.save_video(frames, out, fps=50)
    assert count == len(frames) and (tmp_path / path).exists()
    env.close()


def test_without_a_render_mode_render_returns_nothing_and_bad_modes_raise(demo):
    assert proleg.ProlegEnv(demo).render() is None
    with pytest.raises(ValueError, match="not offered"):
        proleg.ProlegEnv(demo, render_mode="human")
    with pytest.raises(ValueError, match="no frames"):
        proleg.save_video([], "nothing.mp4")
