r"""Structured (revolved) tetrahedral mesh of the grooved foot: layers through the skirt, exact tags.

Why a second foot mesher. pytetwild (`geometry.tetwild.mesh_foot`) meshes the foot isotropically:
its default 4.5 mm edge puts about one quadratic element through the 3 mm skirt, and a finer edge
multiplies the tetrahedra of the whole foot. In the 55 mm pipe the skirt is folded into the 3.5 mm
between the hub rim and the wall, and in the 75 mm pipe's backward drag it is wedged; with one
element through its thickness the crushed fold has no Newton basin (docs/decisions/041-revolved-foot.md).
The foot is a solid of revolution, so a revolved mesh resolves the thickness with a few layers,
keeps the elements long along the skirt and around the axis, and is the same in every sector
(the mesh itself does not break the axial symmetry, unlike the irregular pytetwild mesh).

Section. In the (rho, z) half plane of `geometry.foot` (alpha = angle / 2, u the skirt direction,
n the front-face normal, t the skirt thickness, h the groove depth) a skirt point is
    S(s, d) = F0 + s u - d n,     0 <= d <= t  (d = 0 the smooth front face, d = t the back face),
and the back face point at back-face coordinate b is S(b + t / tan(alpha), t). The section is cut
into bilinear quadrilateral blocks, each split into `n_xi` x `n_eta` cells:
  root     F0, S(s1, 0), S(s1, t), B0 with s1 = b1 + t / tan(alpha), b1 the first groove wall:
           it joins the hub side (rho = r_hub) to the first cross-section perpendicular to u;
  bands    one block per interval between consecutive groove walls on the back face, cross
           sections perpendicular to u; a land spans 0 <= d <= t, a groove 0 <= d <= t - h;
  hub      rho in [r_bore, r_hub], z in [-t_hub, 0], its z levels those of the skirt root
           (so the blocks conform) plus the hub side below the skirt; radial cells of
           `HUB_CELL_FACTOR` x `cell_size` (the hub top is held by the actuators).
The depth levels are the same in every skirt block: exactly `thickness_layers` cells through a
land, split at d = t - h so that a groove removes whole cells (`thickness_cells`: the depth h
takes round(layers h / t) of them, at least one; before issue 29 the count was only about
t / layers per cell, and 4 asked layers gave 5 cells). Each quadrilateral is cut along its
shorter diagonal; duplicate nodes of neighbouring blocks are merged.

Revolution. The section's triangles are swept through `n_theta` equal sectors; each prism
(a, b, c | a', b', c') with a < b < c in section numbering is cut into [a, b, c, a'],
[b, c, a', b'], [c, a', b', c'] (the rule of `geometry.swept`: a quadrilateral face gets the
diagonal from its larger bottom node to its smaller top node whichever prism owns it, so the
mesh conforms, also across the last sector that closes onto the first).

Tags are found by `geometry.tetwild.tag_boundary` against `geometry.foot.foot_segments` with a
tolerance of 1e-9 of the tip radius: every vertex lies on the exact surfaces, so nothing is snapped,
and `meta['curved_surfaces']` lets `TaggedMesh.to_skfem(order=2)` put the midside nodes of the
cones and cylinders on the exact surfaces as for the pytetwild meshes.
"""

from __future__ import annotations

import math

import numpy as np

from softcrawl.geometry.design import DesignError, FootDesign
from softcrawl.geometry.foot import foot_segments, skirt_directions
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import boundary_facets, curved_surface_meta, orient_positive
from softcrawl.geometry.tetwild import tag_boundary

#: Defaults of the revolved foot mesh: 48 sectors (5.1 mm arcs at the 39 mm tip), three cells
#: through the 3 mm skirt, 2 mm cells along the skirt.
N_THETA = 48
THICKNESS_LAYERS = 3
CELL_SIZE = 2.0
#: The hub is held at its top face by the actuators and barely strains: its radial cells are this
#: many times `cell_size`.
HUB_CELL_FACTOR = 2.0


def _divisions(length: float, size: float) -> int:
    return max(1, int(math.ceil(length / size - 1e-9)))


