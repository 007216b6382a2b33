"""Shared fixtures: the engines to test on (MuJoCo where its library is installed; with
PROLEG_REQUIRE_MUJOCO set it must be, as in scripts/test), the shipped scenarios, and the
proleg binary for the command-line comparisons."""

import os
import shutil
from pathlib import Path

import pytest

import proleg


def _mujoco_present() -> bool:
    try:
        proleg.load(proleg.scenario_path("demo.simulation.xml"), engine="mujoco").close()
        return True
    except proleg.ProlegError:
        return False


MUJOCO = _mujoco_present()
ENGINES = [
    "rapier",
    pytest.param(
        "mujoco",
        marks=pytest.mark.skipif(
            not MUJOCO and not os.environ.get("PROLEG_REQUIRE_MUJOCO"),
            reason="MuJoCo's library is not installed (scripts/install-mujoco)",
        ),
    ),
]


@pytest.fixture(params=ENGINES)
def engine(request):
    return request.param


@pytest.fixture
def demo():
    return proleg.scenario_path("demo.simulation.xml")


@pytest.fixture
def proleg_bin():
    """The proleg program: $PROLEG_BIN, or on the PATH."""
    found = os.environ.get("PROLEG_BIN") or shutil.which("proleg")
    if not found or not Path(found).exists():
        pytest.skip("no proleg program (set PROLEG_BIN)")
    return found
