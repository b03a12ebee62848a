"""Assembly of the robot from part meshes (three ePSAs, seal heads, rings, two feet).

Layout (reference configuration, z along the robot axis, units mm):
* ePSA i (i = 1, 2, 3): axis at (d cos psi_i, d sin psi_i), psi = 90, 210, 330 deg, z in [0, L];
* seal head i: z in [L, L + t_s] on ePSA i;
* ring k (k = 1..n): centred at z_k = k L / (n + 1), thickness t_r, holes around the ePSAs;
* rear foot: hub top face at z = 0 (hub z in [-t_hub, 0]); front foot: hub bottom face on the seal
  heads, z = L + t_s. Both feet lean backwards (the same orientation).

Each part is meshed on its own (cached) and placed by a rigid motion; parts do not share nodes. The
paper ties them (Abaqus *Tie*); here the touching facets carry interface tags
``interface:<a>/<b>`` (facets of part a lying on part b, outward from a) and ``interface:<b>/<a>``.
The other boundary facets keep the part's tag, prefixed with the part: ``epsa1:chamber_wall``,
``ring2:outer``, ``foot_rear:back``... Regions: ``epsa1..3``, ``seal_head1..3``, ``ring1..n``,
``foot_rear``, ``foot_front``. Fibers: two per ePSA, in the order epsa1 (+, -), epsa2, epsa3.

The centre channel (room for the endoscope) is the largest axis-centred cylinder free of actuators,
of radius d - R0 (5 mm for Table 1).
"""

from __future__ import annotations

import numpy as np

from softcrawl.geometry.design import RobotDesign
from softcrawl.geometry.epsa_shape import epsa_surface, seal_head_surface
from softcrawl.geometry.foot import foot_surface
from softcrawl.geometry.ring import ring_surface
from softcrawl.geometry.tagged_mesh import TaggedMesh
from softcrawl.geometry.tetwild import CacheDir, mesh_epsa, mesh_foot, mesh_ring, mesh_seal_head


def _on_disk(
    mesh: TaggedMesh, tris: np.ndarray, centre: tuple[float, float], radius: float, tol: float
) -> np.ndarray:
    c = mesh.points[tris].mean(axis=1)
    return np.hypot(c[:, 0] - centre[0], c[:, 1] - centre[1]) <= radius + tol


def assemble_robot(
    design: RobotDesign | None = None, edge_length: float | None = None, cache_dir: CacheDir = None
) -> TaggedMesh:
    design = design or RobotDesign()
    e, f, r = design.epsa, design.foot, design.ring
    L, ts = e.length, e.seal_head_thickness
    # Parts share one edge length when given; otherwise each part uses its own default.
    epsa = mesh_epsa(e, edge_length, cache_dir)
    seal = mesh_seal_head(e, edge_length, cache_dir)
    ring = mesh_ring(r, edge_length, cache_dir) if design.n_rings else None
    foot = mesh_foot(f, edge_length, cache_dir)

    parts: list[tuple[str, TaggedMesh]] = []
    for i, (cx, cy) in enumerate(design.actuator_centres, start=1):
        parts.append((f"epsa{i}", epsa.transformed(0.0, (cx, cy, 0.0))))
        parts.append((f"seal_head{i}", seal.transformed(0.0, (cx, cy, 0.0))))
    for k, zk in enumerate(design.ring_centres_z, start=1):
        parts.append((f"ring{k}", ring.transformed(0.0, (0.0, 0.0, zk))))
    parts.append(("foot_rear", foot))
    parts.append(("foot_front", foot.transformed(0.0, (0.0, 0.0, L + ts + f.hub_thickness))))
    meshes = dict(parts)

    # interface facets: {part: {tag: [(other part, mask)]}}
    inter: list[tuple[str, str, str, np.ndarray]] = []  # (part, tag, other, mask over the tag's facets)
    for i, c in enumerate(design.actuator_centres, start=1):
        a, s = f"epsa{i}", f"seal_head{i}"
        inter.append((a, "end_bottom", "foot_rear", np.ones(len(meshes[a].facets["end_bottom"]), bool)))
        fr = meshes["foot_rear"]
        inter.append(("foot_rear", "hub_top", a, _on_disk(fr, fr.facets["hub_top"], c, e.outer_radius, 0.0)))
        inter.append((a, "end_top", s, np.ones(len(meshes[a].facets["end_top"]), bool)))
        inter.append((s, "bottom", a, np.ones(len(meshes[s].facets["bottom"]), bool)))
        inter.append((s, "top", "foot_front", np.ones(len(meshes[s].facets["top"]), bool)))
        ff = meshes["foot_front"]
        inter.append(
            ("foot_front", "hub_bottom", s, _on_disk(ff, ff.facets["hub_bottom"], c, e.outer_radius, 0.0))
        )
        for k, zk in enumerate(design.ring_centres_z, start=1):
            rg = f"ring{k}"
            tris = meshes[a].facets["outer"]
            zc = meshes[a].points[tris].mean(axis=1)[:, 2]
            inter.append((a, "outer", rg, np.abs(zc - zk) <= r.thickness / 2))
            inter.append((rg, f"hole{i}", a, np.ones(len(meshes[rg].facets[f"hole{i}"]), bool)))

    points, tets, region, facets, fibers = [], [], [], {}, []
    source: dict[str, tuple[str, str]] = {}  # robot tag -> (part, part tag)
    region_names: dict[int, str] = {}
    offset = 0
    for rid, (name, m) in enumerate(parts, start=1):
        points.append(m.points)
        tets.append(m.tets + offset)
        region.append(np.full(m.n_tets, rid))
        region_names[rid] = name
        used: dict[str, np.ndarray] = {tag: np.zeros(len(t), bool) for tag, t in m.facets.items()}
        for part, tag, other, mask in inter:
            if part != name:
                continue
            mask = mask & ~used[tag]
            used[tag] |= mask
            facets[f"interface:{name}/{other}"] = m.facets[tag][mask] + offset
            source[f"interface:{name}/{other}"] = (name, tag)
        for tag, t in m.facets.items():
            rest = t[~used[tag]]
            if len(rest):
                facets[f"{name}:{tag}"] = rest + offset
                source[f"{name}:{tag}"] = (name, tag)
        fibers.extend(m.fibers)
        offset += m.n_nodes
    curved = {}
    for new_tag, (name, tag) in source.items():
        segs = meshes[name].meta.get("curved_surfaces", {}).get(tag)
        if segs:
            curved[new_tag] = _shift_segments(segs, name, design)
    meta = {
        "kind": "robot",
        "parts": [n for n, _ in parts],
        "channel_radius_mm": design.channel_radius,
        "curved_surfaces": curved,
        "n_untagged_facets": int(sum(m.meta.get("n_untagged_facets", 0) for _, m in parts)),
    }
    return TaggedMesh(
        np.vstack(points),
        np.vstack(tets),
        np.concatenate(region),
        region_names,
        facets,
        tuple(fibers),
        design.short_hash(),
        float(edge_length or epsa.edge_length),
        meta,
    )