def _block(corners: np.ndarray, xi: np.ndarray, eta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (len(xi) * len(eta), 2) of the bilinear map of corners (p00, p10, p11, p01), and its
    quadrilaterals (counter-clockwise in (xi, eta)) as local node numbers."""
    p00, p10, p11, p01 = corners
    X, E = np.meshgrid(xi, eta, indexing="ij")
    X, E = X[..., None], E[..., None]
    pts = (1 - X) * (1 - E) * p00 + X * (1 - E) * p10 + X * E * p11 + (1 - X) * E * p01
    nx, ne = len(xi), len(eta)
    idx = np.arange(nx * ne).reshape(nx, ne)
    quads = np.column_stack(
        [idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()]
    )
    return pts.reshape(-1, 2), quads


def thickness_cells(design: FootDesign, thickness_layers: int) -> tuple[int, int]:
    """(cells from the front face to the groove bottoms, cells across the groove depth h), which
    sum to `thickness_layers` exactly: the depth h takes round(layers * h / t) cells, at least one
    (none without grooves)."""
    if not design.n_grooves or design.groove_height <= 0:
        return thickness_layers, 0
    if thickness_layers < 2:
        raise DesignError("thickness_layers", "a grooved skirt needs at least 2 cells: one under the grooves")
    n_back = min(
        max(1, round(thickness_layers * design.groove_height / design.skirt_thickness)), thickness_layers - 1
    )
    return thickness_layers - n_back, n_back


def foot_section(
    design: FootDesign, thickness_layers: int = THICKNESS_LAYERS, cell_size: float = CELL_SIZE
) -> tuple[np.ndarray, np.ndarray]:
    """Triangulated (rho, z) section of the foot: nodes (n, 2) and triangles (m, 3), counter-clockwise."""
    a = math.radians(design.angle / 2)
    u, n = skirt_directions(design)
    t, h, w = design.skirt_thickness, design.groove_height, design.groove_width
    r_hub, t_hub, r_b = design.hub_radius, design.hub_thickness, design.bore_radius
    F0 = np.array([r_hub, 0.0])
    shift = t / math.tan(a)  # front-face coordinate of the back face's start

    def S(s: float, d: float) -> np.ndarray:
        return F0 + s * u - d * n

    n_front, n_back = thickness_cells(design, thickness_layers)
    back_depth = h if design.n_grooves else 0.0
    d_front = np.linspace(0.0, t - back_depth, n_front + 1)
    d_back = np.linspace(t - back_depth, t, n_back + 1)[1:] if back_depth else []
    d_all = np.concatenate([d_front, d_back])
    eta_all, eta_groove = d_all / t, d_front / t

    Lb = design.back_face_length
    pitch = Lb / (design.n_grooves + 1)
    walls = [0.0]
    for i in range(design.n_grooves):
        sc = (i + 1) * pitch
        walls += [sc - w / 2, sc + w / 2]
    walls.append(Lb)
    grooves = {2 * i + 1 for i in range(design.n_grooves)}  # index of a groove interval

    parts: list[tuple[np.ndarray, np.ndarray]] = []
    s1 = walls[1] + shift
    root = np.array([F0, S(s1, 0.0), S(s1, t), S(shift, t)])
    n_root = _divisions(0.5 * (s1 + walls[1]), cell_size)
    parts.append(_block(root, np.linspace(0, 1, n_root + 1), eta_all))
    for k in range(1, len(walls) - 1):
        b0, b1 = walls[k] + shift, walls[k + 1] + shift
        depth = t - h if k in grooves else t
        eta = eta_groove if k in grooves else eta_all
        corners = np.array([S(b0, 0.0), S(b1, 0.0), S(b1, depth), S(b0, depth)])
        parts.append(_block(corners, np.linspace(0, 1, _divisions(b1 - b0, cell_size) + 1), eta * t / depth))
    z_root = -eta_all * (t / math.sin(a))  # the skirt root's depth levels on the hub side
    z_levels = np.unique(np.concatenate([z_root, [-t_hub]]))[::-1]  # 0 down to -t_hub
    hub = np.array([[r_hub, 0.0], [r_b, 0.0], [r_b, -t_hub], [r_hub, -t_hub]])
    eta_hub = -z_levels / t_hub
    n_hub = _divisions(r_hub - r_b, HUB_CELL_FACTOR * cell_size)
    parts.append(_block(hub, np.linspace(0, 1, n_hub + 1), eta_hub))

    nodes, quads, offset = [], [], 0
    for pts, q in parts:
        nodes.append(pts)
        quads.append(q + offset)
        offset += len(pts)
    nodes_all = np.vstack(nodes)
    key = np.round(nodes_all / (1e-9 * design.tip_radius)).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    quads_all = inverse.reshape(-1)[np.vstack(quads)]
    xy = nodes_all[first]
    # counter-clockwise quadrilaterals, cut along the shorter diagonal
    p = xy[quads_all]
    area = 0.5 * np.sum(p[:, :, 0] * np.roll(p[:, :, 1], -1, 1) - np.roll(p[:, :, 0], -1, 1) * p[:, :, 1], 1)
    quads_all[area < 0] = quads_all[area < 0][:, ::-1]
    p = xy[quads_all]
    short02 = np.linalg.norm(p[:, 2] - p[:, 0], axis=1) <= np.linalg.norm(p[:, 3] - p[:, 1], axis=1)
    q = quads_all
    tris = np.vstack(
        [
            np.where(short02[:, None], q[:, [0, 1, 2]], q[:, [0, 1, 3]]),
            np.where(short02[:, None], q[:, [0, 2, 3]], q[:, [1, 2, 3]]),
        ]
    )
    return xy, tris


def revolve_section(
    xy: np.ndarray, tris: np.ndarray, n_theta: int, kept: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Points and positively oriented tets of the section swept about the z axis through `kept`
    of `n_theta` equal sectors (None: all, closed onto the first; fewer: an open wedge from
    theta = 0 to 2 pi kept / n_theta, with kept + 1 section planes)."""
    n2 = len(xy)
    kept = n_theta if kept is None else kept
    planes = n_theta if kept == n_theta else kept + 1
    theta = 2 * np.pi * np.arange(planes) / n_theta
    rho, z = np.tile(xy[:, 0], planes), np.tile(xy[:, 1], planes)
    th = np.repeat(theta, n2)
    points = np.column_stack([rho * np.cos(th), rho * np.sin(th), z])
    tris = np.sort(tris, axis=1)
    tets = []
    for k in range(kept):
        lo, hi = k * n2, ((k + 1) % planes) * n2
        a, b, c = (tris[:, i] + lo for i in range(3))
        a1, b1, c1 = (tris[:, i] + hi for i in range(3))
        tets += [np.column_stack(t) for t in ((a, b, c, a1), (b, c, a1, b1), (c, a1, b1, c1))]
    tets = np.vstack(tets).astype(np.int64)
    orient_positive(points, tets)
    return points, tets


def _cut_facets(points: np.ndarray, tets: np.ndarray, angle: float, tol: float):
    """(boundary facets on the plane theta = 0, on the plane theta = angle, the rest) of a wedge."""
    tris, _ = boundary_facets(tets)
    normal_end = np.array([-math.sin(angle), math.cos(angle), 0.0])
    on_start = np.all(np.abs(points[tris][:, :, 1]) < tol, axis=1)
    on_end = np.all(np.abs(points[tris] @ normal_end) < tol, axis=1)
    return tris[on_start], tris[on_end], tris[~(on_start | on_end)]


def mesh_foot_revolved(
    design: FootDesign | None = None,
    *,
    n_theta: int = N_THETA,
    thickness_layers: int = THICKNESS_LAYERS,
    cell_size: float = CELL_SIZE,
    copies: int = 1,
) -> TaggedMesh:
    """Revolved tetrahedral mesh of the foot (region ``foot``), with the tags of `geometry.foot`.

    `copies` > 1: the wedge 0 <= theta <= 2 pi / copies of the same mesh (its first n_theta /
    copies sectors, node for node those of the whole mesh), whose cut faces are tagged
    ``cut_start`` (theta = 0, the plane y = 0) and ``cut_end`` (theta = 2 pi / copies). The whole
    mesh is the wedge turned `copies` times about z (`fem.periodic_tie` ties the two cuts)."""
    design = design or FootDesign()
    if not (isinstance(n_theta, int) and n_theta >= 12):
        raise DesignError("n_theta", f"needs at least 12 sectors around the axis, got {n_theta!r}")
    if not (isinstance(thickness_layers, int) and thickness_layers >= 1):
        raise DesignError(
            "thickness_layers", f"needs at least 1 cell through the skirt, got {thickness_layers!r}"
        )
    thickness_cells(design, thickness_layers)
    if not (isinstance(copies, int) and copies >= 1 and n_theta % copies == 0 and n_theta // copies >= 2):
        raise DesignError(
            "copies", f"must divide the {n_theta} sectors into wedges of at least 2, got {copies!r}"
        )
    if not (isinstance(cell_size, (int, float)) and math.isfinite(cell_size) and cell_size > 0):
        raise DesignError("cell_size", f"must be a positive length in mm, got {cell_size!r}")
    xy, tris = foot_section(design, thickness_layers, float(cell_size))
    points, tets = revolve_section(xy, tris, n_theta, n_theta // copies)
    segments = foot_segments(design)
    tol = 1e-9 * design.tip_radius
    rest, cuts = None, {}
    if copies > 1:
        start, end, rest = _cut_facets(points, tets, 2 * math.pi / copies, tol)
        cuts = {"cut_start": start, "cut_end": end}
    points, facets, n_untagged = tag_boundary(points, tets, segments, tol, snap=False, tris=rest)
    facets |= cuts
    if n_untagged:
        raise RuntimeError(f"revolved foot mesh: {n_untagged} boundary facets on no surface of the foot")
    return TaggedMesh(
        points,
        tets,
        np.ones(len(tets), dtype=int),
        {1: "foot"},
        facets,
        (),
        design.short_hash(),
        float(cell_size),
        {
            "kind": "foot",
            "mesher": "revolved",
            "n_theta": n_theta,
            "thickness_layers": thickness_layers,
            "cell_size": float(cell_size),
            "copies": copies,
            "curved_surfaces": curved_surface_meta(segments),
        },
    )
