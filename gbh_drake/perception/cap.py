"""Cutting the fused mesh at the table and closing its bottom, except over real holes.

The cameras never see an object's bottom (it rests on the table), nor the underside of a rounded
or bevelled foot, so once the table is cut away the mesh is open there, and rays entering through
that opening can cross the object's interior (a tote bag, a pot, a kettle whose floor is not
seen): false through-holes for GbH. The bottom is closed, but not where the depth images saw the
table through the object (a key ring or a tape roll lying flat: the cameras see the table through
the hole, and GbH needs that hole).

The rule, on a raster of the table plane (cells of half a voxel):
1. the mesh is cut exactly at ``crop_z_min`` above the table (its triangles clipped); its bottom
   boundary is its open boundary edges on that cut or at most ``cap_height`` above it;
2. the bottom boundary, projected onto the table, is rasterised and closed (gaps narrower than
   2 ``cap_gap`` bridged); the regions of the plane it encloses (not connected to the raster's
   border) are the candidates;
3. a region stays open when at least ``hole_evidence_fraction`` of its core (the cells farther
   than ``cap_gap`` from its outline: the fused surface bulges where the object meets the table,
   and the table seen right beside the object's foot is no hole) holds depth points at table
   height, whose median height is within ``table_tolerance`` of the plane; a floor seen a few
   millimetres up (a bag's) is not the table;
4. the outline's cells and the other enclosed regions, in the pieces that close something (a
   region, or the cut), are capped: traced (contourpy), triangulated (manifold3d) and added at
   the cut's height, facing down; bottom boundary edges above the cut and over the cap get a
   skirt straight down to it, so the bottom is closed all round.
"""

from __future__ import annotations

from dataclasses import dataclass

import contourpy
import manifold3d
import numpy as np

from gbh_drake.core.lazy import lazy_module
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.table import TablePlane

ndimage = lazy_module("scipy.ndimage")
trimesh = lazy_module("trimesh")


@dataclass
class CapReport:
    """What capping the bottom did."""

    capped_regions: int = 0
    """Enclosed regions of the cut closed (nothing seen through them)."""
    open_holes: int = 0
    """Enclosed regions left open: the cameras saw the table through them."""
    area: float = 0.0
    """Area of the cap (m^2)."""
    faces: int = 0
    """Triangles added."""


