"""The foot's studies against the pipe wall (paper Fig. 10), declared for the registry
(`studies.registry`): the grooved strip and the whole foot, with Coulomb friction."""

from softcrawl.studies.declaration import Study

_OPTIONS = frozenset({"workers", "max_memory", "storage", "retry_failed"})
_RUN = "softcrawl.studies.foot.runs:run_request"
_REPLOT = "softcrawl.studies.foot.runs:replot_folder"
#: The foot's friction coefficients, a stated input (studies/foot/contact_studies.py), for the foot
#: study and `softcrawl crawl`; here so that `--help` reads them without loading the solver.
FOOT_FRICTION = {"mu_smooth": 0.5, "mu_grooved": 0.5}
#: Trial budgets of optimise-feet (`--trials`; studies/foot/optimise.py), here for `--help`: one
#: quick trial is two pipes of roughly 10-20 min each at load 4-6 (docs/decisions/072-optimise-feet.md).
FEET_TRIALS, FEET_QUICK_TRIALS = 40, 12

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
    Study(
        name="optimise-feet",
        summary="a foot that anchors and slides in 55-75 mm pipes (Fig. 4's margin) against its mass",
        run="softcrawl.studies.foot.optimise:run_request",
        default_material=None,
        options=frozenset(
            {"workers", "max_memory", "storage", "trials", "sampler", "seed", "simulator", "confirm", "wedge"}
        ),
        evaluators={"optimise-feet": "softcrawl.studies.foot.optimise_evaluator:evaluate_feet_design"},
        figure="pareto.png",
        tables=("trials.csv", "summary.md"),
        check="softcrawl.studies.foot.optimise:check_request",
        replot="softcrawl.studies.foot.optimise:replot_folder",
        report="softcrawl.studies.foot.optimise:report_block",
        help="optimise-feet: NSGA-II over the foot angle (30-120 deg), skirt thickness (1.5-3.5 mm) and "
        "hardness (50A-70A): maximise the worst-case anchoring margin of Fig. 4 over 55-75 mm pipes "
        "(--quick: 55 and 75 mm, quick mesh) and minimise the mass (studies/foot/optimise.py); the "
        "paper's foot is the first trial; needs DIR/identify/feet/feet.json. The rubber is a design "
        "variable, so it takes no --material.",
    ),
)
