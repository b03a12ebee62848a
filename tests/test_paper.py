"""`softcrawl.paper`: the paper's numbers agree with each other and with the places that still
spell them out (the design defaults of `geometry.design`, which are the paper's Table 1)."""

import pytest

from softcrawl import paper
from softcrawl.analytic import loads
from softcrawl.analytic.prototype import BODY_RADIUS_MM
from softcrawl.geometry.design import EPSADesign, FootDesign, RobotDesign


def test_the_mass_in_tonne_is_the_mass_in_grams():
    assert paper.ROBOT_MASS_T == pytest.approx(paper.ROBOT_MASS_G * 1e-6, rel=1e-15)


def test_eq27_gives_the_printed_theoretical_load():
    g = paper.G_EQ27_M_S2 * 1000.0  # mm/s^2
    load_t = loads.theoretical_load(paper.F_EPSA_MAX_N, paper.ROBOT_MASS_T, g)
    assert load_t * 1e3 == pytest.approx(paper.THEORETICAL_LOAD_KG, abs=5e-4)


def test_the_minimum_diameter_is_the_actuator_bundle():
    assert 2 * BODY_RADIUS_MM == paper.MIN_DIAMETER_MM
    assert 2 * FootDesign().tip_radius == paper.MAX_DIAMETER_MM


def test_table1_is_the_default_design():
    epsa, foot, robot = EPSADesign(), FootDesign(), RobotDesign()
    ours = {
        "length": epsa.length,
        "outer_radius": epsa.outer_radius,
        "chamber_radius": epsa.chamber_radius,
        "fiber_turns": epsa.fiber_turns,
        "groove_height": foot.groove_height,
        "foot_radius": robot.d,
        "rings": robot.n_rings,
    }
    assert ours == {key: value for key, (_, value, _) in paper.TABLE1.items()}
    assert (robot.pipe_diameter_min, robot.pipe_diameter_max) == (
        min(paper.PIPE_DIAMETERS_MM),
        max(paper.PIPE_DIAMETERS_MM),
    )


def test_table2_covers_the_tested_pipes():
    assert tuple(paper.TABLE2_MM_S) == paper.PIPE_DIAMETERS_MM
    assert paper.table2(70.0, "backward") == 16.7 and paper.table2(80.0, "forward") is None
