"""The foot angle over Fig. 21's range (30-120 deg): one meaning, a hub thick enough for the skirt."""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcrawl.geometry.design import HUB_THICKNESS, DesignError, FootDesign
from softcrawl.geometry.foot import foot_profile, foot_segments, foot_volume
from softcrawl.geometry.foot_meshers import mesh_foot_with, quick_sectors
from softcrawl.geometry.foot_revolved import mesh_foot_revolved
from softcrawl.geometry.tagging import boundary_facets
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.foot.model import foot_model
from softcrawl.studies.foot.simulate import simulate_foot

ANGLES = (30.0, 45.0, 60.0, 90.0, 120.0)


@pytest.mark.parametrize("angle", ANGLES)
def test_every_angle_builds_with_the_tip_at_39_mm(angle):
    f = FootDesign(angle=angle)
    s = math.sin(math.radians(angle / 2))
    assert f.hub_thickness == pytest.approx(max(HUB_THICKNESS, 3.0 / s), rel=1e-12)
    assert f.tip_radius == 39.0 and f.hub_radius == 24.0
    prof, _ = foot_profile(f)
    assert prof[:, 0].max() == pytest.approx(39.0, abs=1e-12)  # the tip reaches the 78 mm diameter
    assert f.front_face_length * s == pytest.approx(39.0 - 24.0, rel=1e-12)  # the angle is the cone's
    # the back face leaves the hub side at z = -t / sin(angle / 2), never below the hub
    assert 3.0 / s <= f.hub_thickness + 1e-12


def test_the_hub_is_thickened_only_below_97_deg():
    """4 mm (the committed results' hub) while t / sin(angle / 2) <= 4: angle >= 2 asin(3 / 4)."""
    limit = 2 * math.degrees(math.asin(3.0 / 4.0))  # 97.18 deg
    assert FootDesign(angle=limit + 0.01).hub_thickness == HUB_THICKNESS
    assert FootDesign(angle=limit - 0.5).hub_thickness > HUB_THICKNESS + 1e-3
    assert FootDesign(angle=30).hub_thickness == pytest.approx(11.5911, abs=1e-4)


def test_a_given_hub_is_checked_and_a_derived_one_follows_the_angle():
    with pytest.raises(DesignError, match="hub_thickness"):
        FootDesign(angle=60, hub_thickness=4.0)
    assert FootDesign().replace(angle=60).hub_thickness == pytest.approx(6.0, rel=1e-12)
    assert FootDesign(angle=60).replace(angle=120).hub_thickness == HUB_THICKNESS
    assert FootDesign(angle=60, hub_thickness=7.0).replace(angle=90).hub_thickness == 7.0


@pytest.mark.parametrize("angle", ANGLES)
def test_every_angle_meshes_and_passes_the_mesh_checks(angle):
    design = FootDesign(angle=angle)
    n = quick_sectors(design)
    mesh = mesh_foot_revolved(design, n_theta=n)
    assert np.all(mesh.tet_volumes() > 0)
    assert mesh.quality()["min_quality"] > 0.05
    step = 2 * math.pi / n
    assert mesh.volume() == pytest.approx(foot_volume(design) * math.sin(step) / step, rel=1e-10)
    boundary, _ = boundary_facets(mesh.tets)
    tagged = np.vstack(list(mesh.facets.values()))
    assert len(tagged) == len(boundary) == len(np.unique(np.sort(tagged, axis=1), axis=0))
    assert {"front", "back", "rim", "hub_top", "hub_bottom"} <= set(mesh.facets)
    assert set(mesh.facets) == {s.tag for s in foot_segments(design)}
    rim = np.unique(mesh.facets["rim"])
    rho = np.hypot(mesh.points[rim, 0], mesh.points[rim, 1])
    assert rho.max() == pytest.approx(39.0, abs=1e-9)


def test_quick_sectors_keep_24_at_120_deg_and_grow_towards_the_axis():
    got = [quick_sectors(FootDesign(angle=a)) for a in ANGLES]
    assert got == [47, 45, 42, 34, 24]
    assert quick_sectors(FootDesign(angle=180)) == 24


def test_the_narrowest_foot_places_its_contact_quadrature_on_the_quick_mesh():
    """24 sectors do not place the 30 deg skirt's facet quadrature in its curved P2 elements (the
    quick runs of record 066 failed so); `quick_sectors` does."""
    design = FootDesign(angle=30)
    mesh = mesh_foot_with(design, "revolved", sectors=quick_sectors(design)).to_skfem(2)
    model = foot_model(mesh, solid_law(get_material("rubber-70a"), hyperelastic_only=True), design, 35.0, 0.0)
    assert len(model.contacts) == 2


@pytest.mark.slow
@pytest.mark.parametrize("angle", ANGLES)
def test_every_angle_inserts_into_the_70_mm_pipe(angle):
    """The quick insertion and drags of record 066 converge at every angle of Fig. 21."""
    r = simulate_foot(FootDesign(angle=angle), 70.0, quick=True)
    assert r.converged, r.message
    assert r.normal_force > 1.0 and r.forward.peak > 0.0 and r.backward.peak > 0.0