def cut_at_height(mesh: trimesh.Trimesh, table: TablePlane, height: float) -> trimesh.Trimesh:
    """The part of ``mesh`` higher than ``height`` (m) above the table plane, cut exactly: the
    triangles across the plane are clipped, the new vertices are shared between neighbours (so
    the cut's boundary is closed where the mesh was), the winding is kept."""
    if len(mesh.faces) == 0:
        return mesh
    vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    h = table.heights(vertices) - height
    above = h > 0
    count = above[faces].sum(axis=1)
    kept = [faces[count == 3]]
    crossing = faces[(count == 1) | (count == 2)]
    if len(crossing) == 0:
        return _compact(vertices, kept[0])
    # Rotate each crossing triangle (keeping its winding) so that its odd vertex comes first:
    # the one above when one is, the one below when two are.
    odd = above[crossing] == (count[(count == 1) | (count == 2)] == 1)[:, None]
    shift = np.argmax(odd, axis=1)
    rows = np.arange(len(crossing))[:, None]
    a, b, c = crossing[rows, (shift[:, None] + np.arange(3)) % 3].T
    # One new vertex per cut edge, computed from its lower-indexed end so neighbours agree.
    edges = np.sort(np.concatenate([np.column_stack([a, b]), np.column_stack([a, c])]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    i, j = unique.T
    t = h[i] / (h[i] - h[j])
    new = vertices[i] + t[:, None] * (vertices[j] - vertices[i])
    ab, ac = np.split(inverse.reshape(-1) + len(vertices), 2)
    one_up = above[a]
    kept.append(np.column_stack([a, ab, ac])[one_up])  # a above: triangle a, ab, ac
    # a below, b and c above: quad b, c, ac, ab.
    kept.append(np.column_stack([b, c, ac])[~one_up])
    kept.append(np.column_stack([b, ac, ab])[~one_up])
    return _compact(np.vstack([vertices, new]), np.vstack(kept))


def _compact(vertices: np.ndarray, faces: np.ndarray) -> trimesh.Trimesh:
    """The mesh of ``faces`` with only the vertices they use."""
    if len(faces) == 0:
        return trimesh.Trimesh()
    used, remap = np.unique(faces, return_inverse=True)
    return trimesh.Trimesh(vertices[used], remap.reshape(-1, 3), process=False)


def bottom_boundary(mesh: trimesh.Trimesh, table: TablePlane, height: float,
                    cap_height: float) -> tuple[np.ndarray, np.ndarray]:
    """The mesh's open boundary near the table: its boundary edges (each in only one triangle)
    whose ends are at most ``cap_height`` (m) above the cut ``height`` (m). Returns (edges
    (m, 2) vertex indices, directed as in their triangle; on_plane (m,) bool: the edge lies on
    the cut, where :func:`cut_at_height` cut the mesh)."""
    if len(mesh.faces) == 0:
        return np.zeros((0, 2), dtype=np.int64), np.zeros(0, dtype=bool)
    boundary = mesh.edges[trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)]
    h = table.heights(mesh.vertices)[boundary] - height  # (m, 2)
    low = np.all(h <= cap_height, axis=1)
    return boundary[low], np.all(np.abs(h[low]) < 1e-6, axis=1)


def cap_bottom(mesh: trimesh.Trimesh, table: TablePlane, config: ScanConfig,
               p_W_low: np.ndarray) -> tuple[trimesh.Trimesh, CapReport]:
    """``mesh`` (already cut at ``config.crop_z_min`` by :func:`cut_at_height`) closed at the
    bottom: capped at the cut, with a skirt down to the cap from boundaries a little higher
    (under an object's foot the cameras never saw), except over regions through which the depth
    points at table height ``p_W_low`` (n, 3), W, saw the table (see the module's rule).
    Returns (mesh, report)."""
    report = CapReport()
    height = config.crop_z_min
    edges, on_plane = bottom_boundary(mesh, table, height, config.cap_height)
    if len(edges) == 0:
        return mesh, report
    basis = table.basis()
    cell = 0.5 * config.voxel_size
    ends = mesh.vertices[edges] @ basis[:, :2]  # (m, 2, 2) in the plane
    gap = int(np.ceil(config.cap_gap / cell))
    pad = gap + 3
    lower = ends.reshape(-1, 2).min(axis=0) - pad * cell
    shape = tuple(np.ceil((ends.reshape(-1, 2).max(axis=0) - lower) / cell).astype(int) + pad)

    # 1-2. The outline on the raster, closed; the regions it encloses.
    wall = np.zeros(shape, dtype=bool)
    cells = _segment_cells(ends, lower, cell, shape)  # (m, k, 2)
    wall[cells[..., 0], cells[..., 1]] = True
    if gap > 0:
        wall = ndimage.binary_closing(wall, structure=_disk(gap))
    regions, n = ndimage.label(~wall)
    border = np.unique(np.concatenate([regions[0], regions[-1], regions[:, 0], regions[:, -1]]))
    enclosed = np.setdiff1d(np.arange(1, n + 1), border)

    # 3. Evidence: depth points at table height inside a region's core.
    open_regions = _seen_through(regions, enclosed, ~wall, p_W_low, table, basis, lower, cell,
                                 config)
    closed_regions = np.setdiff1d(enclosed, open_regions)

    # 4. The cap: the outline's cells and the enclosed regions not seen through, in the pieces
    # that close something (a region, or the cut itself): not the shadow of a boundary that
    # closes nothing, e.g. the unseen underside of a handle near the table.
    capped = wall | np.isin(regions, closed_regions)
    pieces, _ = ndimage.label(capped, structure=np.ones((3, 3), dtype=bool))
    closing = np.isin(regions, closed_regions)
    closing[cells[on_plane][..., 0], cells[on_plane][..., 1]] = True
    capped &= np.isin(pieces, np.unique(pieces[closing & capped]))
    report.open_holes = len(open_regions)
    report.capped_regions = len(closed_regions)
    cap = _triangulate(capped, lower, cell)
    if cap is None:
        return mesh, report
    points_2d, faces = cap
    vertices = points_2d @ basis[:, :2].T + (table.height + height) * table.normal_W
    cap_mesh = trimesh.Trimesh(vertices, faces[:, ::-1], process=False)  # facing down
    report.area = float(cap_mesh.area)
    report.faces = len(faces)
    parts = [mesh, cap_mesh]

    # The skirt: boundary edges above the cut, over the cap, continued straight down to it.
    ij = _cells(ends.reshape(-1, 2), lower, cell, shape).reshape(-1, 2, 2)
    over_cap = capped[ij[:, 0, 0], ij[:, 0, 1]] & capped[ij[:, 1, 0], ij[:, 1, 1]]
    skirt = edges[over_cap & ~on_plane]
    if len(skirt):
        top = mesh.vertices[skirt.reshape(-1)]
        foot = top - (table.heights(top) - height)[:, None] * table.normal_W
        vertices = np.vstack([top, foot])
        a, b = np.arange(0, 2 * len(skirt), 2), np.arange(1, 2 * len(skirt), 2)
        a_, b_ = a + len(top), b + len(top)
        # The boundary edge a -> b belongs to the triangle above; its continuation runs b -> a.
        faces = np.vstack([np.column_stack([b, a, a_]), np.column_stack([b, a_, b_])])
        parts.append(trimesh.Trimesh(vertices, faces, process=False))
        report.faces += len(faces)
    return trimesh.util.concatenate(parts), report


def _segment_cells(ends: np.ndarray, lower: np.ndarray, cell: float, shape) -> np.ndarray:
    """Raster cells (m, k, 2) crossed by the 2-D segments ``ends`` (m, 2, 2), sampled at k points
    each (spaced below half a cell)."""
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1).max()
    t = np.linspace(0.0, 1.0, int(np.ceil(length / (0.4 * cell))) + 2)[None, :, None]
    samples = ends[:, None, 0] + t * (ends[:, None, 1] - ends[:, None, 0])  # (m, k, 2)
    return _cells(samples.reshape(-1, 2), lower, cell, shape).reshape(samples.shape)


