r"""Conforming swept mesh of the whole robot: three ePSAs, seal heads, n rings and two foot hubs.

Why swept and conforming (docs/decisions/043-robot-mesh.md). The parts are tied in the paper (Abaqus
*Tie*). A mesh whose parts share their interface nodes is a perfect tie: the interface carries
any force exactly and needs no constraint equations. Everything in the robot's load path is a
prism over one cross-section: the actuators are cylinders along z, the rings are plates with
holes of the actuator radius, the foot hubs are disks. So one triangulated cross-section,
extruded in z layer by layer, gives every part; a layer keeps only the triangles of the parts
present at its height, and neighbouring parts share nodes by construction.

Cross-section (z = const). Actuator i is the polar mesh of `geometry.swept.cross_section` (a
fan to the chamber radius r0, `n_radial` rings across the wall) centred at c_i = d (cos psi_i,
sin psi_i), psi = 90, 210, 330 deg. The web between and around the actuators (rings, hubs) is a
Delaunay triangulation of the actuators' outer-circle nodes, of points on the axis-centred
circles (ring and hub outer radii, ring and hub bores) and of fill points; triangles inside an
actuator disk or the smallest bore or outside the largest circle are dropped. A chord of an
actuator circle is always a Delaunay edge of this point set (the circle through its two ends
that nearly follows the actuator circle holds no point), and the axis circles are sampled
finely enough for theirs to be (checked: a missing circle edge is an error).

Layers (z): rear hub [-t_hub, 0], actuators [0, L] (the chamber r < r0 is empty for c < z < L - c),
seal heads [L, L + t_s], front hub [L + t_s, L + t_s + t_hub]; ring k at z_k +- t_r / 2
(z_k = k L / (n + 1)) occupies the web annulus between the ring bore and the ring's outer radius.
The hubs are the feet's disks (under the actuators too); rings and hubs share one outline
(`stiff_outline`);
the conical grooved skirts of `geometry.foot` are not part of this mesh (they carry no load in
free bending; the crawling gait will need them with contact). Each prism is split into three
tetrahedra by the global node order (as in `geometry.swept`), so all layers conform.

Regions: epsa1..3, seal_head1..3, ring1..n, foot_rear, foot_front. Facet tags: chamber_wall{i},
chamber_ends{i} (actuator i's cavity), outer{i} (rho_i = R0, 0 <= z <= L, interface facets under
the rings included: the fiber sheets live there), rear_bottom (z = -t_hub, the clamp),
front_top (z = L + t_s + t_hub). `meta['curved_surfaces']` snaps P2 midside nodes to the exact
cylinders (`TaggedMesh.to_skfem(order=2)`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import Delaunay

from softcrawl.geometry.design import DesignError, RobotDesign
from softcrawl.geometry.swept import boundary_faces, cross_section, levels
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import RevolvedSegment, curved_surface_meta, orient_positive

_LOCAL_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


@dataclass(frozen=True, kw_only=True)
class RobotMeshSettings:
    """Actuator cross-section (`n_around` sectors, `n_radial` cells across the wall), the axial
    element size and the target edge length of the web between the actuators (mm)."""

    n_around: int = 16
    n_radial: int = 2
    axial_size: float = 5.0
    web_size: float = 3.0

    def __post_init__(self):
        if self.n_around < 8 or self.n_around % 4:
            raise DesignError("n_around", f"needs a multiple of 4, at least 8, got {self.n_around}")
        if self.n_radial < 1:
            raise DesignError("n_radial", f"needs at least 1 cell across the wall, got {self.n_radial}")
        for name in ("axial_size", "web_size"):
            if not getattr(self, name) > 0:
                raise DesignError(name, f"must be a positive length in mm, got {getattr(self, name)}")


MESH_PRESETS = {
    "quick": RobotMeshSettings(n_around=12, n_radial=1, axial_size=10.0, web_size=4.0),
    "default": RobotMeshSettings(),
    "fine": RobotMeshSettings(n_around=20, n_radial=2, axial_size=4.0, web_size=2.5),
}


@dataclass(frozen=True)
class CrossSection:
    """Nodes (n, 2), triangles (t, 3) and per triangle: owner actuator (0..2, -1 for the web),
    whether it is inside the chamber radius, and the distance of its centroid from the axis."""

    nodes: np.ndarray
    tris: np.ndarray
    actuator: np.ndarray
    in_chamber: np.ndarray
    rho: np.ndarray
    axis_radii: tuple[float, ...]


def _axis_radii(design: RobotDesign) -> tuple[float, ...]:
    """The axis-centred circles of the section: one bore and one outline for the rings and the
    hubs together (the smaller bore, the larger outer radius; see `stiff_outline`)."""
    bore, outer = stiff_outline(design)
    return (bore, outer) if bore > 0 else (outer,)


def stiff_outline(design: RobotDesign) -> tuple[float, float]:
    """(bore radius, outer radius) of the rings and foot hubs in this mesh. By default both have
    the body's part radius (`softcrawl.body`, 24 mm) and their bores differ by 0.5 mm (ring 3.5,
    hub 4 mm); parts given explicitly may differ more. One outline for both keeps the section's
    circles apart, so the web needs no sub-millimetre cells (which made the web, not the
    actuators, hold most of the unknowns). The parts are ABS and Shore 70A rubber, 3-4 orders
    stiffer than the silicone: 1 mm on their outline does not change how the actuators bend."""
    f, r = design.foot, design.ring
    bores = [b for b in (f.bore_radius, r.bore_radius if design.n_rings else None) if b is not None]
    outers = [f.hub_radius] + ([r.outer_radius] if design.n_rings else [])
    return min(bores), max(outers)


def robot_cross_section(
    design: RobotDesign,
    settings: RobotMeshSettings,
    *,
    outline_points: int | None = None,
    symmetric: bool = False,
) -> CrossSection:
    """The section of the module docstring. `outline_points`: the number of points on the outline
    circle of rings and hubs (None: from the spacing rule below); the one-body mesh
    (`geometry.body_mesh`) sets it to its skirts' sector count, so that the skirts' roots meet the
    hubs node to node. `symmetric`: every circle's point count a multiple of 3 and actuator i's
    polar section turned by psi_i - psi_1, so that the point set has the robot's three-fold
    symmetry (the default robot mesh has neither)."""
    e = design.epsa
    R0, r0 = e.outer_radius, e.chamber_radius
    xy, tris, is_wall = cross_section(r0, R0, settings.n_around, settings.n_radial)
    n_act = len(xy)
    outer_ring = np.arange(n_act - settings.n_around, n_act)  # last ring: rho = R0
    centres = np.array(design.actuator_centres)
    turn = np.arctan2(centres[:, 1], centres[:, 0]) - math.atan2(centres[0, 1], centres[0, 0])
    rot = [np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]) for a in turn]
    nodes = [(xy @ rot[i].T if symmetric else xy) + c for i, c in enumerate(centres)]
    act_tris = [tris + i * n_act for i in range(3)]
    radii = _axis_radii(design)
    # axis circles: spacing below the web size and comparable to the gap to the actuators, so
    # that their chords are Delaunay edges (checked below; the outline's chords are edges of the
    # convex hull, hence Delaunay edges, at any spacing)
    circle_pts = []
    for r in radii:
        gap = abs(r - (design.d + R0)) if r > design.d else abs(design.d - R0 - r)
        spacing = min(settings.web_size, 1.5 * gap)
        n = max(24, math.ceil(2 * math.pi * r / spacing))
        n = 3 * math.ceil(n / 3) if symmetric else n
        if outline_points is not None and r == radii[-1]:
            n = outline_points
        th = 2 * math.pi * (np.arange(n) + 0.5) / n
        circle_pts.append(np.column_stack([r * np.cos(th), r * np.sin(th)]))
    circles = np.vstack(circle_pts)
    fill = _fill_points(design, settings, radii, centres, R0, symmetric)
    web_nodes = np.vstack([np.vstack([nodes[i][outer_ring] for i in range(3)]), circles, fill])
    web_index = np.r_[np.concatenate([outer_ring + i * n_act for i in range(3)]),
                      3 * n_act + np.arange(len(circles) + len(fill))]  # fmt: skip
    tri = Delaunay(web_nodes).simplices
    cxy = web_nodes[tri].mean(axis=1)
    rho_c = np.hypot(cxy[:, 0], cxy[:, 1])
    keep = (rho_c > radii[0]) & (rho_c < radii[-1])
    for c in centres:
        keep &= np.hypot(cxy[:, 0] - c[0], cxy[:, 1] - c[1]) > R0
    tri = tri[keep]
    area = _areas(web_nodes, tri)
    if area.min() < 1e-6 * settings.web_size**2:
        raise RuntimeError("robot cross-section: a degenerate web triangle; change web_size")
    web_tris = web_index[tri]
    all_nodes = np.vstack([*nodes, circles, fill])
    _check_circle_edges(all_nodes, web_tris, design, radii, outer_ring, n_act)
    all_tris = np.vstack([*act_tris, web_tris])
    owner = np.r_[np.repeat(np.arange(3), len(tris)), np.full(len(web_tris), -1)]
    in_chamber = np.r_[np.tile(~is_wall, 3), np.zeros(len(web_tris), bool)]
    c_all = all_nodes[all_tris].mean(axis=1)
    return CrossSection(all_nodes, all_tris, owner, in_chamber, np.hypot(c_all[:, 0], c_all[:, 1]), radii)


def _areas(xy: np.ndarray, tris: np.ndarray) -> np.ndarray:
    a, b, c = xy[tris[:, 0]], xy[tris[:, 1]], xy[tris[:, 2]]
    return 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def _fill_points(
    design: RobotDesign,
    settings: RobotMeshSettings,
    radii: np.ndarray,
    centres: np.ndarray,
    R0: float,
    symmetric: bool = False,
) -> np.ndarray:
    """Points on concentric circles in the web, kept clear of every circle of the section."""
    h = settings.web_size
    pts = []
    for r in np.arange(radii[0] + h, radii[-1], h):
        n = max(12, math.ceil(2 * math.pi * r / h))
        n = 3 * math.ceil(n / 3) if symmetric else n
        th = 2 * math.pi * np.arange(n) / n + (r / h) * 0.5 * (2 * math.pi / n)
        pts.append(np.column_stack([r * np.cos(th), r * np.sin(th)]))
    if not pts:
        return np.zeros((0, 2))
    p = np.vstack(pts)
    rho = np.hypot(p[:, 0], p[:, 1])
    clear = np.ones(len(p), bool)
    for r in radii:
        clear &= np.abs(rho - r) > 0.6 * h
    for c in centres:
        clear &= np.hypot(p[:, 0] - c[0], p[:, 1] - c[1]) > R0 + 0.6 * h
    return p[clear]


def _check_circle_edges(
    nodes: np.ndarray,
    web_tris: np.ndarray,
    design: RobotDesign,
    radii: np.ndarray,
    outer_ring: np.ndarray,
    n_act: int,
) -> None:
    """Every chord of an actuator circle and of an axis circle is an edge of the web."""
    e = np.sort(np.vstack([web_tris[:, [0, 1]], web_tris[:, [1, 2]], web_tris[:, [2, 0]]]), axis=1)
    edges = set(map(tuple, e))
    for i in range(3):
        ring = outer_ring + i * n_act
        chords = np.sort(np.column_stack([ring, np.roll(ring, -1)]), axis=1)
        if not all(tuple(c) in edges for c in chords):
            raise RuntimeError(f"robot cross-section: the web does not follow actuator {i + 1}'s circle")
    rho = np.hypot(nodes[:, 0], nodes[:, 1])
    for r in radii:
        on = np.nonzero(np.abs(rho - r) < 1e-9 * r)[0]
        on = on[np.argsort(np.arctan2(nodes[on, 1], nodes[on, 0]))]
        chords = np.sort(np.column_stack([on, np.roll(on, -1)]), axis=1)
        if not all(tuple(c) in edges for c in chords):
            raise RuntimeError(f"robot cross-section: the web does not follow the circle r = {r} mm")


def layer_levels(design: RobotDesign, settings: RobotMeshSettings, extra: tuple = ()) -> np.ndarray:
    """The z levels: every part boundary (and the levels `extra`), each interval cut into elements
    of about axial_size."""
    e, f = design.epsa, design.foot
    L, c, ts, th = e.length, e.end_cap_thickness, e.seal_head_thickness, f.hub_thickness
    breaks = {-th, 0.0, c, L - c, L, L + ts, L + ts + th} | {float(z) for z in extra}
    for zk in design.ring_centres_z:
        breaks |= {zk - design.ring.thickness / 2, zk + design.ring.thickness / 2}
    breaks = sorted(breaks)
    return np.unique(np.concatenate([levels(a, b, settings.axial_size) for a, b in zip(breaks, breaks[1:])]))


def layer_parts(design: RobotDesign, cs: CrossSection, zmid: float) -> list[tuple[str, np.ndarray]]:
    """(region name, triangle mask) of the parts present in the layer at height zmid."""
    e, r = design.epsa, design.ring
    L, c, ts = e.length, e.end_cap_thickness, e.seal_head_thickness
    act = cs.actuator >= 0
    bore, outer = stiff_outline(design)
    if zmid < 0.0 or zmid > L + ts:
        hub = act | ((cs.actuator < 0) & (cs.rho > bore) & (cs.rho < outer))
        return [("foot_rear" if zmid < 0 else "foot_front", hub)]
    if zmid > L:
        return [(f"seal_head{i + 1}", cs.actuator == i) for i in range(3)]
    in_cap = zmid < c or zmid > L - c
    parts = [(f"epsa{i + 1}", (cs.actuator == i) & (in_cap | ~cs.in_chamber)) for i in range(3)]
    for k, zk in enumerate(design.ring_centres_z, start=1):
        if abs(zmid - zk) < r.thickness / 2:
            web = (cs.actuator < 0) & (cs.rho > bore) & (cs.rho < outer)
            parts.append((f"ring{k}", web))
    return parts


def mesh_robot_swept(
    design: RobotDesign | None = None, settings: RobotMeshSettings | str = "default"
) -> TaggedMesh:
    """The conforming robot mesh of the module docstring."""
    design = design or RobotDesign()
    settings = MESH_PRESETS[settings] if isinstance(settings, str) else settings
    cs = robot_cross_section(design, settings)
    z = layer_levels(design, settings)
    n2 = len(cs.nodes)
    tris = np.sort(cs.tris, axis=1)
    names = ["foot_rear", *(f"epsa{i}" for i in (1, 2, 3)), *(f"seal_head{i}" for i in (1, 2, 3))]
    names += [f"ring{k}" for k in range(1, design.n_rings + 1)] + ["foot_front"]
    rid = {name: i for i, name in enumerate(names, start=1)}
    tets, region = [], []
    for k in range(len(z) - 1):
        for name, mask in layer_parts(design, cs, 0.5 * (z[k] + z[k + 1])):
            a, b, cc = (tris[mask, i] + k * n2 for i in range(3))
            a1, b1, c1 = a + n2, b + n2, cc + n2
            tets += [np.column_stack(t) for t in ((a, b, cc, a1), (b, cc, a1, b1), (cc, a1, b1, c1))]
            region.append(np.full(3 * int(mask.sum()), rid[name]))
    tets = np.vstack(tets).astype(np.int64)
    region = np.concatenate(region)
    points = np.column_stack([np.tile(cs.nodes, (len(z), 1)), np.repeat(z, n2)])
    used, tets = np.unique(tets, return_inverse=True)
    tets = tets.reshape(-1, 4)
    points = points[used]
    orient_positive(points, tets)
    facets = tag_robot_facets(points, tets, design)
    return TaggedMesh(
        points,
        tets,
        region,
        {i: name for name, i in rid.items()},
        facets,
        (),
        design.short_hash(),
        float(settings.axial_size),
        {
            "kind": "robot",
            "mesher": "swept-conforming",
            "settings": {k: getattr(settings, k) for k in ("n_around", "n_radial", "axial_size", "web_size")},
            "channel_radius_mm": design.channel_radius,
            "curved_surfaces": curved_surface_meta(robot_segments(design)),
        },
    )


def robot_segments(design: RobotDesign) -> list[RevolvedSegment]:
    e = design.epsa
    R0, r0, L, c = e.outer_radius, e.chamber_radius, e.length, e.end_cap_thickness
    out = []
    for i, centre in enumerate(design.actuator_centres, start=1):
        out.append(RevolvedSegment(f"outer{i}", (R0, 0.0), (R0, L), centre, curved=True))
        out.append(RevolvedSegment(f"chamber_wall{i}", (r0, L - c), (r0, c), centre, curved=True))
    return out


def tag_robot_facets(points: np.ndarray, tets: np.ndarray, design: RobotDesign) -> dict[str, np.ndarray]:
    e, f = design.epsa, design.foot
    R0, r0, L, c, ts = e.outer_radius, e.chamber_radius, e.length, e.end_cap_thickness, e.seal_head_thickness
    tol = 1e-9 * max(L, R0)
    boundary = boundary_faces(tets)
    faces = tets[:, _LOCAL_FACES].reshape(-1, 3)
    _, first = np.unique(np.sort(faces, axis=1), axis=0, return_index=True)
    faces = faces[np.sort(first)]  # every face once (interior ones with one of their orientations)

    def on(tris: np.ndarray, cond) -> np.ndarray:  # noqa: ANN001
        return np.all(cond(points[tris]), axis=1)

    def in_z(p: np.ndarray, a: float, b: float) -> np.ndarray:
        return (p[..., 2] > a - tol) & (p[..., 2] < b + tol)

    out = {}
    for i, (cx, cy) in enumerate(design.actuator_centres, start=1):
        rho_f = np.hypot(points[faces][..., 0] - cx, points[faces][..., 1] - cy)
        on_outer = np.all((np.abs(rho_f - R0) < tol) & in_z(points[faces], 0.0, L), axis=1)
        out[f"outer{i}"] = faces[on_outer]
        rho_b = np.hypot(points[boundary][..., 0] - cx, points[boundary][..., 1] - cy)
        cavity = boundary[np.all((rho_b < r0 + tol) & in_z(points[boundary], c, L - c), axis=1)]
        flat = on(cavity, lambda p: (np.abs(p[..., 2] - c) < tol) | (np.abs(p[..., 2] - L + c) < tol))
        out[f"chamber_wall{i}"] = cavity[~flat]
        out[f"chamber_ends{i}"] = cavity[flat]
    out["rear_bottom"] = boundary[on(boundary, lambda p: np.abs(p[..., 2] + f.hub_thickness) < tol)]
    top = L + ts + f.hub_thickness
    out["front_top"] = boundary[on(boundary, lambda p: np.abs(p[..., 2] - top) < tol)]
    for tag, tris in out.items():
        if len(tris) == 0:
            raise RuntimeError(f"robot mesh: tag {tag!r} has no facets")
    return {k: v.astype(np.int64) for k, v in out.items()}
