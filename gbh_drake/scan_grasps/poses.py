"""Poses as a document writes them, and quaternions (w, x, y, z), in numpy."""

from __future__ import annotations

import numpy as np


def quaternion_matrix(q) -> np.ndarray:
    """The rotation (3, 3) of the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = np.asarray(q, dtype=float)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def matrix_quaternion(R: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z), w >= 0, of the rotation R (3, 3)."""
    R = np.asarray(R, dtype=float)
    trace = np.trace(R)
    if trace > 0:
        s = 2.0 * np.sqrt(trace + 1.0)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
        q = np.zeros(4)
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    q = np.asarray(q, dtype=float)
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def pose_entry(X: np.ndarray) -> dict:
    """A pose X_BF (4, 4) as the document writes it: ``matrix`` (4 rows), ``translation`` (m)
    and ``quaternion_wxyz`` (the rotation; ROS orders it x, y, z, w)."""
    X = np.asarray(X, dtype=float)
    return {"matrix": X.tolist(), "translation": X[:3, 3].tolist(),
            "quaternion_wxyz": matrix_quaternion(X[:3, :3]).tolist()}


def parse_pose(text: str) -> np.ndarray:
    """A pose from the command line: ``x,y,z,roll,pitch,yaw`` (m and degrees, extrinsic x-y-z:
    R = Rz(yaw) Ry(pitch) Rx(roll)), or 16 numbers (a 4x4 matrix, row by row). Raises
    ValueError."""
    values = [float(v) for v in text.replace(",", " ").split()]
    if len(values) == 16:
        X = np.array(values).reshape(4, 4)
    elif len(values) == 6:
        r, p, y = np.radians(values[3:])
        cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
        X = np.eye(4)
        X[:3, :3] = np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                              [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                              [-sp, cp * sr, cp * cr]])
        X[:3, 3] = values[:3]
    else:
        raise ValueError(f"a pose is x,y,z,roll,pitch,yaw (m, deg) or 16 numbers, got "
                         f"{len(values)} numbers")
    return check_pose(X)


def check_pose(X) -> np.ndarray:
    """``X`` as a float (4, 4) array when it is a pose (finite, a rotation and a translation,
    last row 0 0 0 1), else ValueError."""
    X = np.asarray(X, dtype=float)
    if X.shape != (4, 4):
        raise ValueError(f"a pose is a 4x4 matrix, got shape {X.shape}")
    if not np.isfinite(X).all():
        raise ValueError("a pose's numbers must be finite")
    R = X[:3, :3]
    if float(np.abs(R.T @ R - np.eye(3)).max()) > 1e-5 or np.linalg.det(R) < 0 \
            or not np.allclose(X[3], [0, 0, 0, 1]):
        raise ValueError("not a pose: its 3x3 part is not a rotation (or its last row is not "
                         "0 0 0 1)")
    return X
