"""The revolved foot mesh (`geometry.foot_revolved`): exact volumes, conforming tets, the foot's tags."""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcrawl.geometry.design import DesignError, FootDesign
from softcrawl.geometry.foot import foot_segments, foot_volume
from softcrawl.geometry.foot_revolved import foot_section, mesh_foot_revolved
from softcrawl.geometry.tagging import TET_FACES, boundary_facets


def _chord_factor(n_theta: int) -> float:
    """A section swept through n chords of angle D encloses sin(D) / D of the solid of revolution."""
    step = 2 * math.pi / n_theta
    return math.sin(step) / step


@pytest.mark.parametrize(
    ("n_theta", "params"),
    [
        (24, {}),
        (48, {}),
        (24, {"n_grooves": 0}),
        (24, {"angle": 90.0, "hub_thickness": 4.5}),
        (24, {"angle": 180.0}),
        (24, {"groove_height": 0.4, "n_grooves": 3, "skirt_thickness": 2.0}),
    ],
)
def test_volume_is_the_chordal_solid_of_revolution(n_theta, params):
    design = FootDesign(**params)
    mesh = mesh_foot_revolved(design, n_theta=n_theta)
    assert np.all(mesh.tet_volumes() > 0)
    assert mesh.quality()["min_quality"] > 0.05  # no slivers (the default mesh: 0.12)
    # exact (not a discretisation error): each prism is {(rho cos(D/2), y, z): |y| <= rho sin(D/2)}
    assert mesh.volume() == pytest.approx(foot_volume(design) * _chord_factor(n_theta), rel=1e-10)


def test_planar_tags_have_the_chordal_area_and_every_tag_is_present():
    design = FootDesign()
    mesh = mesh_foot_revolved(design, n_theta=36)
    exact = {}
    for s in foot_segments(design):
        exact[s.tag] = exact.get(s.tag, 0.0) + s.area()
    assert set(mesh.facets) == set(exact)
    for tag in ("hub_top", "hub_bottom"):  # annuli: polygon area = sin(D)/D x the circle's
        assert mesh.area(tag) == pytest.approx(exact[tag] * _chord_factor(36), rel=1e-10)
    for tag, area in exact.items():  # cones and cylinders: within the chordal error
        assert mesh.area(tag) == pytest.approx(area, rel=2e-2)


def test_the_mesh_conforms_and_every_boundary_facet_has_one_tag():
    mesh = mesh_foot_revolved(FootDesign(), n_theta=24)
    faces = np.sort(mesh.tets[:, TET_FACES].reshape(-1, 3), axis=1)
    _, counts = np.unique(faces, axis=0, return_counts=True)
    assert counts.max() == 2  # no face is shared by three tets (no overlap)
    boundary, _ = boundary_facets(mesh.tets)
    tagged = np.vstack(list(mesh.facets.values()))
    assert len(tagged) == len(boundary)
    assert len(np.unique(np.sort(tagged, axis=1), axis=0)) == len(boundary)


@pytest.mark.parametrize("layers", [2, 3, 4, 5, 6])
def test_cells_through_the_skirt(layers):
    design = FootDesign()
    xy, tris = foot_section(design, thickness_layers=layers)
    # nodes on the rim (the skirt's end cross-section, a land): exactly layers + 1
    a = math.radians(design.angle / 2)
    u = np.array([math.sin(a), -math.cos(a)])
    tip = np.array([design.hub_radius, 0.0]) + design.front_face_length * u
    on_rim = np.abs((xy - tip) @ u) < 1e-9
    assert on_rim.sum() == layers + 1
    mesh = mesh_foot_revolved(design, n_theta=24, thickness_layers=layers)
    assert len(mesh.facets["rim"]) == 2 * layers * 24


