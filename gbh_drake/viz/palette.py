"""The colours of what gbh_drake draws in Meshcat, one home for each, and the legend that names
them (replays' legend, the studio's page, docs/studio.md).

The simulated object keeps its own colour (the built-in objects' own, a mesh file's
:data:`~gbh_drake.modeling.object_asset.MESH_RGBA`); everything drawn over it has a colour of
its own, far from the others in hue: the scan (translucent blue), the hanging structures (the
paper's Figs. 4-5: red c, black axis v, red hit and green missed rays, blue contacts H), the
ranked grasps (yellow lines), the chosen grasp (cyan, with its solid model; darker closed),
the refused grasps (purple), the cameras (brown frusta), the space they did not see (magenta)
and the space they saw free (white).
"""

from __future__ import annotations

from dataclasses import dataclass

#: (r, g, b, a) in [0, 1].
RGBA = tuple[float, float, float, float]

SCAN: RGBA = (0.25, 0.45, 0.95, 0.45)
STRUCTURE: RGBA = (0.9, 0.1, 0.1, 1.0)
"""A hanging position c (and the rays that hit)."""
AXIS: RGBA = (0.0, 0.0, 0.0, 1.0)
"""A hanging direction v."""
MISSED: RGBA = (0.1, 0.7, 0.2, 1.0)
CONTACTS: RGBA = (0.1, 0.3, 0.9, 1.0)
RANKED: RGBA = (0.95, 0.8, 0.05, 1.0)
CHOSEN: RGBA = (0.0, 0.8, 0.85, 1.0)
CHOSEN_SOLID: RGBA = (0.0, 0.8, 0.85, 0.35)
CLOSED: RGBA = (0.0, 0.4, 0.5, 1.0)
"""The chosen grasp's gripper closed (darker cyan)."""
REFUSED: RGBA = (0.55, 0.2, 0.8, 1.0)
REFUSED_POSITION: RGBA = (0.35, 0.35, 0.35, 1.0)
"""A hanging position the detector refused (too small, not a through-hole, exit proof)."""
CAMERA: RGBA = (0.55, 0.35, 0.1, 1.0)
FIRST_LOOK: RGBA = (0.8, 0.65, 0.45, 1.0)
UNSEEN: RGBA = (0.9, 0.15, 0.7, 0.8)
FREE: RGBA = (1.0, 1.0, 1.0, 0.6)


@dataclass(frozen=True)
class Key:
    """One entry of the legend: what it is and its colour."""

    label: str
    rgba: RGBA


#: The legend: everything drawn over the simulated object, in the order it appears.
LEGEND = (
    Key("scan (fused views)", SCAN),
    Key("hanging position c, hit rays", STRUCTURE),
    Key("hanging direction v", AXIS),
    Key("missed rays", MISSED),
    Key("ranked grasps", RANKED),
    Key("chosen grasp (open)", CHOSEN),
    Key("chosen grasp (closed)", CLOSED),
    Key("refused grasps", REFUSED),
    Key("refused hanging positions", REFUSED_POSITION),
    Key("cameras", CAMERA),
    Key("what the cameras did not see", UNSEEN),
    Key("what the cameras saw free", FREE),
)


def css(rgba: RGBA) -> str:
    """``rgba`` as a CSS colour (opaque: a legend's swatch)."""
    r, g, b, _ = rgba
    return f"rgb({round(255 * r)}, {round(255 * g)}, {round(255 * b)})"
