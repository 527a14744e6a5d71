"""The CSV of a floating body: its motion and the fluid's loads on it, a row every interval.

``body_<name>.csv`` (`BodyRecorder`), one row per sample, columns:

    time [s];
    x, y, z [m]: the centre of gravity;
    qw, qx, qy, qz: the orientation as a unit quaternion (scalar first), the rotation from the body at t = 0;
    roll, pitch, yaw [deg]: the same as Euler angles, R = Rz(yaw) Ry(pitch) Rx(roll) (about the world's
    x, y and z axes, in that order; a 2D body's rotation about y is its pitch);
    vx, vy, vz [m/s]; wx, wy, wz [rad/s]: velocity of the centre of gravity, angular velocity (world);
    fx, fy, fz [N]; tx, ty, tz [N m]: the fluid's force and its torque about the centre of gravity
    (`shoal.body_coupling`), measured at the sample's particle positions;
    cfx, cfy, cfz [N]; ctx, cty, ctz [N m]: the same of the contact forces of the walls and the other bodies
    (`shoal.physics.contact`; zero while the body touches nothing).

2D bodies are per metre of width (N/m, N m/m).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from .recorder_state import Recorder

COLUMNS = ["time", "x", "y", "z", "qw", "qx", "qy", "qz", "roll", "pitch", "yaw", "vx", "vy", "vz", "wx", "wy", "wz",
           "fx", "fy", "fz", "tx", "ty", "tz", "cfx", "cfy", "cfz", "ctx", "cty", "ctz"]


def orientation(rotation):
    """(quaternion (w, x, y, z), (roll, pitch, yaw) [deg]) of a rotation matrix, R = Rz(yaw) Ry(pitch) Rx(roll)."""
    r = Rotation.from_matrix(np.asarray(rotation, float))
    x, y, z, w = r.as_quat()
    if w < 0:  # q and -q are one rotation: the one with w >= 0
        x, y, z, w = -x, -y, -z, -w
    yaw, pitch, roll = r.as_euler("ZYX", degrees=True)
    return (w, x, y, z), (roll, pitch, yaw)


class BodyRecorder(Recorder):
    """Samples floating body number `index` of ``model.floating`` and appends a row to ``body_<name>.csv``
    in `out_dir` (module docstring). Collective under MPI (the loads are summed over the ranks)."""

    def __init__(self, model, index, out_dir):
        self.index = index
        self.name = model.floating.bodies[index].name
        self.path = Path(out_dir) / f"body_{self.name}.csv"
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(COLUMNS)
        self.rows = []

    def __call__(self, sim):
        coupling = sim.model.floating
        centres = np.array([b.state.position for b in coupling.bodies])
        loads = sim.model.floating_loads(coupling.row, centres)[self.index].copy()  # the next call reuses its buffer
        contact = sim.model.floating_loads(coupling.row, centres, contact=True)[self.index]
        s = coupling.bodies[self.index].state
        q, euler = orientation(s.rotation)
        row = [sim.time, *s.position, *q, *euler, *s.velocity, *s.angular_velocity, *loads, *contact]
        row = [float(v) for v in row]
        self.rows.append(row)
        self.writer.writerow([f"{v:.12g}" for v in row])
        self.file.flush()

    def close(self):
        self.file.close()
