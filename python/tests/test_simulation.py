"""proleg.load and Simulation: stepping, typed reads, writes, and errors as exceptions."""

import math

import numpy as np
import pytest

import proleg


def test_the_demo_crawls_and_its_state_reads_as_arrays(demo, engine):
    s = proleg.load(demo, engine=engine)
    assert s.engine == engine and s.dt == 0.001 and s.time == 0.0
    summary = s.run(2.0)
    assert summary["steps"] == 2000 and s.step_count == 2000
    assert summary["displacement"] > 0.1, summary
    angles = s.joint_angles()
    assert angles.dtype == np.float64 and angles.shape == (5,)
    assert np.all(np.abs(angles) <= 90.0) and np.any(np.abs(angles) > 1.0)
    assert s.joint_speeds().shape == (5,) and s.joint_torques().shape == (5,)
    assert np.allclose(s.com(), summary["end_com"])
    assert math.isfinite(s.heading()) and s.energy() > 0.0
    assert s.modules() == [("PatternGenerator_sinusoidal", [0, 1, 2, 3, 4])]


def test_the_same_seed_gives_the_same_trajectory(demo, engine):
    a, b = proleg.load(demo, engine=engine), proleg.load(demo, engine=engine)
    a.step(1500)
    b.step(1500)
    assert np.array_equal(a.joint_angles(), b.joint_angles())
    assert np.array_equal(a.com(), b.com())


def test_parameters_and_joint_targets_change_the_gait(demo):
    s = proleg.load(demo)
    assert s.parameter(0, "Amplitude") == 40.0
    s.set_parameter(0, "Amplitude", 10.0)
    assert s.parameter(0, "Amplitude", joint=3) == 10.0
    with pytest.raises(ValueError, match="outside"):
        s.set_parameter(0, "Amplitude", 500.0)
    with pytest.raises(ValueError, match="not a finite number"):
        s.set_parameter(0, "Amplitude", float("nan"))
    with pytest.raises(ValueError, match="no parameter"):
        s.set_parameter(0, "Wobble", 1.0)
    s.set_joint_targets(np.full(5, 20.0))
    s.step(1500)
    assert np.allclose(s.joint_angles(), 20.0, atol=1.0), s.joint_angles()
    with pytest.raises(ValueError, match="expected 5"):
        s.set_joint_targets(np.zeros(3))
    with pytest.raises(ValueError, match="finite"):
        s.set_joint_targets(np.array([0.0, 0.0, np.nan, 0.0, 0.0]))
    s.set_joint_targets(None)


def test_a_closed_simulation_raises_and_the_interpreter_lives_on(demo):
    s = proleg.load(demo)
    s.close()
    with pytest.raises(RuntimeError, match="closed"):
        s.step()
    assert proleg.load(demo).run(0.1)["steps"] == 100


def test_a_missing_file_is_a_config_error_naming_it(tmp_path):
    missing = tmp_path / "nothing.simulation.xml"
    with pytest.raises(proleg.ConfigError) as e:
        proleg.load(missing)
    assert "nothing.simulation.xml" in str(e.value)
    assert e.value.file.endswith("nothing.simulation.xml")


def test_a_malformed_file_is_a_config_error_with_line_and_column(tmp_path, demo):
    bad = tmp_path / "bad.simulation.xml"
    bad.write_text(
        '<?xml version="1.0"?>\n<simulation>\n  <robot>robots/snake5p.robot.xml</robt>\n'
        "</simulation>\n"
    )
    with pytest.raises(proleg.ConfigError) as e:
        proleg.load(bad)
    assert e.value.file.endswith("bad.simulation.xml")
    assert (e.value.line, e.value.column) == (3, 34), (e.value.line, e.value.column)
    assert str(e.value).startswith(str(bad)), str(e.value)


def test_an_unknown_engine_is_a_value_error(demo):
    with pytest.raises(ValueError, match="unknown engine"):
        proleg.load(demo, engine="bullet")
