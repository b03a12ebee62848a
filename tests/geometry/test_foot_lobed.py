"""The lobed reading of Fig. 3 (`geometry.foot_lobed`): its tip outline, wall share and the axis."""

from __future__ import annotations

import math

import numpy as np
import pytest

from softcrawl.geometry import foot_lobed as fl
from softcrawl.geometry.design import FootDesign


def test_a_lobe_is_the_section_about_its_sub_circle():
    lobe = fl.lobe_design(FootDesign())
    assert (lobe.hub_radius, lobe.tip_radius, lobe.bore_radius) == (10.0, 25.0, 0.0)
    assert lobe.back_face_length == pytest.approx(FootDesign().back_face_length, rel=1e-12)
    assert all(math.hypot(*c) == pytest.approx(14.0, rel=1e-12) for c in fl.lobe_centres(FootDesign()))


def test_the_outline_reaches_39_mm_at_a_lobe_and_28_86_between_two():
    f = FootDesign()
    assert fl.outline_radius(f, 0.0) == pytest.approx(39.0, abs=1e-12)
    # between two lobes: the two tip circles (radius 25 about points 14 mm out) meet at 7 + sqrt(478)
    assert fl.outline_radius(f, math.pi / 3) == pytest.approx(7.0 + math.sqrt(625.0 - 147.0), abs=1e-12)


@pytest.mark.parametrize("diameter", [55.0, 60.0, 65.0, 70.0, 75.0, 78.5])
def test_wall_share_against_sampling_the_three_tip_circles(diameter):
    """The closed form against a direct count: directions where some tip circle lies beyond R."""
    f = FootDesign()
    phi = np.linspace(0.0, 2 * np.pi, 360_000, endpoint=False)
    reach = np.zeros_like(phi)
    for cx, cy in fl.lobe_centres(f):  # farthest point of a circle of radius 25 about c along phi
        along = cx * np.cos(phi) + cy * np.sin(phi)
        across = -cx * np.sin(phi) + cy * np.cos(phi)
        reach = np.maximum(reach, along + np.sqrt(np.clip(25.0**2 - across**2, 0.0, None)))
    assert fl.contact_share(f, diameter) == pytest.approx(np.mean(reach > diameter / 2), abs=1e-4)


def test_the_lobes_cover_the_axis():
    assert fl.axis_crossing(FootDesign()) == pytest.approx(-4.0 / math.tan(math.radians(60.0)), abs=1e-12)
    assert fl.axis_crossing(FootDesign(tip_radius=27.5, n_grooves=0)) is None  # lobes of 13.5 < d


@pytest.mark.slow
def test_the_lobed_mesh_is_tagged_and_reaches_39_mm(tmp_path):
    mesh = fl.mesh_foot_lobed(FootDesign(), edge_length=4.0, cache_dir=tmp_path)
    assert mesh.meta["n_untagged_facets"] <= 10
    assert {"front", "back", "rim", "hub_top", "hub_bottom"} <= set(mesh.facets)
    rho = np.hypot(mesh.points[:, 0], mesh.points[:, 1])
    assert rho.max() == pytest.approx(39.0, abs=0.05)
