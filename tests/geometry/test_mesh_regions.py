"""Every region of every mesh a study uses (quick, default, fine), its extent and its volume against
the design (issue 32: a region built with the wrong extent on the default mesh went unseen while
the tests used only the quick mesh).

The expectations come from the design objects, not from hard-coded dimensions, so they hold for a
changed default design. Volumes are exact up to the polygons the meshes are built on:

* swept ePSA and the robot's actuators and seal heads: the cross-section nodes lie on the circles
  rho = r0 and rho = R0 with n sectors, so every annulus and disk is an inscribed n-gon and the
  volume is f = n sin(2 pi / n) / (2 pi) times the exact one (to round-off);
* the robot's rings and hubs: the web's axis-centred circles are sampled at about the web size, so
  their polygons fall short of the circles by at most (2 pi / m)^2 / 6 (< 1 % for every preset);
* the revolved foot: every section vertex revolved on chords of n sectors, volume sin D / D times
  the exact Pappus volume (`geometry.foot.foot_volume`), D = 2 pi / n.
"""

import math

import numpy as np
import pytest

from softcrawl.geometry.design import EPSADesign, FootDesign, RobotDesign
from softcrawl.geometry.foot import foot_profile, foot_volume
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.geometry.foot_revolved import N_THETA
from softcrawl.geometry.robot_mesh import MESH_PRESETS as ROBOT_PRESETS
from softcrawl.geometry.robot_mesh import mesh_robot_swept, stiff_outline
from softcrawl.geometry.swept import mesh_epsa_swept
from softcrawl.studies.crawl.mesh import QUICK_SECTORS
from softcrawl.studies.epsa.model import MESH_PRESETS as EPSA_PRESETS
from softcrawl.studies.epsa.model import MeshSettings
from softcrawl.studies.foot.simulate import QUICK as FOOT_QUICK

#: Polygon of the web's axis-centred circles against the circles (module docstring).
WEB_TOL = 0.01
EXACT = 1e-9


def polygon_factor(n: int) -> float:
    """Area of the n-gon inscribed in a circle over the circle's area."""
    return n * math.sin(2 * math.pi / n) / (2 * math.pi)


def region_points(mesh, name: str) -> np.ndarray:
    return mesh.points[np.unique(mesh.tets[mesh.region == mesh.region_id(name)])]


# ------------------------------------------------------------------------------------------- ePSA
#: The ePSA meshes of the studies: the presets, and the convergence study's finest size (h = 10 / 5 /
#: 3.33 mm, `softcrawl epsa --convergence`; 10 and 5 mm are the quick and default presets).
EPSA_MESHES = {
    "quick": lambda d: EPSA_PRESETS["quick"],
    "default": lambda d: EPSA_PRESETS["default"],
    "fine": lambda d: MeshSettings.from_size(10.0 / 3.0, d),
}


@pytest.mark.parametrize("size", list(EPSA_MESHES))
def test_epsa_regions_extent_and_volume(size):
    design = EPSADesign()
    s = EPSA_MESHES[size](design)
    mesh = mesh_epsa_swept(
        design, n_around=s.n_around, n_radial=s.n_radial, axial_size=s.axial_size, seal_head=True
    )
    assert sorted(mesh.region_names.values()) == ["epsa", "seal_head"]
    assert np.isin(mesh.region, list(mesh.region_names)).all()
    f = polygon_factor(s.n_around)
    L, R0, ts = design.length, design.outer_radius, design.seal_head_thickness
    body, head = region_points(mesh, "epsa"), region_points(mesh, "seal_head")
    assert body[:, 2].min() == pytest.approx(0.0, abs=EXACT) and body[:, 2].max() == pytest.approx(L)
    assert head[:, 2].min() == pytest.approx(L) and head[:, 2].max() == pytest.approx(L + ts)
    assert np.hypot(body[:, 0], body[:, 1]).max() == pytest.approx(R0)
    # the chamber is empty between the end caps: no body tet has its centroid inside it
    rid = mesh.region_id("epsa")
    cen = mesh.points[mesh.tets[mesh.region == rid]].mean(axis=1)
    inside = (np.hypot(cen[:, 0], cen[:, 1]) < design.chamber_radius * math.cos(math.pi / s.n_around)) & (
        np.abs(cen[:, 2] - L / 2) < design.chamber_length / 2
    )
    assert not inside.any()
    assert mesh.volume("epsa") == pytest.approx(f * design.body_volume, rel=EXACT)
    assert mesh.volume("seal_head") == pytest.approx(f * math.pi * R0**2 * ts, rel=EXACT)


