"""The foot's studies against the pipe wall (paper Fig. 10), declared for the registry
(`studies.registry`): the grooved strip and the whole foot, with Coulomb friction."""

from softcrawl.studies.declaration import Study

_OPTIONS = frozenset({"workers", "max_memory", "storage", "retry_failed"})
_RUN = "softcrawl.studies.foot.runs:run_request"
_REPLOT = "softcrawl.studies.foot.runs:replot_folder"
#: The foot's friction coefficients, a stated input (studies/foot/contact_studies.py), for the foot
#: study and `softcrawl crawl`; here so that `--help` reads them without loading the solver.
FOOT_FRICTION = {"mu_smooth": 0.5, "mu_grooved": 0.5}

STUDIES = (
    Study(
        name="groove",
        summary="paper Fig. 10(a): a grooved strip pressed at 100 kPa and dragged 5 mm",
        run=_RUN,
        default_material="rubber-70a",
        options=_OPTIONS,
        evaluators={"groove": "softcrawl.studies.foot.contact_studies:evaluate_groove"},
        figure="groove.png",
        tables=("curves.csv", "summary.csv", "groove-rule.md"),
        rule=("groove_height",),
        table1="softcrawl.studies.foot.groove_rule:table1_rows",
        replot=_REPLOT,
        help="groove (Fig. 10(a)): contact with the pipe wall, Coulomb friction, over groove heights h "
        "and friction coefficients mu; see studies/foot/contact_studies.py for the grid.",
    ),
    Study(
        name="foot",
        summary="paper Fig. 10(b): the whole foot inserted into 55-75 mm pipes and dragged 8 mm",
        run=_RUN,
        default_material="rubber-70a",
        options=_OPTIONS,
        evaluators={"foot": "softcrawl.studies.foot.contact_studies:evaluate_foot"},
        figure="foot.png",
        tables=("curves.csv", "summary.csv"),
        replot=_REPLOT,
        help="foot (Fig. 10(b)): the whole foot inserted into 55-75 mm pipes and dragged 8 mm forward "
        "and backward (F_bwd / F_fwd, skirt flip); see studies/foot/contact_studies.py.",
    ),
    Study(
        name="identify-feet",
        summary="mu_smooth and mu_grooved fitted to one foot's share of eq. 26 at 70 mm (Table 2 held out)",
        run="softcrawl.studies.foot.identify_run:run_request",
        folder="identify",
        default_material=None,
        tables=("feet.json", "feet.md"),
        in_review=False,
        marker="feet.json",
        help="identify-feet: the feet's friction coefficients fitted to one sliding foot's share of "
        "eq. 26 (/ 3, record 062) at 70 mm (studies/foot/identify.py), DIR/identify/feet[-quick]/feet.json.",
    ),
)
