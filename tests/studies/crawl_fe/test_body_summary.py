"""The FE-body crawl's summary text (`studies.crawl_fe.summary.summary_text`) says what summary.json
holds: each cycle's stride, speed, turn and wall time ("not recorded" for runs and cycles before the
time was kept, docs/decisions/092-cycle-time.md), a bellows' corrugations (093) and the linear
solver the run used (absent in runs before it was kept).
"""

from softcrawl.studies.crawl_fe.summary import summary_text


def _summary(**over):
    s = {
        "pipe": {"kind": "bellows", "diameter_mm": 75.0, "bend_radius_mm": None,
                 "corrugation_mm": [2.0, 10.0]},
        "mesh": "quick",
        "materials": {"epsa": "ecoflex-00-50@mu=0.0638"},
        "message": "2 cycle(s) reached",
        "strides_mm": [26.0, 24.0],
        "turns_deg": [0.0, 0.5],
        "cycle_wall_s": [408.4, None],
        "schedule": {"cycle_s": 2.0},
        "paper_speed_mm_s": None,
        "mass": {"total_g": 127.7, "prototype_g": 70.2},
        "solver": {"dofs": 139497, "newton_iterations": 273, "factorizations": 143,
                   "linear_solver": "pardiso", "wall_s": 1218.0, "peak_rss_gb": 3.7, "linear_s": 900.0,
                   "contact_share": 0.03},
    }  # fmt: skip
    return s | over


def test_the_text_gives_each_cycles_wall_time_the_corrugations_and_the_solver():
    text = summary_text(_summary())
    assert "bellows 75 mm pipe, corrugations 2 mm deep, 10 mm pitch" in text
    assert "cycle 1: stride 26.000 mm, speed 13.00 mm/s, turn +0.00 deg, 408 s of wall time" in text
    assert "cycle 2: stride 24.000 mm, speed 12.00 mm/s, turn +0.50 deg, wall time not recorded" in text
    assert "143 factorisations (pardiso)" in text


def test_a_summary_from_before_the_times_and_the_solver_were_kept_still_reads():
    old = _summary(pipe={"kind": "straight", "diameter_mm": 70.0, "bend_radius_mm": None})
    del old["cycle_wall_s"], old["solver"]["linear_solver"]
    text = summary_text(old)
    assert text.count("wall time not recorded") == 2 and "143 factorisations, 1218 s" in text
