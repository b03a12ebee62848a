"""One body geometry (`softcrawl.body`): the foot hub, the rings, the swept robot and the planner."""

from __future__ import annotations

import pytest

from softcrawl import paper
from softcrawl.analytic.prototype import BODY_RADIUS_MM
from softcrawl.body import BODY, Body
from softcrawl.errors import InputError
from softcrawl.geometry.design import DesignError, FootDesign, RingDesign, RobotDesign
from softcrawl.geometry.robot_mesh import stiff_outline


def test_the_envelope_is_the_papers_minimum_diameter():
    assert BODY.envelope_diameter == paper.MIN_DIAMETER_MM == 2 * (paper.D_MM + paper.EPSA_RADIUS_MM)
    assert BODY.part_radius == BODY.envelope_radius + BODY.rim == 24.0


def test_hub_rings_robot_and_planner_derive_from_the_one_body():
    robot = RobotDesign()
    radii = {
        "foot hub": FootDesign().hub_radius,
        "ring": RingDesign().outer_radius,
        "robot's foot hub": robot.foot.hub_radius,
        "robot's ring": robot.ring.outer_radius,
        "swept robot outline": stiff_outline(robot)[1],
    }
    assert set(radii.values()) == {BODY.part_radius}, radii
    assert BODY_RADIUS_MM == BODY.clearance_radius == paper.MIN_DIAMETER_MM / 2
    assert robot.bundle_diameter == BODY.envelope_diameter


@pytest.mark.parametrize("d", [12.0, 16.0])
def test_a_robot_of_another_d_sizes_its_parts_from_its_own_body(d):
    robot = RobotDesign(d=d)
    assert robot.body == Body(d=d)
    assert robot.foot.hub_radius == robot.ring.outer_radius == d + 9.0 + BODY.rim


def test_a_closed_ring_cannot_be_the_46_mm_envelope():
    """Holes of radius R0 at d leave no material outside them at P = d + R0 (record 066)."""
    with pytest.raises(DesignError, match="outer_radius"):
        RingDesign(outer_radius=BODY.envelope_radius)
    RingDesign(outer_radius=BODY.part_radius)


def test_the_committed_results_foot_is_unchanged():
    """The default foot's hash (the committed foot and crawl results' design) did not move."""
    assert FootDesign().short_hash() == "2dfe9df3cb76"
    assert FootDesign().to_dict()["hub_thickness"] == 4.0


@pytest.mark.parametrize("field", ["d", "epsa_radius", "rim"])
def test_body_rejects_a_non_positive_length(field):
    with pytest.raises(InputError, match=field):
        Body(**{field: 0.0})
