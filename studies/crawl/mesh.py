"""Two grooved feet in one mesh for the crawl (`studies.crawl.model`).

Each foot is the `geometry.foot` mesh (hub top at z = 0, hub below it down to -hub_thickness,
skirt leaning back towards -z). The rear foot stays where it is; the front foot is shifted by
`separation` along +z (the robot's hub-to-hub distance: ePSA length + seal head + hub). A foot
marked `mirrored` is reflected z -> -z - hub_thickness about its own hub mid-plane, so that its hub
keeps its place and its skirt leans forward (+z); reflected tets and facets are reordered to stay
positively and outward oriented, and the curved-surface descriptions (for the P2 nodes' snapping)
are reflected with them.

Meshers (`geometry.foot_meshers`). "revolved" (the default): `geometry.foot_revolved`, the foot study's
structured mesh, every vertex and P2 midside node on the exact surfaces, refined by its sectors
and its cells through the skirt; "tetwild": `geometry.tetwild.mesh_foot` (pytetwild, refined by
its edge length), the mesh of the crawl results computed before the revolved mesh existed
(docs/decisions/055-crawl-revolved.md says why the crawl moved).

Tags: "rear:TAG" and "front:TAG" for every foot tag (hub_top, hub_bottom, front, back, rim, ...).
`attach_tag(foot, mirrored)` names the hub face the actuators are glued to: the rear foot's face
looking forward, the front foot's face looking back.
"""

from __future__ import annotations

import numpy as np

from softcrawl.geometry.design import RobotDesign
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.geometry.tagged_mesh import TaggedMesh

FEET = ("rear", "front")


def _placed(foot: TaggedMesh, dz: float, mirrored: bool, hub_thickness: float):
    p = foot.points.copy()
    tets, facets = foot.tets.copy(), {k: v.copy() for k, v in foot.facets.items()}
    sign, shift = (-1.0, -hub_thickness + dz) if mirrored else (1.0, dz)
    p[:, 2] = sign * p[:, 2] + shift
    if mirrored:
        tets[:, [0, 1]] = tets[:, [1, 0]]
        facets = {k: v[:, [0, 2, 1]] for k, v in facets.items()}
    curved = {
        tag: [
            [[s[0][0], sign * s[0][1] + shift], [s[1][0], sign * s[1][1] + shift], list(s[2])] for s in segs
        ]
        for tag, segs in foot.meta.get("curved_surfaces", {}).items()
    }
    return p, tets, facets, curved


def attach_tag(foot: str, mirrored: bool) -> str:
    """The hub face of `foot` ("rear"/"front") that the actuators act on."""
    looks_forward = (foot == "rear") != mirrored
    return f"{foot}:{'hub_top' if looks_forward else 'hub_bottom'}"


def two_feet(
    foot: TaggedMesh, separation: float, hub_thickness: float, mirrored: tuple[bool, bool] = (False, False)
) -> TaggedMesh:
    """The rear foot at the origin and the front one `separation` ahead (module docstring)."""
    points, tets, region, facets, curved = [], [], [], {}, {}
    offset = 0
    for rid, (name, dz, mirror) in enumerate(zip(FEET, (0.0, separation), mirrored), start=1):
        p, t, f, c = _placed(foot, dz, mirror, hub_thickness)
        points.append(p)
        tets.append(t + offset)
        region.append(np.full(len(t), rid))
        facets |= {f"{name}:{tag}": tris + offset for tag, tris in f.items()}
        curved |= {f"{name}:{tag}": segs for tag, segs in c.items()}
        offset += len(p)
    return TaggedMesh(
        np.vstack(points),
        np.vstack(tets),
        np.concatenate(region),
        {1: "foot_rear", 2: "foot_front"},
        facets,
        (),
        foot.design_hash,
        foot.edge_length,
        {"kind": "two_feet", "curved_surfaces": curved, "mirrored": list(mirrored)},
    )


#: Included skirt angles (deg) a crawl takes (`softcrawl crawl --foot-angle`): Fig. 21's range, over
#: which `FootDesign` builds with its derived hub (docs/decisions/066-body-geometry.md) and the tip
#: stays at 39 mm, so every foot touches the pipes of Table 2.
MIN_FOOT_ANGLE, MAX_FOOT_ANGLE = 30.0, 120.0

#: Sectors of the revolved feet in the --quick crawl and crawl study (82k DOFs against 164k at the
#: default 48); their stride against the default mesh's: docs/decisions/055-crawl-revolved.md.
QUICK_SECTORS = 24


def separation(foot_design=None) -> float:
    """The hub-to-hub distance of the Table 1 robot (`geometry.design`) with the feet `foot_design`
    (None: the paper's): ePSA length + seal head + the foot's hub thickness (a narrower skirt's
    thicker hub, record 066, moves the front foot forward)."""
    robot = RobotDesign() if foot_design is None else RobotDesign(foot=foot_design)
    return robot.epsa.length + robot.epsa.seal_head_thickness + robot.foot.hub_thickness


def crawl_mesh(mirrored: tuple[bool, bool] = (False, False), cache_dir=None, foot=None, **mesh_options):
    """(foot design, skfem MeshTet2 of the two feet) of the Table 1 robot (`geometry.design`) with
    the feet `foot` (a `FootDesign`, checked against the robot; None: the paper's); `mesh_options`
    go to `geometry.foot_meshers.mesh_foot_with` (mesher, sectors, thickness_layers, edge_length),
    whose mesh cache is keyed by the foot design's hash."""
    robot = RobotDesign() if foot is None else RobotDesign(foot=foot)
    mesh = mesh_foot_with(robot.foot, cache_dir=cache_dir, **mesh_options)
    both = two_feet(mesh, separation(robot.foot), robot.foot.hub_thickness, mirrored)
    return robot.foot, both.to_skfem(2)
