"""The material studies, declared for the registry (`studies.registry`): which material reproduces
the paper's own FE observations of Figs. 8-9 (no FE)."""

from softcrawl.studies.declaration import Study

STUDIES = (
    Study(
        name="paper-material",
        summary="the shear-modulus window in which the paper's Fig. 8 observations hold (no FE)",
        run="softcrawl.studies.material.paper_material:run_request",
        default_material=None,
        tables=("windows.csv", "paper-material.json"),
        in_review=False,
        help="paper-material: which material (Neo-Hookean, Yeoh, Gent; every shape and shear modulus) "
        "reproduces the paper's own FE observations of Figs. 8-9; no FE "
        "(studies/material/paper_material.py); shown in the review's material section.",
    ),
)
