"""Small helpers that write SDFormat snippets (poses, boxes, inertia, hydroelastic properties)."""

from __future__ import annotations

import numpy as np


def fmt(values) -> str:
    """Space-separated numbers with enough digits for metres and kilograms."""
    return " ".join(f"{float(v):.9g}" for v in np.ravel(values))


def pose(xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0), relative_to: str | None = None) -> str:
    attr = f' relative_to="{relative_to}"' if relative_to else ""
    return f"<pose{attr}>{fmt(xyz)} {fmt(rpy)}</pose>"


def inertial(mass: float, com, inertia_3x3) -> str:
    """``<inertial>`` for a body of ``mass`` kg, centre of mass ``com`` (m), inertia about the com."""
    inertia = np.asarray(inertia_3x3, dtype=float)
    return (
        f"<inertial>{pose(com)}<mass>{float(mass):.9g}</mass><inertia>"
        f"<ixx>{inertia[0, 0]:.9g}</ixx><ixy>{inertia[0, 1]:.9g}</ixy>"
        f"<ixz>{inertia[0, 2]:.9g}</ixz><iyy>{inertia[1, 1]:.9g}</iyy>"
        f"<iyz>{inertia[1, 2]:.9g}</iyz><izz>{inertia[2, 2]:.9g}</izz></inertia></inertial>"
    )


def box_inertia(mass: float, size) -> np.ndarray:
    """Inertia (3, 3) about the centre of a solid box of ``size`` (3,) metres."""
    x, y, z = np.asarray(size, dtype=float) ** 2
    return mass / 12.0 * np.diag([y + z, x + z, x + y])


def hydroelastic(
    kind: str,
    *,
    modulus: float | None = None,
    mu: float = 0.8,
    dissipation: float = 3.0,
) -> str:
    """``<drake:proximity_properties>`` for a ``kind`` = 'rigid' or 'compliant' hydroelastic geometry.

    ``modulus`` (Pa) only for compliant geometry; ``mu`` is both static and dynamic friction;
    ``dissipation`` the Hunt-Crossley dissipation (s/m)."""
    if kind not in ("rigid", "compliant"):
        raise ValueError(f"hydroelastic kind must be 'rigid' or 'compliant', not {kind!r}")
    lines = [f"<drake:{kind}_hydroelastic/>"]
    if kind == "compliant":
        lines.append(f"<drake:hydroelastic_modulus>{float(modulus):.6g}</drake:hydroelastic_modulus>")
    lines += [
        f"<drake:hunt_crossley_dissipation>{dissipation:g}</drake:hunt_crossley_dissipation>",
        f"<drake:mu_dynamic>{mu:g}</drake:mu_dynamic>",
        f"<drake:mu_static>{mu:g}</drake:mu_static>",
    ]
    return "<drake:proximity_properties>" + "".join(lines) + "</drake:proximity_properties>"


def material(rgba) -> str:
    return f"<material><diffuse>{fmt(rgba)}</diffuse></material>"


def box_geometry(size) -> str:
    return f"<geometry><box><size>{fmt(size)}</size></box></geometry>"


def mesh_geometry(uri: str, scale: float = 1.0) -> str:
    return f"<geometry><mesh><uri>{uri}</uri><scale>{fmt([scale] * 3)}</scale></mesh></geometry>"
