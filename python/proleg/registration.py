"""The shipped scenarios as Gymnasium ids: ``gymnasium.make("proleg/FlatCrawl-v0")`` makes a
:class:`proleg.ProlegEnv`, ``gymnasium.make_vec`` a natively vectorized
:class:`proleg.ProlegVectorEnv`. Any keyword of :class:`proleg.ProlegEnv` can be passed to
either (``engine="mujoco"``, ``mode="residual"``, ``control_period=0.05``, ...)."""

import gymnasium

from .envs import scenario_path

#: Id -> (simulation file under the scenarios folder, what it is).
SCENARIOS = {
    "proleg/FlatCrawl-v0": (
        "demo.simulation.xml",
        "experiment 1's five-joint snake on a flat floor, 30 s",
    ),
    "proleg/HillCourse-v0": (
        "experiment2_adaptive.simulation.xml",
        "experiment 2: the tactile snake (five pads) at the irregular hill, 90 s",
    ),
    "proleg/Stairs-v0": (
        "gait_stairs.simulation.xml",
        "the five-joint snake at a flight of 20-mm steps, 20 s",
    ),
}


def register_envs() -> None:
    """Registers every id of :data:`SCENARIOS` (again, harmlessly, on a second call)."""
    for env_id, (file, _) in SCENARIOS.items():
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point="proleg.envs:ProlegEnv",
            vector_entry_point="proleg.vector:ProlegVectorEnv",
            kwargs={"path": scenario_path(file)},
        )
