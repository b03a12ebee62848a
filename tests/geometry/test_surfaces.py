"""Surfaces and fibers (no meshing): watertight, right volumes, fibers on the outer surface, robot layout."""

import math

import numpy as np
import pytest

from softcrawl.geometry.assembly import robot_surfaces
from softcrawl.geometry.design import EPSADesign, FootDesign, RingDesign, RobotDesign
from softcrawl.geometry.epsa_shape import epsa_surface, fiber_helices, seal_head_surface
from softcrawl.geometry.foot import foot_profile, foot_segments, foot_surface, foot_volume
from softcrawl.geometry.ring import ring_surface, ring_volume
from softcrawl.geometry.surfaces import signed_volume


def _closed(surface):
    return surface.n_open_edges == 0 and surface.is_manifold


def test_epsa_surface_closed_with_cavity():
    e = EPSADesign()
    s = epsa_surface(e, 48)
    assert _closed(s)
    assert s.n_cells > 0
    # inscribed 48-gons: relative volume deficit sin(2 pi/n)/(2 pi/n) - 1 = -0.29 %
    assert signed_volume(s) == pytest.approx(e.body_volume, rel=4e-3)
    assert signed_volume(seal_head_surface(e)) == pytest.approx(math.pi * 81 * 3, rel=4e-3)


@pytest.mark.parametrize("N", [1, 10, 20, 50])
def test_fiber_helices(N):
    e = EPSADesign(fiber_turns=N)
    fibers = fiber_helices(e)
    assert len(fibers) == 2
    for f in fibers:
        length = np.linalg.norm(np.diff(f, axis=0), axis=1).sum()
        assert length == pytest.approx(e.helix_length, rel=5e-3)
        assert np.allclose(np.hypot(f[:, 0], f[:, 1]), e.outer_radius, atol=1e-12)  # on rho = R0
        assert f[0, 2] == 0 and f[-1, 2] == pytest.approx(e.length)
    # opposite handedness: theta increases along one helix and decreases along the other
    t0 = np.unwrap(np.arctan2(fibers[0][:, 1], fibers[0][:, 0]))
    t1 = np.unwrap(np.arctan2(fibers[1][:, 1], fibers[1][:, 0]))
    assert t0[-1] - t0[0] == pytest.approx(2 * math.pi * N)
    assert t1[-1] - t1[0] == pytest.approx(-2 * math.pi * N)
    assert fiber_helices(EPSADesign(fiber_turns=0)) == ()


@pytest.mark.parametrize(
    "foot",
    [
        FootDesign(),
        FootDesign(angle=100, groove_height=2.0, n_grooves=3),
        FootDesign(angle=180, hub_thickness=3.0),
        FootDesign(bore_radius=0.0),
    ],
)
def test_foot_surface(foot):
    s = foot_surface(foot)
    assert _closed(s)
    assert signed_volume(s) == pytest.approx(foot_volume(foot), rel=3e-3)
    prof, tags = foot_profile(foot)
    assert len(prof) == len(tags)
    assert set(tags) >= {"front", "back", "rim", "hub_top", "hub_bottom"}
    # the groove bottoms sit h below the back face
    assert prof[:, 0].max() == pytest.approx(foot.tip_radius)
    assert sum(1 for s in foot_segments(foot) if s.tag == "back") == 4 * foot.n_grooves + 1


def test_foot_grooves_on_back_face_only():
    f = FootDesign()
    a = math.radians(f.angle / 2)
    n = np.array([math.cos(a), math.sin(a)])
    prof, tags = foot_profile(f)
    front = [prof[i] for i, t in enumerate(tags) if t == "front"][0]
    # every back-face vertex lies between the front plane and t behind it; groove bottoms at t - h
    depth = np.array([(front - p) @ n for p, t in zip(prof, tags) if t == "back"])
    assert depth.max() == pytest.approx(f.skirt_thickness)
    assert depth.min() == pytest.approx(f.skirt_thickness - f.groove_height)


def test_ring_surface():
    r = RingDesign()
    s = ring_surface(r)
    assert _closed(s)
    assert signed_volume(s) == pytest.approx(ring_volume(r), rel=3e-3)


def test_robot_actuators_do_not_intersect_and_channel_radius():
    design = RobotDesign()
    parts = robot_surfaces(design)
    R0, d = design.epsa.outer_radius, design.d
    centres = design.actuator_centres
    channel = min(
        np.hypot(parts[f"epsa{i}"].points[:, 0], parts[f"epsa{i}"].points[:, 1]).min() for i in (1, 2, 3)
    )
    assert channel == pytest.approx(d - R0, abs=1e-9) and design.channel_radius == d - R0
    for i in (1, 2, 3):
        p = np.asarray(parts[f"epsa{i}"].points)
        for j in (1, 2, 3):
            if i != j:
                rho = np.hypot(p[:, 0] - centres[j - 1][0], p[:, 1] - centres[j - 1][1])
                assert rho.min() > R0  # no point of actuator i inside actuator j
    # psi = 90, 210, 330 deg on radius d
    assert np.allclose([math.degrees(math.atan2(y, x)) % 360 for x, y in centres], [90, 210, 330])
    assert np.allclose([math.hypot(x, y) for x, y in centres], d)
    assert set(parts) == {
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
    # rings within the actuator length, feet at both ends
    for k in (1, 2, 3):
        zb = parts[f"ring{k}"].bounds
        assert 0 < zb[4] < zb[5] < design.epsa.length
        assert max(abs(zb[0]), abs(zb[1]), abs(zb[2]), abs(zb[3])) <= design.ring.outer_radius + 1e-9
    assert parts["foot_rear"].bounds[5] == pytest.approx(0.0)
    top = design.epsa.length + design.epsa.seal_head_thickness
    assert parts["foot_front"].bounds[5] == pytest.approx(top + design.foot.hub_thickness)
    # the front foot's skirt clears the actuators (hub radius > d + R0)
    ff = np.asarray(parts["foot_front"].points)
    below = ff[ff[:, 2] < top]
    assert np.hypot(below[:, 0], below[:, 1]).min() >= d + R0
