"""Plugin modules load from Python as from the command line: the example plugins built by
``proleg plugin build``, found through ``PROLEG_PLUGINS`` as ``proleg run`` finds them, drive
a simulation to the displacement ``proleg run`` reports; without them the module is unknown
and the error names it. Each interpreter scans the plugin folders once, at its first load,
so every case runs in an interpreter of its own."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

import proleg

ROOT = Path(proleg.scenario_path("demo.simulation.xml")).parent.parent
CONFIG = ROOT / "plugins" / "configs" / "snake5p_square_wave.simulation.xml"


@pytest.fixture
def plugin_lib(tmp_path, proleg_bin):
    # `proleg plugin build` reuses the plugin workspace's cargo build (target/plugins).
    lib = tmp_path / "lib"
    built = subprocess.run(
        [proleg_bin, "plugin", "build", "--lib", str(lib)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=dict(os.environ, PROLEG_PLUGINS=""),
    )
    assert built.returncode == 0, built.stdout + built.stderr
    assert "module Square_wave" in built.stdout, built.stdout
    return lib


def _python(code: str, plugins: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code, str(CONFIG)],
        capture_output=True,
        text=True,
        env=dict(os.environ, PROLEG_PLUGINS=plugins),
    )


def test_a_plugin_module_simulation_runs_from_python_as_under_proleg_run(plugin_lib, proleg_bin):
    cli = subprocess.run(
        [proleg_bin, "run", str(CONFIG), "--duration", "4"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=dict(os.environ, PROLEG_PLUGINS=str(plugin_lib)),
    )
    assert cli.returncode == 0, cli.stderr
    line = next(l for l in cli.stdout.splitlines() if l.startswith("displacement"))
    cli_displacement = float(line.split()[1])
    assert cli_displacement > 0.1, cli.stdout

    ran = _python(
        "import sys, proleg\n"
        "s = proleg.load(sys.argv[1])\n"
        "print(s.modules())\n"
        "print(s.run(4.0)['displacement'])\n",
        str(plugin_lib),
    )
    assert ran.returncode == 0, ran.stderr
    modules, displacement = ran.stdout.strip().splitlines()
    assert "Square_wave" in modules, modules
    assert f"{float(displacement):.4f}" == f"{cli_displacement:.4f}"


def test_without_the_plugin_the_module_is_unknown_and_named(plugin_lib):
    ran = _python(
        "import sys, proleg\n"
        "try:\n"
        "    proleg.load(sys.argv[1])\n"
        "except proleg.ConfigError as e:\n"
        "    print(e.file, e.line)\n"
        "    print(e)\n",
        "",
    )
    assert ran.returncode == 0, ran.stderr
    where, message = ran.stdout.strip().split("\n", 1)
    assert where.endswith("snake5p_square_wave.actuation.xml 5"), where
    assert '"Square_wave"' in message, message
