"""A Gymnasium environment over any proleg simulation file.

The policy is one more module of the robot's control kernel: alone it drives every joint,
as a residual (``mode="residual"``) it adds to the file's own modules, which the kernel
sums (thesis fig. 4.4). An action is one value in [-1, 1] per joint; it moves the joint's
target by ``action_scale`` times half the joint's range (1 alone, 0.25 as a residual),
around the middle of its limits or around the modules' sum. The targets are held for one
control period (``control_period``, 20 ms by default).

The observation is float64, one value per name in :attr:`ProlegEnv.observation_names`:
joint angles (rad) and speeds (rad/s), tactile pads (0/1), laser ranges (m), gravity's
direction in the head's frame, the centre of mass's velocity in the heading frame
(forward, lateral, up; m/s), and, as a residual, sine and cosine of each generator's
phase.

With ``render_mode="rgb_array"``, :meth:`ProlegEnv.render` draws the world off-screen
through the renderer of ``proleg run --video``; :func:`proleg.save_video` writes frames
as a video (ffmpeg) or PNG files.

With ``replay_fps`` (frames per simulated second), every episode is recorded as it is
stepped: :meth:`ProlegEnv.replay` gives it and :meth:`ProlegEnv.save_html` writes it as a
self-contained page with the 3D viewer of ``proleg run --html`` (orbit, scrub, side by
side with another replay through :func:`proleg.save_html`).

The reward is the growth over the step of proleg's fitness (``fitness="distance"``: metres
along the start heading; also ``"displacement"`` and ``"speed"``) minus ``energy_weight``
per joule the servos put out: an episode's return is the optimizers' score of the same
episode. An episode terminates when the robot leaves the world or the physics diverges
(``info["exit"]`` says which) and is truncated at the file's duration (or ``duration``).
The same seed and actions give the same trajectory, bit for bit.
"""

from __future__ import annotations

import os
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces

from . import _native
from .replay import Replay, save_html


#: The shipped ``configs/`` a release wheel carries inside the package (scripts/release).
_PACKAGED_CONFIGS = os.path.join(os.path.dirname(__file__), "configs")


def configs_root() -> str:
    """Where the shipped simulation files are: ``$PROLEG_CONFIGS`` when set, else the
    copy a release wheel carries, else the ``configs/`` folder of the checkout the package
    was built from."""
    if os.environ.get("PROLEG_CONFIGS"):
        return os.environ["PROLEG_CONFIGS"]
    if os.path.isdir(_PACKAGED_CONFIGS):
        return _PACKAGED_CONFIGS
    return _native.CONFIGS


def scenario_path(file: str) -> str:
    """The path of a shipped simulation file (under :func:`configs_root`)."""
    return os.path.normpath(os.path.join(configs_root(), file))


def options_doc() -> str:
    """The keyword options every environment takes, with their defaults: the library's
    own list (``proleg.ENV_OPTIONS``), so no default is written in Python."""
    return "\n".join(
        f"    {name} = {default}: {doc}" for name, default, doc in _native.ENV_OPTIONS
    )


class ProlegEnv(gymnasium.Env):
    """One robot in one world of a simulation file (see the module's documentation).

    Keyword options (their defaults are the library's):
    """

    metadata = {"render_modes": ["rgb_array"]}

    def __init__(
        self,
        path: str | os.PathLike,
        render_mode: str | None = None,
        render_size: tuple[int, int] = (640, 480),
        **options: Any,
    ):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode {render_mode!r} is not offered: {self.metadata['render_modes']}"
            )
        self.render_mode = render_mode
        self._render_size = render_size
        self._renderer = None
        self._path = os.fspath(path)
        self._env = _native.Env(self._path, **options)
        self.action_space = spaces.Box(-1.0, 1.0, (self._env.action_len,), np.float32)
        self.observation_space = spaces.Box(
            -np.inf, np.inf, (self._env.obs_len,), np.float64
        )
        #: The name of every observation index.
        self.observation_names: list[str] = self._env.observation_names
        self.metadata = {
            **self.metadata,
            "render_fps": round(1.0 / self._env.control_period),
        }

    @property
    def engine(self) -> str:
        """The engine stepping the world (``"rapier"`` or ``"mujoco"``)."""
        return self._env.engine

    @property
    def control_period(self) -> float:
        """Simulated seconds per step."""
        return self._env.control_period

    @property
    def max_steps(self) -> int:
        """Steps per episode (then it is truncated)."""
        return self._env.max_steps

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Starts an episode in a fresh world built with ``seed`` (as ``proleg run`` builds
        it with the file's ``<seed>``); without one, the next seed of the stream the last
        seed started."""
        super().reset(seed=seed)
        if seed is not None and seed < 0:
            raise ValueError(f"seed {seed}: give a non-negative integer")
        return self._env.reset(seed)

    def step(self, action) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """Holds the targets of ``action`` for one control period."""
        a = np.ascontiguousarray(action, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(
                f"action of shape {a.shape}, expected {self.action_space.shape}"
            )
        return self._env.step(a)

    def render(self) -> np.ndarray | None:
        """With ``render_mode="rgb_array"``: the world now as an (height, width, 3) uint8
        array, drawn off-screen by the renderer ``proleg run --video`` uses (the camera
        follows the robot). The renderer is made at the first call."""
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            setting = _native.headless_vulkan_setting()
            if setting is not None:
                os.environ.setdefault(*setting)
            width, height = self._render_size
            self._renderer = _native.Renderer(self._path, width, height, self._env.engine)
        return self._renderer.frame(self._env)

    def replay(self, label: str | None = None) -> Replay:
        """The running episode's frames so far (all of them once it ended) for the 3D
        replay, titled ``label`` (else the file, episode and seed). Needs ``replay_fps``."""
        return self._env.replay(label)

    def save_html(self, path: str | os.PathLike, label: str | None = None) -> tuple[str, int]:
        """Writes the episode stepped since the last reset (so far, or all of it once it
        ended) as a self-contained 3D replay page; returns the file and its size in bytes.
        Needs ``replay_fps`` (e.g. ``proleg.ProlegEnv(file, replay_fps=30)``)."""
        return save_html(path, self.replay(label))

    def close(self) -> None:
        """Frees the world and the renderer (closing twice is fine)."""
        self._renderer = None
        self._env.close()


ProlegEnv.__doc__ = (ProlegEnv.__doc__ or "") + "\n" + options_doc() + "\n"