@pytest.mark.parametrize(("sectors", "layers"), [(96, 4), (128, 6)])
def test_the_refined_mesh_has_the_asked_sectors_and_cells(sectors, layers):
    """Count them on the mesh itself: distinct vertex angles, and distinct depths of the rim's
    vertices below the front face."""
    design = FootDesign()
    mesh = mesh_foot_revolved(design, n_theta=sectors, thickness_layers=layers)
    p = mesh.points
    off_axis = np.hypot(p[:, 0], p[:, 1]) > 1e-6
    angles = np.round(
        np.mod(np.arctan2(p[off_axis, 1], p[off_axis, 0]), 2 * np.pi) / (2 * np.pi) * sectors, 6
    )
    assert len(np.unique(angles)) == sectors
    assert np.allclose(angles, np.round(angles))
    rim = np.unique(mesh.facets["rim"])
    rz = np.column_stack([np.hypot(p[rim, 0], p[rim, 1]), p[rim, 2]])
    a = math.radians(design.angle / 2)
    n = np.array([math.cos(a), math.sin(a)])
    depth = -(rz - np.array([design.hub_radius, 0.0])) @ n
    assert len(np.unique(np.round(depth, 9))) == layers + 1  # layers cells through the skirt


def test_a_grooved_skirt_needs_two_cells():
    with pytest.raises(DesignError, match="thickness_layers"):
        mesh_foot_revolved(FootDesign(), n_theta=24, thickness_layers=1)


def test_grooves_are_cut_to_their_depth():
    design = FootDesign(groove_height=1.5)
    mesh = mesh_foot_revolved(design, n_theta=24)
    a = math.radians(design.angle / 2)
    n = np.array([math.cos(a), math.sin(a)])
    back = mesh.facets["back"]
    rz = np.column_stack([np.hypot(mesh.points[:, 0], mesh.points[:, 1]), mesh.points[:, 2]])
    depth = (-(rz - np.array([design.hub_radius, 0.0])) @ n)[back]  # d from the front face's line
    t, h = design.skirt_thickness, design.groove_height
    assert depth.min() == pytest.approx(t - h, abs=1e-9)
    assert depth.max() == pytest.approx(t, abs=1e-9)
    bottoms = np.all(np.abs(depth - (t - h)) < 1e-9, axis=1)  # facets on the groove bottoms
    lands = np.all(np.abs(depth - t) < 1e-9, axis=1)
    assert bottoms.sum() > 0 and lands.sum() > 0


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"n_theta": 8}, "n_theta"),
        ({"thickness_layers": 0}, "thickness_layers"),
        ({"cell_size": -1.0}, "cell_size"),
    ],
)
def test_bad_settings_name_the_parameter(kwargs, name):
    with pytest.raises(DesignError, match=name):
        mesh_foot_revolved(FootDesign(), **kwargs)


@pytest.mark.parametrize("copies", [2, 4, 6])
def test_a_wedge_is_the_whole_mesh_cut(copies):
    """The wedge's nodes are the whole mesh's first ones, its volume and every tag's area the
    whole's / copies, and its cuts lie on theta = 0 and theta = 2 pi / copies."""
    whole = mesh_foot_revolved(FootDesign(), n_theta=24)
    wedge = mesh_foot_revolved(FootDesign(), n_theta=24, copies=copies)
    assert np.array_equal(wedge.points, whole.points[: len(wedge.points)])

    def volume(m):
        p = m.points[m.tets]
        return (
            np.abs(
                np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
            ).sum()
            / 6
        )

    def area(m, tag):
        p = m.points[m.facets[tag]]
        return np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1).sum() / 2

    assert volume(wedge) * copies == pytest.approx(volume(whole), rel=1e-12)
    for tag in whole.facets:
        assert area(wedge, tag) * copies == pytest.approx(area(whole, tag), rel=1e-12)
    angle = 2 * math.pi / copies
    start, end = wedge.points[wedge.facets["cut_start"]], wedge.points[wedge.facets["cut_end"]]
    assert np.abs(start[..., 1]).max() < 1e-9
    assert np.abs(end @ np.array([-math.sin(angle), math.cos(angle), 0.0])).max() < 1e-9
    assert area(wedge, "cut_start") == pytest.approx(area(wedge, "cut_end"), rel=1e-12)
    assert wedge.meta["copies"] == copies


@pytest.mark.parametrize("copies", [0, 5, 24, 2.0])
def test_a_wedge_must_divide_the_sectors(copies):
    with pytest.raises(DesignError, match="copies"):
        mesh_foot_revolved(FootDesign(), n_theta=24, copies=copies)
