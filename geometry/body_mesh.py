r"""The whole robot as one conforming mesh: the swept robot and both feet's grooved skirts.

Why one conforming mesh (docs/decisions/076-one-body.md). The swept robot mesh
(`geometry.robot_mesh`, record 043) already ties actuators, seal heads, rings and foot hubs by
shared nodes; its hubs are the feet's hub disks but carry no skirts. The skirts are the revolved
foot's (`geometry.foot_revolved`, the crawl's reduced model's feet), whose root is the segment
rho = r_hub, -t / sin(alpha) <= z <= 0 of the hub's side. Both meshes are prisms: the robot's
are its cross-section's triangles extruded between z levels, the skirt's are its (rho, z)
section's triangles swept between angles. They meet node to node on the hub side when

  - the outline circle of the robot's section (rings and hubs, radius r_hub) has one point per
    skirt sector, at the skirt's angles theta_k = 2 pi (k + 1/2) / n_sectors;
  - the robot's hub layers include the skirt root's depth levels (z of the section's nodes on
    rho = r_hub).

Then every quadrilateral of the hub side is one face of a robot prism and of a skirt prism, and
it conforms when both prisms cut it along the same diagonal. So all prisms, robot and skirt, are
cut by one rule on one order of the nodes (Dompierre et al. 1999, "How to subdivide pyramids,
prisms and hexahedra into tetrahedra"): each quadrilateral is cut along the diagonal through its
lowest-ranked vertex; a prism whose lowest vertex is W0 (after turning the prism so) becomes

    diagonal W1-W5:  [W0 W1 W2 W5] [W0 W1 W5 W4] [W0 W4 W5 W3]
    diagonal W2-W4:  [W0 W1 W2 W4] [W0 W4 W2 W5] [W0 W4 W5 W3]

(W3..W5 above W0..W2). A face's diagonal depends only on its own four vertices, so any two prisms
sharing it agree. The rank sorts the nodes by (z, rho, polar angle modulo 120 deg): a rotation by
120 deg about the axis keeps every rank comparison between the nodes of one prism (two nodes of
one prism are never each other's images), so with a section that has the three-fold symmetry
(`robot_cross_section(..., symmetric=True)`, sector counts multiples of 3) the tetrahedra have it
too.

Regions: those of the robot mesh; the skirts' tets join their foot's region (foot_rear,
foot_front), the rubber of the hub. Facet tags: the robot's (`robot_mesh.tag_robot_facets`) and,
per foot, "rear:front", "rear:rim", "rear:back" (and "front:..."), the skirt faces of
`geometry.foot` that meet the wall, found by the exact predicates of `geometry.tagging` (every
skirt boundary facet must get one). The front foot is the reduced crawl's ("paper" feet, both
skirts leaning back): its hub top at z = L + t_s + t_hub. `meta['curved_surfaces']` snaps the P2
midside nodes of the actuators' cylinders and the skirts' cones onto the exact surfaces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import cKDTree

from softcrawl.geometry.design import DesignError, RobotDesign
from softcrawl.geometry.foot import foot_segments
from softcrawl.geometry.foot_design import FootDesign
from softcrawl.geometry.foot_meshers import quick_sectors
from softcrawl.geometry.foot_revolved import CELL_SIZE, THICKNESS_LAYERS, foot_section
from softcrawl.geometry.robot_mesh import (
    MESH_PRESETS,
    RobotMeshSettings,
    layer_levels,
    layer_parts,
    robot_cross_section,
    robot_segments,
    tag_robot_facets,
)
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tagging import boundary_facets, classify_facets, curved_surface_meta, orient_positive

#: The skirt faces that meet the wall, tagged per foot ("rear:front", ...).
SKIRT_TAGS = ("front", "rim", "back")
FEET = ("rear", "front")

#: A prism (W0..W5) turned so that its vertex m is W0, for m = 0..5.
_TURN = np.array(
    [
        [0, 1, 2, 3, 4, 5],
        [1, 2, 0, 4, 5, 3],
        [2, 0, 1, 5, 3, 4],
        [3, 4, 5, 0, 1, 2],
        [4, 5, 3, 1, 2, 0],
        [5, 3, 4, 2, 0, 1],
    ]
)


@dataclass(frozen=True, kw_only=True)
class BodyMeshSettings:
    """The robot's section and layers (`robot`), the skirts' `sectors` (also the points on the
    rings' and hubs' outline; a multiple of 3), cells through the skirt and along it (mm)."""

    robot: RobotMeshSettings
    sectors: int
    thickness_layers: int = THICKNESS_LAYERS
    cell_size: float = CELL_SIZE

    def __post_init__(self):
        if not (isinstance(self.sectors, int) and self.sectors >= 12 and self.sectors % 3 == 0):
            raise DesignError("sectors", f"needs a multiple of 3, at least 12, got {self.sectors!r}")
        if not (isinstance(self.thickness_layers, int) and self.thickness_layers >= 2):
            raise DesignError("thickness_layers", f"needs at least 2 cells, got {self.thickness_layers!r}")
        if not (math.isfinite(self.cell_size) and self.cell_size > 0):
            raise DesignError("cell_size", f"must be a positive length in mm, got {self.cell_size!r}")


#: quick: the quick robot with 36 skirt sectors; default: the default robot with the reduced
#: crawl's default feet (48 sectors). The reduced crawl's quick feet have 24 sectors, but in the
#: quick body 24 points on the 24 mm outline, 1 mm outside the actuators, leave web cells so thin
#: that the fiber sheets' facet quadrature on outer{i} cannot be placed in their curved P2
#: elements (measured: 24 fails, 36 and 48 build; record 076).
BODY_MESH_PRESETS = {
    "quick": BodyMeshSettings(robot=MESH_PRESETS["quick"], sectors=36),
    "default": BodyMeshSettings(robot=MESH_PRESETS["default"], sectors=48),
}


def settings_for(foot: FootDesign, preset: str) -> BodyMeshSettings:
    """The preset's settings with at least the reduced crawl's sectors for this foot angle
    (`geometry.foot_meshers.quick_sectors`, more below 120 deg), rounded up to a multiple of 3."""
    if preset not in BODY_MESH_PRESETS:
        raise DesignError("mesh", f"{preset!r} is not one of {sorted(BODY_MESH_PRESETS)}")
    s = BODY_MESH_PRESETS[preset]
    return replace(s, sectors=max(s.sectors, 3 * math.ceil(quick_sectors(foot) / 3)))


def hub_tops(design: RobotDesign) -> dict[str, float]:
    """z of each foot's hub top, where its skirt leaves the hub (rear 0, front L + t_s + t_hub)."""
    e = design.epsa
    return {"rear": 0.0, "front": e.length + e.seal_head_thickness + design.foot.hub_thickness}


