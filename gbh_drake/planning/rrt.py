"""RRT-Connect (Kuffner and LaValle, 2000) in the arm's joint space, collision-checked by Drake.

Written here rather than taken from OMPL because OMPL's Python bindings draw from one
process-wide random generator that can be seeded only once: two plans in one process would not
repeat, and a scenario's seed must give the same trial every time. This one draws from a numpy
generator seeded per call, so the same inputs and seed give the same path.

Edges are checked with Drake's ``CheckEdgeCollisionFree`` (configurations every
``edge_step_size`` along the edge); the path is then shortened by random shortcuts.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.planning.model import HandPose, PlanningModel


def plan_rrt_connect(model: PlanningModel, q_start, q_goal, hand: HandPose, *,
                     seed: int = 0, max_iterations: int = 3000, step: float = 0.2,
                     shortcuts: int = 60) -> list[np.ndarray] | None:
    """Collision-free waypoints (rad, 7 each) from ``q_start`` to ``q_goal`` with the hand at
    ``hand``, or None if either end collides or no path was found in ``max_iterations``.

    ``step`` (rad): the longest edge the trees grow at once (max-norm over the joints)."""
    q_start, q_goal = np.asarray(q_start, dtype=float), np.asarray(q_goal, dtype=float)
    if not (model.free(q_start, hand) and model.free(q_goal, hand)):
        return None
    if model.edge_free(q_start, q_goal, hand):
        return [q_start, q_goal]
    rng = np.random.default_rng(seed)
    lo, hi = model.arm_lower, model.arm_upper
    trees = ([q_start], [-1]), ([q_goal], [-1])  # (nodes, parent index) of each tree

    def extend(tree, q_target):
        """Grows ``tree`` one step toward ``q_target``; the new node's index, or None."""
        nodes, parents = tree
        i = int(np.argmin(np.abs(np.asarray(nodes) - q_target).max(axis=1)))
        delta = q_target - nodes[i]
        length = np.abs(delta).max()
        q_new = q_target if length <= step else nodes[i] + delta * (step / length)
        if not model.edge_free(nodes[i], q_new, hand):
            return None
        nodes.append(q_new)
        parents.append(i)
        return len(nodes) - 1

    def connect(tree, q_target):
        """Extends ``tree`` toward ``q_target`` until it reaches it (index) or is blocked."""
        while True:
            k = extend(tree, q_target)
            if k is None:
                return None
            if np.array_equal(tree[0][k], q_target):
                return k

    for iteration in range(max_iterations):
        grow, other = (trees[0], trees[1]) if iteration % 2 == 0 else (trees[1], trees[0])
        k = extend(grow, rng.uniform(lo, hi))
        if k is None:
            continue
        j = connect(other, grow[0][k])
        if j is None:
            continue
        a, b = _branch(grow, k), _branch(other, j)
        path = a[::-1] + b[1:]
        if grow is trees[1]:
            path = path[::-1]
        return _shortcut(model, path, hand, rng, shortcuts)
    return None


def _branch(tree, k: int) -> list[np.ndarray]:
    """The nodes from node ``k`` back to the tree's root."""
    nodes, parents = tree
    out = []
    while k != -1:
        out.append(nodes[k])
        k = parents[k]
    return out


def _shortcut(model: PlanningModel, path: list[np.ndarray], hand: HandPose, rng,
              attempts: int) -> list[np.ndarray]:
    """Replaces stretches of ``path`` by straight, collision-free edges (random attempts)."""
    path = list(path)
    for _ in range(attempts):
        if len(path) <= 2:
            break
        i, j = sorted(rng.choice(len(path), size=2, replace=False))
        if j - i >= 2 and model.edge_free(path[i], path[j], hand):
            path = path[: i + 1] + path[j:]
    return path
