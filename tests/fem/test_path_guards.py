"""Every loop of a solve is bounded: a wrong model fails fast with a message, never spins."""

import numpy as np

from softcrawl.fem import reference_models as RM
from softcrawl.fem.chamber import Chamber
from softcrawl.fem.path import NewtonOptions, load_path, volume_path
from softcrawl.fem.reference_models import MU


def test_a_flipped_chamber_normal_fails_fast_instead_of_creeping_forever(monkeypatch):
    """With the Nanson normal flipped, the load and volume no longer match the tangent: pressure
    control creeps in ever smaller steps and volume control creeps on without reaching a target
    or a peak. Before the step guards the plane-strain tube ran for more than 290 s; now the path
    ends with a message that names the last converged load and the guard."""
    kinematics = Chamber._kinematics

    def flipped(self, x):
        F, cofN = kinematics(self, x)
        return F, -cofN

    monkeypatch.setattr(Chamber, "_kinematics", flipped)
    model = RM.tube_model(1.0, 20.0, n_radial=4, n_angle=4)
    res = load_path(model, [(0.5 * MU, 0.0), (2.0 * MU, 0.0)])
    assert not res.converged
    assert "diverged after the last converged load (P = " in res.message
    assert any(
        word in res.message for word in ("max_substeps", "min_step_fraction", "max_volume_steps", "cut")
    )
    assert res.stats.iterations < 1000, res.stats  # bounded work (~600 iterations, ~10 s)


def test_the_substep_guard_names_itself():
    """One sub-step allowed and two Newton iterations: pressure control gives up at once, says
    why, and volume control (which the guard does not limit) takes over and lands on the target."""
    model = RM.tube_model(3.0, 9.0, n_radial=2, n_angle=3)
    opt = NewtonOptions(max_substeps=1, max_iter=2, predictor="none")
    res = load_path(model, [(0.9 * MU, 0.0)], options=opt)
    assert "1 sub-steps (max_substeps) did not reach P = 27 kPa" in res.events[0], res.events
    assert res.converged and res.steps[-1].control == "volume"


def test_the_volume_step_guard_names_itself():
    model = RM.tube_model(3.0, 9.0, n_radial=2, n_angle=3)
    V0 = model.chamber_volume(model.initial_state())
    res = volume_path(model, [1.5 * V0], options=NewtonOptions(max_volume_steps=1, max_iter=2))
    assert not res.converged
    assert "max_volume_steps" in res.message, res.message
    # and with room to work the same target is reached
    ok = volume_path(model, [1.5 * V0])
    assert ok.converged and np.isclose(ok.steps[-1].volume, 1.5 * V0, rtol=1e-9)
