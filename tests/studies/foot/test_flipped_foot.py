"""The flipped foot of the backward crawl (`studies.foot.flip`, docs/decisions/067-flipped-foot.md):
the flip's kinematics against its closed form, the FE fold's geometry, and the grooved face on the
wall of a 70 mm pipe."""

import math

import numpy as np
import pytest

from softcrawl.geometry.design import DesignError, FootDesign
from softcrawl.geometry.foot import foot_profile
from softcrawl.studies.foot.flip import fold_angle_into, hinge, rotated


def _rotate_profile(design, phi):
    prof, tags = foot_profile(design)
    pts = np.vstack([prof[:, 0], np.zeros(len(prof)), prof[:, 1]])
    d = rotated(pts, design, phi)
    return (pts + d)[[0, 2]].T, tags


def _mean_normal(poly, tags, tag):
    """Area-weighted mean radial component of the outward normals of the profile's edges `tag`
    (the profile is counter-clockwise, so the outward normal of edge p -> q is (dz, -drho))."""
    n = len(poly)
    total, radial = 0.0, 0.0
    for i, t in enumerate(tags):
        if t != tag:
            continue
        p, q = poly[i], poly[(i + 1) % n]
        e = q - p
        length = math.hypot(*e)
        rho = 0.5 * (p[0] + q[0])
        total += length * rho
        radial += e[1] * rho
    return radial / total


@pytest.mark.parametrize("angle", [120.0, 150.0])
def test_the_flip_mirrors_the_mid_surface_and_turns_the_grooved_face_out(angle):
    """A rigid rotation of the section by Delta = pi - angle about the hinge: the mid-surface line
    keeps its radii (no membrane hoop strain), a face point at e from it moves from
    rho_m - e cos(alpha) to rho_m + e cos(alpha) (z: from -e sin(alpha) to -e sin(alpha) below
    the mirrored line), and the grooved face's outward normal turns
    from the axis (radial component -cos(alpha) on its lands) to the wall (+cos(alpha))."""
    design = FootDesign(angle=angle)
    a = math.radians(angle / 2)
    H, delta = hinge(design)
    assert delta == pytest.approx(math.pi - 2 * a)
    t = design.skirt_thickness
    u = np.array([math.sin(a), -math.cos(a)])
    n = np.array([math.cos(a), math.sin(a)])
    for s in (2.0, 8.0, 15.0):
        for e in (-t / 2, 0.0, t / 2):
            p = H + s * u + e * (-n)  # e > 0 towards the back face
            d = rotated(np.array([[p[0]], [0.0], [p[1]]]), design, delta)
            rho1, z1 = p[0] + d[0, 0], p[1] + d[2, 0]
            assert rho1 == pytest.approx(H[0] + s * math.sin(a) + e * math.cos(a), abs=1e-12)
            assert z1 - H[1] == pytest.approx(s * math.cos(a) - e * math.sin(a), abs=1e-12)
    moulded, tags = _rotate_profile(design, 0.0)
    assert _mean_normal(moulded, tags, "back") < 0 < _mean_normal(moulded, tags, "front")
    # only the skirt turns (the hub's points move too under the rigid map, so take the skirt's faces)
    flipped, _ = _rotate_profile(design, delta)
    assert _mean_normal(flipped, tags, "front") < 0 < _mean_normal(flipped, tags, "back")


