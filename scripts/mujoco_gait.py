#!/usr/bin/env python3
"""Replays a proleg gait in MuJoCo: the cross-engine check of `proleg export mjcf --gait`.

Usage: mujoco_gait.py MODEL.xml MODEL.gait.tsv

Loads the exported MJCF, sets every position servo to the target proleg's servos had at
each step (the TSV: time, then one column per joint in degrees), steps MuJoCo at the
model's timestep and prints the horizontal displacement of the robot's centre of mass
(its root body's subtree), the same measure `proleg` prints.
"""
import math
import sys

import mujoco
import numpy as np


def main(model_path, gait_path):
    model = mujoco.MjModel.from_xml_path(model_path)
    data = mujoco.MjData(model)
    with open(gait_path) as f:
        header = f.readline().rstrip("\n").split("\t")
        rows = np.loadtxt(f, delimiter="\t", ndmin=2)
    joints = header[1:]
    actuators = [model.actuator(name).id for name in joints]
    free = [j for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE
            and model.joint(j).name.endswith("_free")]
    if len(free) != 1:
        sys.exit(f"{model_path}: expected one robot root with a free joint, found {len(free)}")
    root = model.jnt_bodyid[free[0]]
    mujoco.mj_forward(model, data)
    start = data.subtree_com[root].copy()
    for row in rows:
        data.ctrl[actuators] = np.radians(row[1:])
        mujoco.mj_step(model, data)
    if not np.all(np.isfinite(data.qpos)):
        sys.exit("MuJoCo blew up: non-finite positions")
    end = data.subtree_com[root]
    shift = math.hypot(end[0] - start[0], end[1] - start[1])
    print(f"mujoco {mujoco.__version__}: {len(rows)} steps of {model.opt.timestep} s, "
          f"displacement {shift:.4f} m")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
