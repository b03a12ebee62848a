"""The conforming swept robot mesh: parts tied by shared nodes, tags, exact curved surfaces."""

import math

import numpy as np
import pytest

from softcrawl.geometry.design import DesignError, RobotDesign
from softcrawl.geometry.robot_mesh import RobotMeshSettings, mesh_robot_swept
from softcrawl.geometry.swept import boundary_faces


@pytest.fixture(scope="module")
def mesh():
    return mesh_robot_swept(RobotDesign(), "quick")


def test_parts_share_their_interface_nodes(mesh):
    """Tied parts have no boundary between them: no boundary face lies on an actuator's outer
    cylinder inside a ring, nor on the planes where actuators meet the hubs and seal heads."""
    design = RobotDesign()
    e = design.epsa
    faces = boundary_faces(mesh.tets)
    p = mesh.points[faces]
    for cx, cy in design.actuator_centres:
        on_cyl = np.all(np.abs(np.hypot(p[..., 0] - cx, p[..., 1] - cy) - e.outer_radius) < 1e-9, axis=1)
        for zk in design.ring_centres_z:
            inside = np.all(np.abs(p[..., 2] - zk) < design.ring.thickness / 2 - 1e-9, axis=1)
            assert not np.any(on_cyl & inside)
        in_disk = np.all(np.hypot(p[..., 0] - cx, p[..., 1] - cy) < e.outer_radius - 1e-9, axis=1)
        for z in (0.0, e.length, e.length + e.seal_head_thickness):
            assert not np.any(in_disk & np.all(np.abs(p[..., 2] - z) < 1e-9, axis=1))
    assert sorted(mesh.region_names.values())[:3] == ["epsa1", "epsa2", "epsa3"]


def test_curved_p2_surfaces_are_exact(mesh):
    """With midside nodes on the cylinders, the chamber and outer areas are the exact ones to
    the P2 geometry error (observed 7.7e-5 on the quick mesh)."""
    import skfem

    e = RobotDesign().epsa
    m2 = mesh.to_skfem(order=2)
    for tag, exact in (("chamber_wall1", 2 * math.pi * e.chamber_radius * e.chamber_length),
                       ("outer2", 2 * math.pi * e.outer_radius * e.length)):  # fmt: skip
        fb = skfem.FacetBasis(m2, skfem.ElementTetP2(), facets=m2.boundaries[tag])
        assert fb.dx.sum() == pytest.approx(exact, rel=3e-4)


def test_bad_settings_are_named():
    with pytest.raises(DesignError) as err:
        RobotMeshSettings(n_around=10)
    assert err.value.parameter == "n_around"


@pytest.mark.parametrize("n_rings, d", [(1, 14.0), (5, 14.0), (3, 11.0), (3, 16.0)])
def test_every_study_design_meshes(n_rings, d):
    mesh = mesh_robot_swept(RobotDesign(n_rings=n_rings, d=d), "quick")
    assert mesh.quality()["n_inverted"] == 0
    assert sum(name.startswith("ring") for name in mesh.region_names.values()) == n_rings
