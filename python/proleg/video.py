"""Frames into a video: the encoder ``proleg run --video`` uses (ffmpeg, the format by the
file's extension; a folder, or no ffmpeg installed, gives numbered PNG files)."""

from __future__ import annotations

import os
from typing import Iterable

import numpy as np

from . import _native


def save_video(frames: Iterable[np.ndarray], path: str | os.PathLike, fps: int = 50) -> tuple[str, int]:
    """Writes (height, width, 3) uint8 frames (``env.render()``'s) to ``path``; returns
    the file (or folder) written and the number of frames."""
    writer = None
    for frame in frames:
        frame = np.ascontiguousarray(frame, dtype=np.uint8)
        if frame.ndim != 3 or frame.shape[2] != 3:
            raise ValueError(f"frame of shape {frame.shape}: give (height, width, 3) uint8 arrays")
        if writer is None:
            writer = _native.VideoWriter(os.fspath(path), frame.shape[1], frame.shape[0], fps)
        writer.write(frame)
    if writer is None:
        raise ValueError("no frames to write")
    return writer.close()
