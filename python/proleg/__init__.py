"""proleg from Python: simulations of chain-like modular robots and Gymnasium environments.

The work is done by the Rust library (``proleg._native``); this package gives it Python
shapes:

- :func:`load` a simulation file into a :class:`Simulation` to step and read,
- :class:`ProlegEnv`, a Gymnasium environment over any simulation file, and
  :class:`ProlegVectorEnv`, N of them stepped natively on a thread pool,
- registered ids for the shipped scenarios (``proleg/FlatCrawl-v0``, ``proleg/HillCourse-v0``,
  ``proleg/Stairs-v0``) and for the locomotion suite's terrain families (``proleg/Pegs-v0``,
  ... :data:`TASKS`), each on either engine (``engine="rapier"`` or ``"mujoco"``),
- :func:`read_store`, an experiment store as a pandas table,
- :meth:`ProlegEnv.render` (``render_mode="rgb_array"``) and :func:`save_video`,
- :meth:`ProlegEnv.save_html` (``replay_fps=30``) and :func:`save_html`, a stepped episode
  as a self-contained 3D replay page (one, or two side by side),
- :func:`proleg.sb3.SB3VecEnv`, the vector environment for Stable-Baselines3,
- :func:`save_policy` and :func:`load_policy`, a learned policy's network in the weights
  file proleg's policy module reads, run by the library's own forward pass.

Errors of the library arrive as exceptions with its message: a file that does not load as
:class:`ConfigError` (with ``file``, ``line`` and ``column``), bad input as ``ValueError``,
a closed environment as ``RuntimeError``, anything else as :class:`ProlegError`.
"""

from ._native import MUJOCO_LIBRARY as _MUJOCO_LIBRARY
from ._native import VERSION as __version__
from ._mujoco import use_wheel_library as _use_wheel_library
from ._native import ENV_OPTIONS, ConfigError, ProlegError, Simulation, load
from .envs import ProlegEnv, scenario_path
from .policy import load_policy, save_policy
from .registration import SCENARIOS, TASKS, register_envs
from .replay import Replay, save_html
from .store import read_store
from .vector import ProlegVectorEnv
from .video import save_video

register_envs()
# MuJoCo from the `mujoco` extra's wheel, unless PROLEG_MUJOCO names another.
_use_wheel_library(_MUJOCO_LIBRARY)

__all__ = [
    "ConfigError",
    "ENV_OPTIONS",
    "ProlegEnv",
    "ProlegError",
    "ProlegVectorEnv",
    "Replay",
    "SCENARIOS",
    "TASKS",
    "Simulation",
    "__version__",
    "load",
    "load_policy",
    "read_store",
    "save_html",
    "save_policy",
    "save_video",
    "scenario_path",
]