def _cells(points_2d: np.ndarray, lower: np.ndarray, cell: float, shape) -> np.ndarray:
    """Raster cell (n, 2) of each 2-D point, clipped to the raster."""
    ij = np.floor((points_2d - lower) / cell).astype(int)
    return np.clip(ij, 0, np.asarray(shape) - 1)


def _disk(radius: int) -> np.ndarray:
    i, j = np.mgrid[-radius:radius + 1, -radius:radius + 1]
    return i * i + j * j <= radius * radius


def _seen_through(regions: np.ndarray, enclosed: np.ndarray, free: np.ndarray,
                  p_W_low: np.ndarray, table: TablePlane, basis: np.ndarray,
                  lower: np.ndarray, cell: float, config: ScanConfig) -> np.ndarray:
    """The enclosed region labels through which the table was seen."""
    if len(enclosed) == 0 or len(p_W_low) == 0:
        return np.zeros(0, dtype=int)
    # Only the region's core counts: the fused surface can bulge a few millimetres where the
    # object meets the table, and the table seen just beside the object's foot is no hole.
    margin = max(config.cap_gap, 2.0 * cell) / cell
    inner = np.where(ndimage.distance_transform_edt(free) > margin, regions, 0)
    xy = p_W_low @ basis[:, :2]
    inside = np.all((xy >= lower) & (xy < lower + cell * np.asarray(regions.shape)), axis=1)
    ij = _cells(xy[inside], lower, cell, regions.shape)
    label = inner[ij[:, 0], ij[:, 1]]
    keep = np.isin(label, enclosed)
    label, ij, h = label[keep], ij[keep], table.heights(p_W_low[inside][keep])
    seen = []
    for region in enclosed:
        mine = label == region
        size = np.count_nonzero(inner == region)
        if size == 0 or not mine.any():
            continue
        cells = np.unique(ij[mine, 0] * regions.shape[1] + ij[mine, 1])
        if (len(cells) >= config.hole_evidence_fraction * size
                and np.median(h[mine]) < config.table_tolerance):
            seen.append(region)
    return np.asarray(seen, dtype=int)


def _triangulate(mask: np.ndarray, lower: np.ndarray, cell: float
                 ) -> tuple[np.ndarray, np.ndarray] | None:
    """Triangles covering the raster ``mask`` (cells [i, j], i along the first axis): its
    outline traced by contourpy at the cells' half-way level, triangulated by manifold3d.
    Returns (points (p, 2) in the plane, faces (f, 3) counter-clockwise) or None if empty."""
    if not mask.any():
        return None
    x = lower[0] + cell * (np.arange(mask.shape[0]) + 0.5)
    y = lower[1] + cell * (np.arange(mask.shape[1]) + 0.5)
    generator = contourpy.contour_generator(x, y, mask.T.astype(np.float64),
                                            fill_type=contourpy.FillType.OuterOffset)
    polygons, offsets = generator.filled(0.5, 1.5)
    points, faces, count = [], [], 0
    for polygon, offset in zip(polygons, offsets, strict=True):
        rings = [polygon[a:b - 1] for a, b in zip(offset[:-1], offset[1:], strict=True)]
        triangles = np.asarray(manifold3d.triangulate(rings), dtype=np.int64).reshape(-1, 3)
        points.extend(rings)
        faces.append(triangles + count)
        count += sum(len(r) for r in rings)
    if count == 0:
        return None
    return np.vstack(points), np.vstack(faces)
