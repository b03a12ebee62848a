"""Meshes of the foot, the ring and the assembled robot (slow: several pytetwild runs)."""

import numpy as np
import pytest

from softcrawl.geometry.assembly import actuator_clearance, mesh_robot
from softcrawl.geometry.design import FootDesign, RingDesign, RobotDesign
from softcrawl.geometry.foot import foot_segments, foot_volume
from softcrawl.geometry.ring import ring_volume
from softcrawl.geometry.tagging import boundary_facets
from softcrawl.geometry.tetwild import mesh_foot, mesh_ring

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def cache_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("parts_cache")


def _check_common(mesh):
    assert (mesh.tet_volumes() > 0).all()
    assert mesh.meta["n_untagged_facets"] == 0
    tris, _ = boundary_facets(mesh.tets)
    assert sum(len(f) for f in mesh.facets.values()) == len(tris)
    assert all(len(f) > 0 for f in mesh.facets.values())


def test_foot_mesh(cache_dir):
    design = FootDesign()
    mesh = mesh_foot(design, cache_dir=cache_dir)
    _check_common(mesh)
    assert set(mesh.facets) == {"hub_top", "hub_bottom", "hub_side", "bore", "front", "back", "rim"}
    assert mesh.volume() == pytest.approx(foot_volume(design), rel=0.01)
    exact = {}
    for s in foot_segments(design):
        exact[s.tag] = exact.get(s.tag, 0.0) + s.area()
    for tag in ("front", "back", "rim", "hub_bottom"):
        assert mesh.area(tag) == pytest.approx(exact[tag], rel=0.03), tag


def test_ring_mesh(cache_dir):
    design = RingDesign()
    mesh = mesh_ring(design, cache_dir=cache_dir)
    _check_common(mesh)
    assert set(mesh.facets) == {"top", "bottom", "outer", "bore", "hole1", "hole2", "hole3"}
    assert mesh.volume() == pytest.approx(ring_volume(design), rel=0.01)
    plate = np.pi * (design.outer_radius**2 - 3 * design.hole_radius**2 - design.bore_radius**2)
    assert mesh.area("top") == pytest.approx(plate, rel=0.02)
    assert mesh.area("hole1") == pytest.approx(2 * np.pi * design.hole_radius * design.thickness, rel=0.02)


def test_robot_mesh(cache_dir):
    design = RobotDesign()
    mesh = mesh_robot(design, cache_dir=cache_dir)
    _check_common(mesh)
    names = set(mesh.region_names.values())
    assert names == {
        "epsa1",
        "epsa2",
        "epsa3",
        "seal_head1",
        "seal_head2",
        "seal_head3",
        "ring1",
        "ring2",
        "ring3",
        "foot_rear",
        "foot_front",
    }
    for i in (1, 2, 3):
        assert mesh.volume(f"epsa{i}") == pytest.approx(design.epsa.body_volume, rel=0.01)
        for tag in (
            f"epsa{i}:chamber_wall",
            f"epsa{i}:chamber_ends",
            f"interface:epsa{i}/foot_rear",
            f"interface:foot_rear/epsa{i}",
            f"interface:epsa{i}/seal_head{i}",
            f"interface:seal_head{i}/foot_front",
            f"interface:foot_front/seal_head{i}",
            f"interface:epsa{i}/ring2",
            f"interface:ring2/epsa{i}",
        ):
            assert len(mesh.facets[tag]) > 0, tag
    # tie partners cover the same area on both sides
    assert mesh.area("interface:epsa1/ring1") == pytest.approx(mesh.area("interface:ring1/epsa1"), rel=0.03)
    clearance = actuator_clearance(mesh, design)
    assert clearance["max_intrusion_mm"] < 0  # no actuator node inside another actuator
    assert clearance["channel_radius_mm"] == pytest.approx(design.d - design.epsa.outer_radius, abs=0.05)
    assert len(mesh.fibers) == 6
    m = mesh.to_skfem(1)
    assert set(m.subdomains) == names
