"""The crawl studies, declared for the registry (`studies.registry`): stride and anchoring of the FE
crawl (two feet, the ePSAs' axial law) over pipe diameter and friction coefficient; its speed over
the feet's hardness and angle (paper Fig. 21)."""

from softcrawl.studies.declaration import Study

STUDIES = (
    Study(
        name="crawl",
        summary="stride and anchoring of the FE crawl over pipe diameter and friction",
        run="softcrawl.studies.crawl.crawl_study:run_request",
        default_material="rubber-70a",
        options=frozenset({"workers", "max_memory", "storage", "retry_failed", "wedge"}),
        evaluators={"crawl": "softcrawl.studies.crawl.crawl_study:evaluate_crawl"},
        figure="crawl-study.png",
        tables=("summary.csv", "summary.md"),
        replot="softcrawl.studies.crawl.crawl_study:replot_folder",
        check="softcrawl.studies.crawl.crawl_study:check_request",
        in_review=False,
        help="crawl: stride and anchoring of the FE crawl (two feet, the ePSAs' axial law) over pipe "
        "diameter and friction coefficient (studies/crawl/crawl_study.py), "
        "DIR/crawl/rubber-70a[-quick][-wedgeN]/; shown in the review's crawl section.",
    ),
    Study(
        name="feet",
        summary="speed of the FE crawl over the feet's hardness and angle (Fig. 21)",
        run="softcrawl.studies.crawl.feet_study:run_request",
        default_material="rubber-70a",
        options=frozenset({"workers", "max_memory", "storage", "retry_failed", "wedge"}),
        evaluators={"feet": "softcrawl.studies.crawl.feet_study:evaluate_feet"},
        figure="feet.png",
        tables=("feet.csv", "summary.md"),
        replot="softcrawl.studies.crawl.feet_study:replot_folder",
        report="softcrawl.studies.crawl.feet_study:report_block",
        check="softcrawl.studies.crawl.feet_study:check_request",
        help="feet: the FE crawl's speed in the 70 mm pipe over hardness 50A-70A x foot angle 30-120 deg, "
        "with the identified friction, against Fig. 21's two statements (studies/crawl/feet_study.py), "
        "DIR/feet/D70[-quick][-wedgeN]/.",
    ),
    Study(
        name="predict-crawl",
        summary="Table 2 predicted with the identified feet, forward and backward (no re-fit)",
        run="softcrawl.studies.crawl.prediction:run_request",
        folder="predict-crawl",
        default_material=None,
        figure="prediction.png",
        tables=("prediction.md", "prediction.csv"),
        replot="softcrawl.studies.crawl.prediction:replot_folder",
        help="predict-crawl: Table 2's forward and backward speeds at 55-75 mm predicted with the "
        "committed feet identification, never re-fitted; crawls it does not find under DIR are run "
        "(resumable), DIR/predict-crawl/rubber-70a/ (studies/crawl/prediction.py).",
    ),
)