def skirt_section(
    design: RobotDesign, settings: BodyMeshSettings
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The revolved foot's section without its hub block: nodes (n, 2) in (rho, z) with the hub
    top at z = 0, triangles, and the indices of the root nodes on the hub side rho = r_hub."""
    f = design.foot
    xy, tris = foot_section(f, settings.thickness_layers, float(settings.cell_size))
    tol = 1e-9 * f.tip_radius
    keep = xy[tris].mean(axis=1)[:, 0] > f.hub_radius + tol
    used, tris = np.unique(tris[keep], return_inverse=True)
    xy = xy[used]
    root = np.nonzero(np.abs(xy[:, 0] - f.hub_radius) < tol)[0]
    xy[root, 0] = f.hub_radius
    return xy, tris.reshape(-1, 3), root


def split_prisms(prisms: np.ndarray, rank: np.ndarray) -> np.ndarray:
    """Tets (3 m, 4) of prisms (m, 6), each quadrilateral cut through its lowest-ranked vertex."""
    m = np.argmin(rank[prisms], axis=1)
    w = np.take_along_axis(prisms, _TURN[m], axis=1)
    r = rank[w]
    first = np.minimum(r[:, 1], r[:, 5]) < np.minimum(r[:, 2], r[:, 4])
    a = np.where(first[:, None], w[:, [0, 1, 2, 5]], w[:, [0, 1, 2, 4]])
    b = np.where(first[:, None], w[:, [0, 1, 5, 4]], w[:, [0, 4, 2, 5]])
    return np.vstack([a, b, w[:, [0, 4, 5, 3]]])


def symmetry_rank(points: np.ndarray) -> np.ndarray:
    """Rank of each node by (z, rho, polar angle modulo 120 deg), rounded to 1e-8 mm / 1e-10 rad."""
    rho = np.hypot(points[:, 0], points[:, 1])
    phi = np.mod(np.arctan2(points[:, 1], points[:, 0]), 2 * math.pi / 3)
    keys = (np.round(phi * 1e10), np.round(rho * 1e8), np.round(points[:, 2] * 1e8))
    order = np.lexsort(keys)
    rank = np.empty(len(points), dtype=np.int64)
    rank[order] = np.arange(len(points))
    return rank


def mesh_body(design: RobotDesign | None = None, settings: BodyMeshSettings | str = "default") -> TaggedMesh:
    """The conforming one-body mesh of the module docstring."""
    design = design or RobotDesign()
    settings = settings_for(design.foot, settings) if isinstance(settings, str) else settings
    f = design.foot
    sxy, stris, root = skirt_section(design, settings)
    tops = hub_tops(design)
    root_z = [top + z for top in tops.values() for z in sxy[root, 1]]
    cs = robot_cross_section(design, settings.robot, outline_points=settings.sectors, symmetric=True)
    if not math.isclose(cs.axis_radii[-1], f.hub_radius):
        raise DesignError("foot.hub_radius", "the body mesh needs the hub's and the rings' outline equal")
    z = layer_levels(design, settings.robot, extra=tuple(root_z))
    # the robot's prisms: the section's triangles of each part between two levels
    n2 = len(cs.nodes)
    names = ["foot_rear", *(f"epsa{i}" for i in (1, 2, 3)), *(f"seal_head{i}" for i in (1, 2, 3))]
    names += [f"ring{k}" for k in range(1, design.n_rings + 1)] + ["foot_front"]
    rid = {name: i for i, name in enumerate(names, start=1)}
    prisms, region = [], []
    for k in range(len(z) - 1):
        for name, mask in layer_parts(design, cs, 0.5 * (z[k] + z[k + 1])):
            t = cs.tris[mask] + k * n2
            prisms.append(np.hstack([t, t + n2]))
            region.append(np.full(len(t), rid[name]))
    points = [np.column_stack([np.tile(cs.nodes, (len(z), 1)), np.repeat(z, n2)])]
    # the skirts' prisms: the section's triangles between two sectors
    n, ns = settings.sectors, len(sxy)
    theta = 2 * math.pi * (np.arange(n) + 0.5) / n
    offset = len(points[0])
    for foot, top in tops.items():
        rho, th = np.tile(sxy[:, 0], n), np.repeat(theta, ns)
        points.append(np.column_stack([rho * np.cos(th), rho * np.sin(th), np.tile(sxy[:, 1], n) + top]))
        for k in range(n):
            lo, hi = offset + k * ns, offset + ((k + 1) % n) * ns
            prisms.append(np.hstack([stris + lo, stris + hi]))
            region.append(np.full(len(stris), rid[f"foot_{foot}"]))
        offset += n * ns
    points = np.vstack(points)
    prisms, region = np.vstack(prisms).astype(np.int64), np.concatenate(region)
    points, prisms, merged = _merge_roots(points, prisms, len(points) - 2 * n * ns, f.tip_radius)
    if merged != 2 * n * len(root):
        raise RuntimeError(f"body mesh: {merged} skirt root nodes met the hubs, expected {2 * n * len(root)}")
    used, inverse = np.unique(prisms, return_inverse=True)
    points, prisms = points[used], inverse.reshape(prisms.shape)
    tets = split_prisms(prisms, symmetry_rank(points))
    region = np.tile(region, 3)
    if np.any(orient_positive(points, tets) < 1e-12 * f.tip_radius**3 / 6.0):
        raise RuntimeError("body mesh: a degenerate tetrahedron")
    facets = tag_robot_facets(points, tets, design)
    facets |= _tag_skirts(points, tets, region, rid, design)
    curved = curved_surface_meta(robot_segments(design))
    for foot, top in tops.items():
        for s in foot_segments(f, top):
            if s.tag in SKIRT_TAGS and s.curved:
                curved.setdefault(f"{foot}:{s.tag}", []).append([list(s.p0), list(s.p1), list(s.centre)])
    return TaggedMesh(
        points,
        tets,
        region,
        {i: name for name, i in rid.items()},
        facets,
        (),
        design.short_hash(),
        float(settings.robot.axial_size),
        {
            "kind": "body",
            "mesher": "swept-revolved-conforming",
            "settings": {
                **{k: getattr(settings.robot, k) for k in ("n_around", "n_radial", "axial_size", "web_size")},
                "sectors": settings.sectors,
                "thickness_layers": settings.thickness_layers,
                "cell_size": float(settings.cell_size),
            },
            "channel_radius_mm": design.channel_radius,
            "curved_surfaces": curved,
        },
    )


def _merge_roots(points: np.ndarray, prisms: np.ndarray, n_robot: int, scale: float):
    """Skirt nodes (index >= n_robot) that coincide with a robot node (within 1e-9 of `scale`)
    replaced by it; returns points, prisms and the number of nodes merged."""
    tree = cKDTree(points[:n_robot])
    dist, nearest = tree.query(points[n_robot:])
    hit = dist < 1e-9 * scale
    index = np.arange(len(points))
    index[n_robot:][hit] = nearest[hit]
    return points, index[prisms], int(hit.sum())


def _tag_skirts(
    points: np.ndarray, tets: np.ndarray, region: np.ndarray, rid: dict, design: RobotDesign
) -> dict[str, np.ndarray]:
    """Per foot, the skirt's boundary facets on its front, rim and back faces; every boundary facet
    of a skirt tet (not the hub's) must be one of them."""
    f = design.foot
    tris, owner = boundary_facets(tets)
    out = {}
    for foot, top in hub_tops(design).items():
        segments = [s for s in foot_segments(f, top) if s.tag in SKIRT_TAGS]
        mine = tris[region[owner] == rid[f"foot_{foot}"]]
        idx = classify_facets(points, mine, segments, 1e-9 * f.tip_radius)
        rho = np.hypot(points[mine][..., 0], points[mine][..., 1]).max(axis=1)
        in_skirt = rho > f.hub_radius + 1e-9 * f.tip_radius  # a hub facet has no vertex beyond the hub
        if np.any(in_skirt & (idx < 0)):
            raise RuntimeError(
                f"body mesh: {int(np.sum(in_skirt & (idx < 0)))} skirt facets of the {foot} foot untagged"
            )
        for tag in SKIRT_TAGS:
            members = [i for i, s in enumerate(segments) if s.tag == tag]
            out[f"{foot}:{tag}"] = mine[np.isin(idx, members)].astype(np.int64)
    return out


def rotation_defect(points: np.ndarray, angle_deg: float = 120.0) -> float:
    """The mesh's asymmetry under a rotation about the axis: the largest distance (mm) from a node's
    image to the nearest node. 0 to round-off for a mesh with that symmetry; pass the P2 nodes
    (vertices and edge midpoints) to see the connectivity too (a differently cut quadrilateral
    moves an edge midpoint)."""
    a = math.radians(angle_deg)
    rot = np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])
    dist, _ = cKDTree(points).query(points @ rot.T)
    return float(dist.max())
