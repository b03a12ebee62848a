"""The whole robot in FE on a coarse mesh: the checks of issue 15 that can fail.

* equal pressures extend the robot without bending: |theta| < 0.5 deg;
* unequal pressures bend it toward the lower pressure (actuator 1 at psi = 90 deg: phi ~ 90 deg
  and the tip moves to +y when P1 is the lowest);
* phi agrees with eq. 6 fed with the FE lengths within 10 deg;
* the outputs are consistent: the effective d of eq. 7 reproduces the FE theta from the FE
  lengths, and the arc fit and splay are small for this three-ring robot at a moderate load.

Pressures are kept low (<= 20 kPa) so that each path is a few Newton steps on the quick mesh.
The mesh-convergence check (theta at the Table 1 load, default against fine mesh) is slow.
"""

import math

import numpy as np
import pytest

from softcrawl.studies.robot_fe.model import build_robot_model
from softcrawl.studies.robot_fe.response import arc_fit_rms, simulate_robot

KPA = 1e-3


@pytest.fixture(scope="module")
def robot():
    return build_robot_model(None, mesh="quick")


def test_equal_pressures_extend_without_bending(robot):
    run = simulate_robot(robot, [(20 * KPA,) * 3])
    assert run.converged, run.message
    s = run.states[-1]
    assert abs(s.theta_deg) < 0.5  # observed ~0.01 deg
    assert s.extension_mm > 1.0
    assert max(s.lengths_mm) - min(s.lengths_mm) < 0.05 * s.extension_mm
    assert run.material == "ecoflex-00-50@mu=0.0638"


def test_unequal_pressures_bend_toward_the_lower_pressure(robot):
    run = simulate_robot(robot, [(2 * KPA, 12 * KPA, 12 * KPA)])
    assert run.converged, run.message
    s = run.states[-1]
    assert s.theta_deg > 1.0
    assert abs(s.phi_deg - 90.0) < 5.0  # toward actuator 1 (psi = 90 deg), the lowest pressure
    assert s.tip_mm[1] > 1.0 and abs(s.tip_mm[0]) < 0.2 * s.tip_mm[1]
    assert s.lengths_mm[0] < min(s.lengths_mm[1:])


def test_phi_agrees_with_eq6_and_d_eff_closes_eq5(robot):
    run = simulate_robot(robot, [(0.0, 10 * KPA, 15 * KPA)])
    assert run.converged, run.message
    s = run.states[-1]
    assert abs(s.phi_deg - s.phi_cc_deg) < 10.0  # observed 0.03 deg
    assert 90.0 < s.phi_deg < 150.0  # between actuators 1 (90) and 2 (210), nearer 1
    l1, l2, l3 = s.lengths_mm
    q = math.sqrt(l1 * l1 + l2 * l2 + l3 * l3 - l1 * l2 - l1 * l3 - l2 * l3)
    assert math.degrees(2 * q / (3 * s.d_eff_mm)) == pytest.approx(s.theta_deg, rel=1e-9)
    assert s.d_eff_mm == pytest.approx(14.0, rel=0.05)  # observed 14.11 mm at (0, 20, 30) kPa
    assert s.arc_rms_mm < 0.5 and s.splay_mm < 0.5  # observed 0.02 and 0.017 mm at (0, 20, 30) kPa


def test_arc_fit_is_exact_on_an_arc_and_a_line():
    t = np.linspace(0, 1.2, 15)
    arc = np.column_stack([50 * (1 - np.cos(t)), np.zeros_like(t), 50 * np.sin(t)])
    assert arc_fit_rms(arc) < 1e-9
    assert arc_fit_rms(np.column_stack([t, 2 * t, 3 * t])) < 1e-12
    wavy = arc + np.column_stack([np.zeros_like(t), 0.5 * np.sin(8 * t), np.zeros_like(t)])
    assert arc_fit_rms(wavy) > 0.2


@pytest.mark.slow
def test_theta_at_the_table1_load_is_mesh_converged():
    """theta at P = (100, 40, 60) kPa changes by < 2 % from the default to the fine mesh."""
    from softcrawl.studies.robot_fe.robot_studies import LOAD_CASES_KPA

    targets = [tuple(p * KPA for p in P) for P in LOAD_CASES_KPA["asymmetric"]]
    theta = {}
    for mesh in ("default", "fine"):
        run = simulate_robot(build_robot_model(None, mesh=mesh), targets)
        assert run.converged, run.message
        theta[mesh] = run.states[-1].theta_deg
    assert theta["default"] == pytest.approx(theta["fine"], rel=0.02)
