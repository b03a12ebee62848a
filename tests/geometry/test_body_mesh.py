"""The one-body mesh: the swept robot and both grooved skirts, conforming on the hub-skirt interface,
with the reduced crawl's foot geometry and the robot's three-fold symmetry."""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from softcrawl.geometry.body_mesh import (
    BodyMeshSettings,
    hub_tops,
    mesh_body,
    rotation_defect,
    settings_for,
    skirt_section,
    split_prisms,
)
from softcrawl.geometry.design import DesignError, FootDesign, RobotDesign
from softcrawl.geometry.foot_revolved import mesh_foot_revolved
from softcrawl.geometry.robot_mesh import MESH_PRESETS
from softcrawl.geometry.tagging import TET_FACES

DESIGN = RobotDesign()


@pytest.fixture(scope="module")
def quick():
    return mesh_body(DESIGN, "quick")


def _faces(tets):
    """Every face of the tets (sorted vertices) with the number of cells that hold it."""
    key = np.sort(tets[:, TET_FACES].reshape(-1, 3), axis=1)
    faces, counts = np.unique(key, axis=0, return_counts=True)
    return faces, counts


def test_no_duplicated_nodes(quick):
    pairs = cKDTree(quick.points).query_pairs(1e-6)
    assert not pairs  # a skirt root node left unmerged would sit on a hub node


def test_every_face_is_held_by_one_or_two_cells(quick):
    _, counts = _faces(quick.tets)
    assert counts.min() == 1 and counts.max() == 2


def test_the_hub_skirt_interface_is_shared_face_by_face(quick):
    """Every face on a hub side between the skirt root's levels is held by exactly two cells, one
    of the skirt (centroid beyond the hub radius) and one of the hub; their number is that of the
    root's quadrilaterals, two triangles each, in every sector of both feet."""
    f = DESIGN.foot
    settings = settings_for(f, "quick")
    faces, counts = _faces(quick.tets)
    p = quick.points[faces]
    on_side = np.all(np.abs(np.hypot(p[..., 0], p[..., 1]) - f.hub_radius) < 1e-9, axis=1)
    depth = f.skirt_thickness / f.sin_half_angle
    _, _, root = skirt_section(DESIGN, settings)
    interface = np.zeros(len(faces), bool)
    for top in hub_tops(DESIGN).values():
        interface |= on_side & np.all((p[..., 2] >= top - depth - 1e-9) & (p[..., 2] <= top + 1e-9), axis=1)
    assert interface.sum() == 2 * settings.sectors * (len(root) - 1) * 2
    assert np.all(counts[interface] == 2)
    # the two cells of each interface face: one skirt, one hub
    key = np.sort(quick.tets[:, TET_FACES].reshape(-1, 3), axis=1)
    owner = np.repeat(np.arange(len(quick.tets)), 4)
    centroid_rho = np.hypot(*quick.points[quick.tets].mean(axis=1)[:, :2].T)
    lookup = {tuple(k): [] for k in faces[interface]}
    for k, o in zip(map(tuple, key), owner):
        if k in lookup:
            lookup[k].append(centroid_rho[o] > f.hub_radius)
    assert all(sorted(v) == [False, True] for v in lookup.values())


def test_skirts_are_the_reduced_crawls_feet(quick):
    """The rear skirt's vertices are the revolved foot's (the reduced crawl's feet, same FootDesign,
    same sectors, turned by half a sector), and its wall faces have the same areas."""
    f = DESIGN.foot
    n = settings_for(f, "quick").sectors
    foot = mesh_foot_revolved(f, n_theta=n).transformed(rotation_deg=180.0 / n)
    tol = 1e-9 * f.tip_radius
    mine = quick.points[(np.hypot(quick.points[:, 0], quick.points[:, 1]) > f.hub_radius + tol)
                        & (quick.points[:, 2] < 1.0)]  # fmt: skip
    theirs = foot.points[np.hypot(foot.points[:, 0], foot.points[:, 1]) > f.hub_radius + tol]
    assert len(mine) == len(theirs)
    assert cKDTree(theirs).query(mine)[0].max() < 1e-9
    for tag in ("front", "rim", "back"):
        assert quick.area(f"rear:{tag}") == pytest.approx(foot.area(tag), rel=1e-12)
        assert quick.area(f"front:{tag}") == pytest.approx(foot.area(tag), rel=1e-12)


def test_three_fold_symmetry_of_the_p2_nodes(quick):
    """Every P2 node (vertex or edge midpoint: the connectivity too) has its 120 and 240 deg images
    among the nodes (observed 7e-14 mm)."""
    nodes = quick.to_skfem(2).doflocs.T
    assert rotation_defect(nodes, 120.0) < 1e-9
    assert rotation_defect(nodes, 240.0) < 1e-9
    assert rotation_defect(nodes, 90.0) > 0.1  # the measure sees an asymmetry when there is one


def test_regions_and_tags(quick):
    names = set(quick.region_names.values())
    assert {"foot_rear", "foot_front", "epsa1", "ring3", "seal_head2"} <= names
    for foot in ("rear", "front"):
        for tag in ("front", "rim", "back"):
            assert len(quick.facets[f"{foot}:{tag}"]) > 0
    assert quick.volume("epsa1") == pytest.approx(quick.volume("epsa2"), rel=1e-12)
    assert quick.volume("foot_rear") == pytest.approx(quick.volume("foot_front"), rel=1e-12)


def test_prism_split_cuts_a_shared_face_alike():
    """Two prisms sharing a quadrilateral, numbered differently, cut it along the same diagonal,
    and each prism's three tets fill it (volume)."""
    pts = np.array(
        [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 0], [1, 1, 1]], float
    )
    prisms = np.array([[0, 1, 2, 3, 4, 5], [1, 6, 2, 4, 7, 5]])
    for rank in (np.arange(8), np.array([7, 3, 5, 0, 6, 2, 1, 4])):
        tets = split_prisms(prisms, rank)
        a, b, c, d = (pts[tets[:, i]] for i in range(4))
        v = np.abs(np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)) / 6
        assert v.sum() == pytest.approx(1.0) and v.min() > 0
        faces, counts = _faces(tets)
        shared = np.all(np.isin(faces, [1, 2, 4, 5]), axis=1)  # the quadrilateral (1, 2, 5, 4)
        assert shared.sum() == 2 and np.all(counts[shared] == 2)  # two triangles, each held twice


def test_settings_refuse_bad_input():
    with pytest.raises(DesignError, match="sectors"):
        BodyMeshSettings(robot=MESH_PRESETS["quick"], sectors=40)
    with pytest.raises(DesignError, match="mesh"):
        mesh_body(DESIGN, "fine")


def test_narrow_feet_get_the_reduced_crawls_sectors():
    assert settings_for(FootDesign(angle=30), "quick").sectors == 3 * math.ceil(47 / 3)
    assert settings_for(FootDesign(), "quick").sectors == 36
