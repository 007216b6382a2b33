"""The browser's 3D replay of a stepped episode: an environment made with ``replay_fps``
records each episode as it is stepped (:meth:`ProlegEnv.replay`), and :func:`save_html`
writes one self-contained page (the viewer of ``proleg run --html``, three.js and the
stream inlined) that plays it from disk with no server: orbit, scrub, 0.1x to 10x, the
joint angles and the score over time. Two replays play side by side on one timeline (an
open-loop gait against a learned policy, rapier against MuJoCo)."""

from __future__ import annotations

import os

from . import _native

Replay = _native.Replay


def save_html(path: str | os.PathLike, *replays: Replay) -> tuple[str, int]:
    """Writes the page playing ``replays`` (one, or two on one timeline) to ``path``;
    returns the file written and its size in bytes."""
    for r in replays:
        if not isinstance(r, Replay):
            raise TypeError(
                f"{type(r).__name__}: give replays (env.replay()), one or two"
            )
    path = os.fspath(path)
    return path, _native.write_html(path, list(replays))
