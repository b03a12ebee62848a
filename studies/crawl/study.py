"""The crawl study, declared for the registry (`studies.registry`): stride and anchoring of the FE
crawl (two feet, the ePSAs' axial law) over pipe diameter and friction coefficient."""

from softcrawl.studies.declaration import Study

STUDIES = (
    Study(
        name="crawl",
        summary="stride and anchoring of the FE crawl over pipe diameter and friction",
        run="softcrawl.studies.crawl.crawl_study:run_request",
        default_material="rubber-70a",
        options=frozenset({"workers", "max_memory", "storage", "retry_failed"}),
        evaluators={"crawl": "softcrawl.studies.crawl.crawl_study:evaluate_crawl"},
        figure="crawl-study.png",
        tables=("summary.csv", "summary.md"),
        replot="softcrawl.studies.crawl.crawl_study:replot_folder",
        check="softcrawl.studies.crawl.crawl_study:check_request",
        in_review=False,
        help="crawl: stride and anchoring of the FE crawl (two feet, the ePSAs' axial law) over pipe "
        "diameter and friction coefficient (studies/crawl/crawl_study.py), "
        "DIR/crawl/rubber-70a[-quick]/; shown in the review's crawl section.",
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
