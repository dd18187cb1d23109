"""Small vectorised vector helpers shared by the GbH core (unit vectors, sphere grids, bases)."""

from __future__ import annotations

import numpy as np

GOLDEN_ANGLE = np.pi * (3.0 - np.sqrt(5.0))
"""rad: the golden angle, for evenly spread spiral samples (Fibonacci sphere)."""


def unit(v: np.ndarray, eps: float = 1e-12) -> np.ndarray:
    """Normalise vectors along the last axis; zero vectors stay zero."""
    v = np.asarray(v, dtype=float)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.where(n > eps, v / np.maximum(n, eps), 0.0)


def fibonacci_sphere(n: int, hemisphere: bool = False) -> np.ndarray:
    """(n, 3) near-uniform unit vectors; with ``hemisphere`` only z >= 0 (one per line)."""
    i = np.arange(n) + 0.5
    z = 1.0 - i / n if hemisphere else 1.0 - 2.0 * i / n
    r = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
    phi = GOLDEN_ANGLE * i
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def fibonacci_cap(axis: np.ndarray, half_angle: float, n: int) -> np.ndarray:
    """(n, 3) near-uniform unit vectors within ``half_angle`` (rad) of ``axis``; row 0 is axis."""
    i = np.arange(n, dtype=float)
    z = 1.0 - (1.0 - np.cos(half_angle)) * i / max(n - 1, 1)
    r = np.sqrt(np.clip(1.0 - z * z, 0.0, None))
    phi = GOLDEN_ANGLE * i
    local = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    e1, e2 = orthonormal_basis(axis[None])
    R = np.stack([e1[0], e2[0], unit(axis)], axis=1)
    return local @ R.T


def orthonormal_basis(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (n, 3) each, orthogonal to the unit vectors ``u`` (n, 3) and each other."""
    u = unit(u)
    helper = np.where(np.abs(u[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = unit(np.cross(u, helper))
    return e1, np.cross(u, e1)


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angles (rad, in [0, pi]) between unit vectors ``a`` and ``b`` along the last axis."""
    return np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0))


def rotation_angle(R_a: np.ndarray, R_b: np.ndarray) -> float:
    """The angle (deg, in [0, 180]) of the rotation from ``R_a`` to ``R_b`` (3, 3): that of
    R_a^T R_b."""
    R = np.asarray(R_a, dtype=float).T @ np.asarray(R_b, dtype=float)
    return float(np.degrees(np.arccos(np.clip(0.5 * (np.trace(R) - 1.0), -1.0, 1.0))))


def poses_from_axes(y_W: np.ndarray, z_W: np.ndarray, p_WO: np.ndarray) -> np.ndarray:
    """(n, 4, 4) poses X_WG with +y_G, +z_G along ``y_W``, ``z_W`` (n, 3) and origin ``p_WO``.

    ``y_W`` is made orthogonal to ``z_W`` first (Gram-Schmidt); x_G = y_G x z_G.
    """
    z = unit(z_W)
    y = unit(y_W - np.sum(y_W * z, axis=1, keepdims=True) * z)
    X = np.zeros((len(z), 4, 4))
    X[:, :3, 0] = np.cross(y, z)
    X[:, :3, 1] = y
    X[:, :3, 2] = z
    X[:, :3, 3] = p_WO
    X[:, 3, 3] = 1.0
    return X


def frame_coordinates(
    X_WF: np.ndarray, p_WQ: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coordinates x, y, z, each (M, N), of the points ``p_WQ`` (N, 3) in each frame F of
    ``X_WF`` (M, 4, 4): p_FQ = R^T (p_WQ - p_WF), in the dtype of the inputs.

    Written as broadcast multiply-adds rather than a (M, 3) @ (3, N) product: with an inner
    dimension of 3, BLAS threads only add synchronisation, which made the product 2-50 ms
    depending on the machine's load; this is a steady few ms for 144 x 5000."""
    R, t = X_WF[:, :3, :3], X_WF[:, :3, 3]
    p = p_WQ.T  # (3, N)
    out = []
    for i in range(3):
        r = R[:, :, i]  # axis i of every frame, in W
        c = r[:, 0:1] * p[0] + r[:, 1:2] * p[1]
        c += r[:, 2:3] * p[2]
        c -= np.sum(t * r, axis=1)[:, None]
        out.append(c)
    return out[0], out[1], out[2]
