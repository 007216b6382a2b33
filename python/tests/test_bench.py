"""``python -m proleg.bench`` on a suite task's course: the pipeline figure and the vector
environment's rows both run on the course, and bad course options are refused by name."""

import json

import pytest

import proleg
from proleg import _native
from proleg import bench
from proleg.registration import SUITE


def test_pipeline_on_a_course_refuses_an_unknown_family():
    path = proleg.scenario_path("demo.simulation.xml")
    with pytest.raises(ValueError, match="terrain"):
        _native.pipeline_rate(path, "rapier", 0.2, terrain="lava",
                              suite=proleg.scenario_path(SUITE))


def test_pipeline_on_a_course_needs_the_suite():
    path = proleg.scenario_path("demo.simulation.xml")
    with pytest.raises(ValueError, match="suite"):
        _native.pipeline_rate(path, "rapier", 0.2, terrain="pegs")


def test_bench_on_a_course_writes_its_rows(tmp_path, engine):
    out = tmp_path / "bench.json"
    code = bench.main(["--engines", engine, "--envs", "2", "--threads", "1", "--seconds",
                       "0.5", "--pipeline-seconds", "0.2", "--rounds", "1", "--terrain",
                       "pegs", "--terrain-seed", "3", "--json", str(out)])
    assert code == 0
    figures = json.loads(out.read_text())
    assert figures["course"] == {"terrain": "pegs", "difficulty": "medium", "terrain_seed": 3}
    assert figures["pipeline"][engine] > 0
    rows = figures["native"]
    assert {(r["envs"], r["residual_zero_actions"]) for r in rows} == {(2, False), (2, True)}
    assert all(r["robot_steps_per_s"] > 0 and r["vs_pipeline"] > 0 for r in rows)
