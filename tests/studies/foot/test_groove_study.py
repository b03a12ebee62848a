"""The groove-segment model and the groove-height rule of Table 1."""

import numpy as np
import pytest

from softcrawl.fem.laws import NeoHookean
from softcrawl.studies.foot.groove_model import GrooveSegment, groove_mesh, run_groove
from softcrawl.studies.foot.groove_rule import GrooveRuleInputs, decide
from softcrawl.studies.sweeps.spec import StudyError

RUBBER = NeoHookean.nearly_incompressible(5.52 / 3.0)


def test_groove_mesh_has_full_lands():
    seg = GrooveSegment(groove_height=1.0, cell=0.4)
    mesh = groove_mesh(seg)
    assert set(mesh.boundaries) >= {"top", "contact", "y0", "y1"}
    # lands: the contact facets at z = 0 cover n_grooves (pitch - w) x width
    facets = mesh.boundaries["contact"]
    z = mesh.p[2, mesh.facets[:, facets]]
    x = mesh.p[:, mesh.facets[:, facets]]
    bottom = np.all(z < 1e-9, axis=0)
    a, b, c = x[:, 0, bottom], x[:, 1, bottom], x[:, 2, bottom]
    area = 0.5 * np.linalg.norm(np.cross((b - a).T, (c - a).T), axis=1).sum()
    assert area == pytest.approx(seg.n_grooves * (seg.pitch - seg.groove_width) * seg.width, rel=1e-9)


def test_bad_groove_inputs_name_the_parameter():
    with pytest.raises(StudyError, match="groove_height"):
        GrooveSegment(groove_height=3.5)
    with pytest.raises(StudyError, match="cell"):
        GrooveSegment(cell=0.0)


def test_groove_drag_normal_force_and_plateau():
    """N = p A (the backing keeps its footprint) and the sliding plateau is mu N (full slip)."""
    seg = GrooveSegment(groove_height=1.0, cell=0.4)
    states = {}
    r = run_groove(
        seg, RUBBER, 0.5, pressure=0.1, drag=1.0, drag_steps=4, on_state=lambda *a: states.update(last=a[1:3])
    )
    assert r.converged, r.message
    model, x = states["last"]
    uz = model.displacement(x)[2, model.boundary_nodes("top")]
    assert np.ptp(uz) < 1e-3 * np.abs(uz).max()  # the backing stays level (fem.equal_displacement)
    assert r.normal_error < 5e-3
    assert abs(r.plateau_over_mu_n - 1.0) < 5e-3
    assert r.slip_fraction[-1] == pytest.approx(1.0)
    assert r.metrics["von_mises_mpa_p99"] <= r.metrics["von_mises_mpa_max"]


def _row(h, mu, ratio, vm, strain, deform, status="completed"):
    return {
        "groove_height": str(h),
        "mu": str(mu),
        "trial_status": status,
        "plateau_over_mu_n": str(ratio),
        "von_mises_mpa_p99": str(vm),
        "max_principal_strain_p99": str(strain),
        "deformation_max_mm": str(deform),
    }


def test_groove_rule_takes_the_largest_height_within_the_strain_limit():
    rows = [_row(h, 0.3, 1.0, 0.2 * h, 0.04 * h, 0.1 * h) for h in (0.5, 1.0, 1.5, 2.0)]
    d = decide(rows, GrooveRuleInputs(strain_limit=0.05))
    assert d.status == "decided" and d.value == 1.0
    assert d.friction_independent and d.stress_rises and d.deformation_rises
    d = decide(rows, GrooveRuleInputs(strain_limit=0.01))
    assert d.status == "fallback" and d.value == 0.5


def test_groove_rule_reports_what_the_data_say():
    rows = [_row(h, 0.3, 1.0 + 0.2 * h, 0.3, 0.01, 0.1) for h in (0.5, 1.0)]
    d = decide(rows)
    assert d.friction_independent is False and d.stress_rises is False
    assert decide([_row(1.0, 0.3, 1, 1, 1, 1, status="failed")]).status == "pending"
