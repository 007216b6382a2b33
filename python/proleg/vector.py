"""N proleg environments as one Gymnasium ``VectorEnv``, stepped inside Rust on a thread
pool with the interpreter released: the observations of all environments come back as one
(num_envs, obs) float64 array, the infos as a dict of arrays (each key with its ``_key``
mask, as Gymnasium's vector environments give them).

Autoreset follows ``autoreset_mode``: ``NEXT_STEP`` (Gymnasium's default: the step after an
episode ends resets that environment, ignores its action and returns reward 0),
``SAME_STEP`` (the ending step returns the new episode's first observation; the last one
is ``info["final_obs"][i]``, its info ``info["final_info"]``) or ``DISABLED`` (reset with
``options={"reset_mask": mask}``). The arrays are the same, bit for bit, whatever the
number of threads: each world is stepped by one thread at a time and shares nothing.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from . import _native
from .envs import options_doc

_INFO_KEYS = ("time", "score", "energy", "exit")


class ProlegVectorEnv(VectorEnv):
    """``num_envs`` environments of one simulation file, ``autoreset_mode`` Gymnasium's
    (or its name). Keyword options (their defaults are the library's):
    """

    def __init__(
        self,
        path: str | os.PathLike,
        num_envs: int = 1,
        autoreset_mode: AutoresetMode | str | None = None,
        render_mode: str | None = None,
        **options: Any,
    ):
        if render_mode is not None:
            raise ValueError(f"render_mode {render_mode!r} is not offered by the vector env")
        if autoreset_mode is not None:
            options["autoreset"] = autoreset_mode
        self._venv = _native.VecEnv(os.fspath(path), num_envs, **options)
        mode_ = AutoresetMode[self._venv.autoreset.upper()]
        self.autoreset_mode = mode_
        self.num_envs = num_envs
        self.render_mode = None
        self.single_action_space = spaces.Box(
            -1.0, 1.0, (self._venv.action_len,), np.float32
        )
        self.single_observation_space = spaces.Box(
            -np.inf, np.inf, (self._venv.obs_len,), np.float64
        )
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        #: The name of every observation index.
        self.observation_names: list[str] = self._venv.observation_names
        self.metadata = {"autoreset_mode": mode_, "render_modes": []}
        self.closed = False

    @property
    def threads(self) -> int:
        """Threads stepping the worlds."""
        return self._venv.threads

    @property
    def max_steps(self) -> int:
        """Steps per episode."""
        return self._venv.max_steps

    @property
    def steps_per_action(self) -> int:
        """Physics steps per environment step."""
        return self._venv.steps_per_action

    def reset(
        self,
        *,
        seed: int | list[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Resets every environment (or those of ``options["reset_mask"]``), environment i
        with ``seed + i``, or with the seeds of a list."""
        mask = None if options is None else options.get("reset_mask")
        if mask is not None:
            mask = np.ascontiguousarray(mask, dtype=np.bool_)
            if mask.shape != (self.num_envs,):
                raise ValueError(
                    f"reset_mask of shape {mask.shape}, expected ({self.num_envs},)"
                )
        if isinstance(seed, (list, tuple)):
            if len(seed) != self.num_envs:
                raise ValueError(f"{len(seed)} seeds for {self.num_envs} environments")
            obs = info = None
            for i, s in enumerate(seed):
                if mask is not None and not mask[i]:
                    continue
                one = np.zeros(self.num_envs, dtype=np.bool_)
                one[i] = True
                obs, info = self._venv.reset(_seed(s), one)
            if obs is None:
                obs, info = self._venv.reset(None, np.zeros(self.num_envs, dtype=np.bool_))
        else:
            if isinstance(seed, int):
                self._np_random_seed = seed
            obs, info = self._venv.reset(_seed(seed), mask)
        return obs, self._infos(info)

    def step(
        self, actions
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """One step of every environment with its row of ``actions``."""
        a = np.ascontiguousarray(actions, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(f"actions of shape {a.shape}, expected {self.action_space.shape}")
        obs, rewards, terminated, truncated, info = self._venv.step(a)
        return obs, rewards, terminated, truncated, self._infos(info)

    def _infos(self, native: dict[str, Any]) -> dict[str, Any]:
        """Gymnasium's vector infos from the native arrays."""
        infos: dict[str, Any] = {}
        every = np.ones(self.num_envs, dtype=np.bool_)
        final = native.get("_final_obs")
        if final is not None and final.any():
            final_obs = np.full(self.num_envs, None, dtype=object)
            for i in np.flatnonzero(final):
                final_obs[i] = native["final_obs"][i]
            infos["final_obs"], infos["_final_obs"] = final_obs, final
            final_info = {}
            for key in _INFO_KEYS:
                final_info[key] = np.asarray(native[key])
                final_info["_" + key] = final.copy()
            if "terrain_seed" in native:
                final_info["terrain_seed"] = np.asarray(native["terrain_seed"])
                final_info["_terrain_seed"] = final & native["_terrain_seed"]
            infos["final_info"], infos["_final_info"] = final_info, final
            # The environments that reset start a new episode: their own info is its first.
            for key in ("time", "score", "energy"):
                native[key] = np.where(final, 0.0, native[key])
            native["exit"] = ["" if f else e for f, e in zip(final, native["exit"])]
            if "terrain_seed" in native:
                native["terrain_seed"] = np.where(
                    final, native["running_terrain_seed"], native["terrain_seed"]
                )
        for key in _INFO_KEYS:
            infos[key] = np.asarray(native[key])
            infos["_" + key] = every
        if "terrain_seed" in native:
            # A suite task's course: the terrain seed of each environment's episode.
            infos["terrain_seed"] = np.asarray(native["terrain_seed"])
            infos["_terrain_seed"] = np.asarray(native["_terrain_seed"])
        infos["reset"], infos["_reset"] = native["reset"], every
        return infos

    def close_extras(self, **kwargs: Any) -> None:
        """Frees the worlds and the thread pool."""
        self._venv.close()


def _seed(seed: int | None) -> int | None:
    if seed is not None and seed < 0:
        raise ValueError(f"seed {seed}: give a non-negative integer")
    return seed


ProlegVectorEnv.__doc__ = (ProlegVectorEnv.__doc__ or "") + "\n" + options_doc() + "\n"
