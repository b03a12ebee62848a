"""The calibration loop recovers a known modulus (fake evaluator: length = L_proto(P * mu* / mu))."""

import pytest

from softcrawl.studies.epsa import response as actuator
from softcrawl.studies.material import calibration as calibrate


def test_calibration_recovers_a_known_modulus(monkeypatch):
    mu_true = 0.08
    pressures = (20.0, 40.0, 60.0, 80.0, 100.0)

    def fake(design, *, material, pressures_kpa, mesh):
        scaled = calibrate.prototype_lengths([p * mu_true / material.mu for p in pressures_kpa])
        rows = (actuator.CurveRow(0.0, 100.0, 9.0, 1.0, 1.0, 0.0, "reference"),) + tuple(
            actuator.CurveRow(p, L, 9.0, 1.0, 1.0, 0.0, "converged") for p, L in zip(pressures_kpa, scaled)
        )
        return actuator.ActuatorCurve(rows, True, None, "ok", 0.0, 0, material.name, material.mu)

    monkeypatch.setattr(calibrate, "simulate_epsa", fake)  # where calibrate_mu looks it up
    cal = calibrate.calibrate_mu(pressures_kpa=pressures, xatol=1e-3)
    assert cal.mu_mpa == pytest.approx(mu_true, rel=0.01)
    assert cal.rms_error_mm < 0.5
    assert len(cal.evaluations) >= 3
