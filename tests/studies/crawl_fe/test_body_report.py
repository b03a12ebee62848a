"""The design review's FE-body section (`studies.crawl_fe.report`) reads the committed runs.

Without runs it names the command that makes one; with a run it shows its figures as the run
recorded them (strides, speeds, the paper's speed and source, turns, mass, effort, how it ended)
and the silicone's modulus, and skips folders that are not FE-body runs.
"""

import json

from softcrawl.studies.crawl_fe.report import FOLDER, STRAIGHT, crawl_fe


def _summary(**over):
    s = {
        "model": "fe-body",
        "converged": True,
        "message": "2 cycle(s) reached",
        "pipe": {"kind": "elbow", "diameter_mm": 70.0, "bend_radius_mm": 60.0},
        "mesh": "quick",
        "cycles": 2,
        "friction": {"mu_smooth": 0.3, "mu_grooved": 0.3},
        "materials": {"epsa": "ecoflex-00-50@mu=0.0638"},
        "silicone_shear_modulus_mpa": 0.0638,
        "mass": {"total_g": 127.68},
        "strides_mm": [26.31, 23.82],
        "speeds_mm_s": [13.155, 11.91],
        "turns_deg": [1.5, -0.25],
        "paper_speed_mm_s": None,
        "paper_source": "the paper gives no bend radius for its L-shaped pipe (Fig. 24)",
        "solver": {"newton_iterations": 346, "wall_s": 2505.0, "peak_rss_gb": 4.0},
    }
    return s | over


def test_without_runs_the_section_names_the_command(tmp_path):
    html = crawl_fe(tmp_path)
    assert "softcrawl crawl --body fe" in html and STRAIGHT.split(" --out")[0] in html


def test_a_run_is_one_row_with_its_own_figures(tmp_path):
    run = tmp_path / FOLDER / "elbow-70-R60"
    run.mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps(_summary()))
    other = tmp_path / FOLDER / "notes"
    other.mkdir()
    (other / "summary.json").write_text(json.dumps({"model": "something else"}))
    html = crawl_fe(tmp_path)
    for text in ("elbow-70-R60", "elbow, R 60 mm, 70 mm", "26.31, 23.82", "13.15, 11.91", "+1.50, -0.25"):
        assert text in html, text
    assert "no bend radius" in html and "127.7" in html and "346" in html and "2505" in html
    assert "0.0638 MPa" in html and "2 / 2" in html
    assert "notes" not in html
    assert "<td>0</td>" in html  # no slip viscosity recorded: a Coulomb run (before record 088)
    viscous = _summary(friction={"mu_smooth": 0.3, "mu_grooved": 0.3, "slip_viscosity_mpa_s_mm": 7.5e-4})
    (run / "summary.json").write_text(json.dumps(viscous))
    assert "<td>0.00075</td>" in crawl_fe(tmp_path)


def test_each_cycles_wall_time_is_shown_where_the_run_kept_it(tmp_path):
    run = tmp_path / FOLDER / "elbow-70-R60"
    run.mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps(_summary(cycle_wall_s=[408.4, None])))
    assert "<td>408, not recorded</td>" in crawl_fe(tmp_path)  # None: a resumed pre-092 checkpoint
    (run / "summary.json").write_text(json.dumps(_summary()))  # a run before the times were kept
    assert "<td>not recorded</td>" in crawl_fe(tmp_path)


def test_a_wedge_run_says_so_in_its_mesh(tmp_path):
    run = tmp_path / FOLDER / "straight-70-default-wedge3"
    run.mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps(_summary(mesh="default", wedge=3)))
    assert "<td>default, wedge 360/3 deg</td>" in crawl_fe(tmp_path)
    (run / "summary.json").write_text(json.dumps(_summary(mesh="default")))  # runs before the wedge
    assert "<td>default</td>" in crawl_fe(tmp_path)
