"""The shipped scenarios as Gymnasium ids: ``gymnasium.make("proleg/FlatCrawl-v0")`` makes a
:class:`proleg.ProlegEnv`, ``gymnasium.make_vec`` a natively vectorized
:class:`proleg.ProlegVectorEnv`. Any keyword of :class:`proleg.ProlegEnv` can be passed to
either (``engine="mujoco"``, ``mode="residual"``, ``control_period=0.05``, ...).

The locomotion suite's tasks have an id per terrain family (``proleg/Pegs-v0``): the demo
snake on a course of the family, ``difficulty="medium"`` unless given (``"easy"``,
``"hard"`` or a tier's number), a train course drawn per reset unless ``terrain_seed`` is
given, the task's 60-s episodes. The held-out families (channel, rubble) have no train
courses: their ids need ``split="test"``, which draws the task's test courses (for scoring,
never for training)."""

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


#: Id -> terrain family of the locomotion suite (``configs/suites/locomotion.suite.xml``).
TASKS = {
    "proleg/Rough-v0": "rough",
    "proleg/Hills-v0": "hills",
    "proleg/Steps-v0": "steps",
    "proleg/StairFlights-v0": "stairs",
    "proleg/Slope-v0": "slope",
    "proleg/Pegs-v0": "pegs",
    "proleg/Channel-v0": "channel",
    "proleg/Rubble-v0": "rubble",
}

#: The suite the task ids run.
SUITE = "suites/locomotion.suite.xml"


def register_envs() -> None:
    """Registers every id of :data:`SCENARIOS` and :data:`TASKS` (again, harmlessly, on a
    second call)."""
    ids = {env_id: {"path": scenario_path(file)} for env_id, (file, _) in SCENARIOS.items()}
    for env_id, family in TASKS.items():
        ids[env_id] = {
            "path": scenario_path("demo.simulation.xml"),
            "terrain": family,
            "suite": scenario_path(SUITE),
        }
    for env_id, kwargs in ids.items():
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point="proleg.envs:ProlegEnv",
            vector_entry_point="proleg.vector:ProlegVectorEnv",
            kwargs=kwargs,
        )
