#!/usr/bin/env python3
"""Times MuJoCo's own `mujoco.rollout` on a model and a control sequence: the reference
figure `proleg bench --engine mujoco` prints beside proleg's pipeline on MuJoCo.

Usage: mujoco_rollout.py MODEL.xml CONTROLS.tsv [REPEATS]

CONTROLS.tsv holds one row per step, one column per actuator (the actuators' own units).
Prints `rollout <steps> steps, best of <repeats>: <steps/s> steps/s` for one thread.
"""
import sys
import time

import mujoco
import numpy as np
from mujoco import rollout


def main(model_path, controls_path, repeats):
    model = mujoco.MjModel.from_xml_path(model_path)
    data = mujoco.MjData(model)
    control = np.loadtxt(controls_path, ndmin=2)
    if control.shape[1] != model.nu:
        sys.exit(f"{controls_path}: {control.shape[1]} columns, the model has {model.nu} actuators")
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state, spec)
    steps = control.shape[0]
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        rollout.rollout(model, data, state[None, :], control[None, :, :])
        best = min(best, time.perf_counter() - start)
    print(f"rollout {steps} steps, best of {repeats}: {steps / best:.0f} steps/s")


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) == 4 else 3)