# ------------------------------------------------------------------------------------------ robot
@pytest.fixture(scope="module", params=list(ROBOT_PRESETS))
def robot(request):
    design = RobotDesign()
    return request.param, design, mesh_robot_swept(design, request.param)


def test_robot_regions_are_the_design_parts(robot):
    _, design, mesh = robot
    parts = ["foot_rear", "foot_front"] + [f"{p}{i}" for p in ("epsa", "seal_head") for i in (1, 2, 3)]
    parts += [f"ring{k}" for k in range(1, design.n_rings + 1)]
    assert sorted(mesh.region_names.values()) == sorted(parts)
    assert all((mesh.region == rid).any() for rid in mesh.region_names)
    assert np.isin(mesh.region, list(mesh.region_names)).all()


def test_robot_actuators_and_seal_heads_extent_and_volume(robot):
    size, design, mesh = robot
    e = design.epsa
    f = polygon_factor(ROBOT_PRESETS[size].n_around)
    L, R0, ts = e.length, e.outer_radius, e.seal_head_thickness
    for i, (cx, cy) in enumerate(design.actuator_centres, start=1):
        for name, z0, z1, volume in (
            (f"epsa{i}", 0.0, L, f * e.body_volume),
            (f"seal_head{i}", L, L + ts, f * math.pi * R0**2 * ts),
        ):
            p = region_points(mesh, name)
            assert p[:, 2].min() == pytest.approx(z0, abs=EXACT), name
            assert p[:, 2].max() == pytest.approx(z1, abs=EXACT), name
            assert np.hypot(p[:, 0] - cx, p[:, 1] - cy).max() == pytest.approx(R0), name
            assert mesh.volume(name) == pytest.approx(volume, rel=EXACT), name


def test_robot_rings_and_hubs_extent_and_volume(robot):
    size, design, mesh = robot
    e, t_hub, t_r = design.epsa, design.foot.hub_thickness, design.ring.thickness
    bore, outer = stiff_outline(design)
    f = polygon_factor(ROBOT_PRESETS[size].n_around)
    annulus = math.pi * (outer**2 - bore**2)
    top = e.length + e.seal_head_thickness
    spans = {"foot_rear": (-t_hub, 0.0, annulus), "foot_front": (top, top + t_hub, annulus)}
    holes = annulus - 3 * f * math.pi * e.outer_radius**2  # the actuators pass through the rings
    for k, zk in enumerate(design.ring_centres_z, start=1):
        spans[f"ring{k}"] = (zk - t_r / 2, zk + t_r / 2, holes)
    for name, (z0, z1, area) in spans.items():
        p = region_points(mesh, name)
        rho = np.hypot(p[:, 0], p[:, 1])
        assert p[:, 2].min() == pytest.approx(z0, abs=EXACT), name
        assert p[:, 2].max() == pytest.approx(z1, abs=EXACT), name
        assert rho.min() == pytest.approx(bore) and rho.max() == pytest.approx(outer), name
        assert mesh.volume(name) == pytest.approx((z1 - z0) * area, rel=WEB_TOL), name
    # the parts fill the robot: total = sum of the parts (no tet in two regions, none in none)
    assert sum(mesh.volume(n) for n in mesh.region_names.values()) == pytest.approx(mesh.volume(), rel=EXACT)


# ------------------------------------------------------------------------------------------- foot
#: The revolved foot meshes of the foot and crawl studies: their quick sectors and the default.
FOOT_SECTORS = sorted({FOOT_QUICK["sectors"], QUICK_SECTORS, N_THETA})


@pytest.mark.parametrize("sectors", FOOT_SECTORS)
def test_revolved_foot_region_extent_and_volume(sectors):
    design = FootDesign()
    mesh = mesh_foot_with(design, "revolved", sectors=sectors)
    assert list(mesh.region_names.values()) == ["foot"] and (mesh.region == mesh.region_id("foot")).all()
    prof, _ = foot_profile(design)
    p = region_points(mesh, "foot")
    rho = np.hypot(p[:, 0], p[:, 1])
    assert p[:, 2].min() == pytest.approx(prof[:, 1].min(), abs=EXACT)
    assert p[:, 2].max() == pytest.approx(prof[:, 1].max(), abs=EXACT)
    assert rho.min() == pytest.approx(prof[:, 0].min(), abs=EXACT)
    assert rho.max() == pytest.approx(prof[:, 0].max(), abs=EXACT)
    d = 2 * math.pi / sectors
    assert mesh.volume("foot") == pytest.approx(math.sin(d) / d * foot_volume(design), rel=1e-6)
