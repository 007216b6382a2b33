"""Where the MuJoCo engine's library is, for a package installed from its wheel: the
registry's ``mujoco-core`` wheel (``pip install 'proleg[mujoco]'``) puts
``libmujoco.so.<version>`` in a ``mujoco/`` folder of site-packages; proleg reads
``PROLEG_MUJOCO`` (else ``~/.local/share/proleg/mujoco``, what ``scripts/install-mujoco``
fills), so the folder found is handed over through it. A ``PROLEG_MUJOCO`` the user set
wins; nothing is loaded here (the library loads at the first MuJoCo world)."""

from __future__ import annotations

import os
import sys


def library_from_wheel(file_name: str, paths: list[str] | None = None) -> str | None:
    """The first ``mujoco/<file_name>`` on ``paths`` (``sys.path``), or None."""
    for entry in sys.path if paths is None else paths:
        candidate = os.path.join(entry or os.curdir, "mujoco", file_name)
        if os.path.isfile(candidate):
            return os.path.abspath(candidate)
    return None


def use_wheel_library(file_name: str) -> str | None:
    """Points proleg at the ``mujoco-core`` wheel's library when the user named none;
    returns the library proleg will load, when known."""
    if os.environ.get("PROLEG_MUJOCO"):
        return os.environ["PROLEG_MUJOCO"]
    found = library_from_wheel(file_name)
    if found is not None:
        os.environ["PROLEG_MUJOCO"] = found
    return found