def test_the_fold_into_a_pipe_brings_the_rim_inside_the_wall():
    """The flip alone leaves the tip at the 39 mm tip radius; a 70 mm pipe needs a larger fold,
    whose rigidly rotated rim lies inside 34.5 mm; no fold turns the skirt past the axis."""
    design = FootDesign()
    prof, tags = foot_profile(design)
    rim = np.array([prof[i] for i, t in enumerate(tags) if t == "rim"] + [prof[tags.index("rim") + 1]])
    theta = np.linspace(0, 2 * np.pi, 7)
    pts = np.vstack(
        [np.outer(rim[:, 0], np.cos(theta)).ravel(), np.outer(rim[:, 0], np.sin(theta)).ravel(),
         np.repeat(rim[:, 1], len(theta))]
    )  # fmt: skip
    _, delta = hinge(design)
    assert fold_angle_into(design, pts, design.tip_radius + 1e-9) == delta
    phi = fold_angle_into(design, pts, 34.5)
    assert delta < phi < math.pi - math.radians(design.angle / 2)
    moved = pts + rotated(pts, design, phi)
    assert np.hypot(moved[0], moved[1]).max() <= 34.5 + 1e-9
    with pytest.raises(ValueError, match="cannot be folded"):
        fold_angle_into(design, pts, 20.0)


@pytest.mark.parametrize("angle", [120.0, 150.0])
def test_the_smallest_pipe_of_a_flipped_foot(angle):
    """Folded as far as it goes, the skirt points along the axis and its rim is a flat ring from
    r_hub - t/2 to r_hub + t/2: the pipe must be wider than 2 (r_hub + t/2 + clearance)."""
    from softcrawl.studies.foot.flip import FOLD_CLEARANCE, flipped_min_diameter

    d = FootDesign(angle=angle)
    assert flipped_min_diameter(d) == pytest.approx(
        2 * (d.hub_radius + d.skirt_thickness / 2 + FOLD_CLEARANCE)
    )


def test_a_bad_flipped_option_names_it():
    from softcrawl.studies.foot.simulate import simulate_foot

    with pytest.raises(DesignError, match="flipped"):
        simulate_foot(flipped="yes")
    with pytest.raises(DesignError, match="pipe_diameter.*52 mm"):
        simulate_foot(FootDesign(), 51.0, flipped=True)


@pytest.mark.slow
def test_the_folded_foot_turns_its_grooved_face_out():
    """The FE fold of the quick foot by the flip (rim rotated by Delta, hub top held): the tip is
    ahead of the hub top, the grooved face's outward normals point to the wall and the smooth
    face's to the axis, and the held state is stable (no negative eigenvalue left once the
    pressure block's are taken off). ~1-2 min."""
    from softcrawl.fem.model import Dirichlet, SolidModel
    from softcrawl.geometry.foot_meshers import mesh_foot_with
    from softcrawl.materials import get_material
    from softcrawl.materials.fem_law import solid_law
    from softcrawl.studies.foot.flip import describe, fold
    from softcrawl.studies.foot.model import FOOT_NEWTON

    design = FootDesign()
    mesh = mesh_foot_with(design, "revolved", sectors=24).to_skfem(2)
    mat = solid_law(get_material("rubber-70a"), hyperelastic_only=True)
    folded = fold(mesh, mat, design, hinge(design)[1], options=FOOT_NEWTON)
    assert folded.converged, folded.message
    held = SolidModel(mesh, mat, dirichlet=[Dirichlet.fixed("hub_top"), Dirichlet.fixed("rim")])
    e = describe(held, folded.x, 0.0)
    assert e.tip_ahead > 3.0
    assert e.grooved_normal > 0.2 and e.smooth_normal < -0.2
    assert e.unstable_modes in (0, None)


@pytest.mark.slow
def test_the_flipped_foot_presses_its_grooved_face_on_the_wall():
    """The quick flipped foot in the 70 mm pipe: more than 90 % of the wall's normal force on the
    grooved face after the release, and during the backward (sliding) drag. ~3-10 min."""
    from softcrawl.studies.foot.simulate import simulate_foot

    r = simulate_foot(FootDesign(), 70.0, quick=True, flipped=True, max_wall_s=None)
    assert r.flipped and np.isfinite(r.normal_force), r.message
    assert r.face_forces["grooved"] > 0.9 * r.normal_force
    assert r.backward is not None and np.all(r.backward.grooved_share > 0.9)
    assert r.backward.peak > 0