def _shift_segments(segs: list[list[list[float]]], name: str, design: RobotDesign) -> list[list[list[float]]]:
    """Curved-surface descriptions of a part moved to its place in the robot (for P2 node snapping)."""
    dx = dy = dz = 0.0
    if name.startswith("epsa") or name.startswith("seal_head"):
        i = int(name[-1]) - 1
        dx, dy = design.actuator_centres[i]
    elif name.startswith("ring"):
        dz = design.ring_centres_z[int(name[4:]) - 1]
    elif name == "foot_front":
        dz = design.epsa.length + design.epsa.seal_head_thickness + design.foot.hub_thickness
    return [[[s[0][0], s[0][1] + dz], [s[1][0], s[1][1] + dz], [s[2][0] + dx, s[2][1] + dy]] for s in segs]


def actuator_clearance(mesh: TaggedMesh, design: RobotDesign) -> dict:
    """Measured from the mesh: the centre channel radius (min distance of actuator nodes to the axis)
    and the largest intrusion of any actuator's nodes into another actuator's cylinder (negative: the
    actuators are apart by at least that much)."""
    R0 = design.epsa.outer_radius
    channel = np.inf
    intrusion = -np.inf
    for i, _c in enumerate(design.actuator_centres, start=1):
        nodes = np.unique(mesh.tets[mesh.region == mesh.region_id(f"epsa{i}")])
        p = mesh.points[nodes]
        channel = min(channel, float(np.hypot(p[:, 0], p[:, 1]).min()))
        for j, cj in enumerate(design.actuator_centres, start=1):
            if j == i:
                continue
            rho = np.hypot(p[:, 0] - cj[0], p[:, 1] - cj[1])
            intrusion = max(intrusion, float(R0 - rho.min()))
    return {"channel_radius_mm": channel, "max_intrusion_mm": intrusion}


def robot_surfaces(design: RobotDesign | None = None, n_theta: int = 48) -> dict:
    """Watertight surfaces of every part, placed as in the assembly ({part name: pyvista.PolyData})."""
    design = design or RobotDesign()
    e, f = design.epsa, design.foot
    body, seal = epsa_surface(e, n_theta), seal_head_surface(e, n_theta)
    out = {}
    for i, (cx, cy) in enumerate(design.actuator_centres, start=1):
        out[f"epsa{i}"] = body.translate((cx, cy, 0.0), inplace=False)
        out[f"seal_head{i}"] = seal.translate((cx, cy, 0.0), inplace=False)
    if design.n_rings:
        ring = ring_surface(design.ring)
        for k, zk in enumerate(design.ring_centres_z, start=1):
            out[f"ring{k}"] = ring.translate((0.0, 0.0, zk), inplace=False)
    foot = foot_surface(f)
    out["foot_rear"] = foot
    out["foot_front"] = foot.translate(
        (0.0, 0.0, e.length + e.seal_head_thickness + f.hub_thickness), inplace=False
    )
    return out


def mesh_robot(
    design: RobotDesign | None = None, edge_length: float | None = None, cache_dir: CacheDir = None
) -> TaggedMesh:
    """The assembled robot, see :func:`assemble_robot`."""
    return assemble_robot(design, edge_length=edge_length, cache_dir=cache_dir)


#: The mesher of each part kind of `softcrawl mesh`.
MESHERS = {"epsa": mesh_epsa, "foot": mesh_foot, "ring": mesh_ring, "robot": mesh_robot}
