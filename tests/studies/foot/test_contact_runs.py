"""Outputs of the foot studies from stored point results (no FE), and the slow whole-foot run."""

import json

import pytest

from softcrawl.studies.foot.contact_studies import point_file
from softcrawl.studies.foot.runs import contact_spec, write_contact_outputs


def _groove_point(folder, h, mu, strain):
    summary = {
        "converged": True,
        "normal_force_n": 0.26,
        "normal_force_error": 1e-15,
        "plateau_over_mu_n": 1.0,
        "von_mises_mpa_p99": 0.2 * h,
        "von_mises_mpa_max": 0.3 * h,
        "max_principal_strain_p99": strain,
        "deformation_max_mm": 0.1 * h,
    }
    curve = {
        "drag_mm": [1.0, 2.0],
        "friction_n": [0.07, 0.078],
        "normal_n": [0.26, 0.26],
        "contact_fraction": [0.5, 0.5],
    }
    path = point_file(folder, "groove", {"groove_height": h, "mu": mu})
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"summary": summary, "curve": curve}))


def test_groove_outputs_tables_plot_and_rule(tmp_path):
    spec = contact_spec("groove", tmp_path, "rubber-70a", quick=True)
    rows = []
    for h in spec.grid["groove_height"]:
        for mu in spec.grid["mu"]:
            _groove_point(tmp_path, h, mu, 0.04 * h)
            rows.append({"groove_height": h, "mu": mu, "trial_status": "completed", "reason": ""})
    rows[-1]["trial_status"] = "failed"
    rows[-1]["reason"] = "stage 'drag' diverged"
    outcome = write_contact_outputs("groove", spec, rows, tmp_path)
    assert not outcome.ok and "diverged" in outcome.problems[0]
    names = {p.name for p in outcome.written}
    assert {"summary.csv", "curves.csv", "groove.png", "groove-rule.md"} <= names
    rule = (tmp_path / "groove-rule.md").read_text()
    assert "Groove height h: 1.0 mm" in rule  # h = 2 failed: 1.0 is the largest completed within 0.10


@pytest.mark.slow
def test_foot_in_a_75_mm_pipe(tmp_path):
    """Insertion into the largest pipe and 2 mm of drag each way: the wall's normal force is
    positive, the forward resistance positive, everything converged."""
    from softcrawl.analytic.pipe import Pipe
    from softcrawl.geometry.design import FootDesign
    from softcrawl.geometry.foot_revolved import mesh_foot_revolved
    from softcrawl.materials import get_material
    from softcrawl.materials.fem_law import solid_law
    from softcrawl.studies.foot.model import run_foot

    design = FootDesign()
    mesh = mesh_foot_revolved(design).to_skfem(2)
    mat = solid_law(get_material("rubber-70a"))
    r = run_foot(
        mesh,
        mat,
        design,
        Pipe(diameter=75.0),
        mu_smooth=0.5,
        mu_grooved=0.5,
        drag=2.0,
        insert_steps=4,
        drag_steps=2,
    )
    assert r.converged, r.message
    assert r.normal_force > 0 and r.forward.peak > 0 and r.backward.peak > 0
