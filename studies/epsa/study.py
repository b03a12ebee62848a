"""The actuator's studies, declared for the registry (`studies.registry`): the paper's sweeps of
Figs. 8 and 9, its static identification (Section VII-A), the constrained optimiser and the k_p
mismatch report."""

from softcrawl.studies.declaration import Study

_SWEEP = frozenset({"workers", "max_memory", "storage", "retry_failed", "simulator", "mesh_size", "fibers"})
_EVALUATORS = {
    "epsa": "softcrawl.studies.epsa.evaluator:evaluate_epsa",
    # chamber-radius and fiber-turns: optuna's best is the rule's design (sweep_objective.py)
    "epsa-rule": "softcrawl.studies.epsa.sweep_objective:evaluate_rule_sweep",
}
_RUN = "softcrawl.studies.epsa.grid_studies:run_request"
_REPLOT = "softcrawl.studies.epsa.grid_studies:replot_folder"
_TABLES = ("curves.csv", "summary.csv")
#: Trial budget of optimise-actuator (`softcrawl study --trials`), here so that `--help` reads it
#: without loading the optimiser.
DEFAULT_TRIALS, QUICK_TRIALS = 60, 20

STUDIES = (
    Study(
        name="chamber-radius",
        summary="paper Fig. 8: no fibers, r = 2-6 mm at 20-100 kPa",
        run=_RUN,
        options=_SWEEP,
        evaluators=_EVALUATORS,
        figure="chamber-radius.png",
        tables=_TABLES,
        rule=("chamber_radius",),
        replot=_REPLOT,
        help="chamber-radius (paper Fig. 8): no fibers, r = 2, 3, 4, 5, 6 mm, at 20, 40, 60, 80, 100 kPa.",
    ),
    Study(
        name="fiber-turns",
        summary="paper Fig. 9: r = 3 mm, N = 0-50 turns at 20-100 kPa",
        run=_RUN,
        options=_SWEEP,
        evaluators=_EVALUATORS,
        figure="fiber-turns.png",
        tables=_TABLES,
        rule=("fiber_turns",),
        replot=_REPLOT,
        help="fiber-turns (paper Fig. 9): r = 3 mm, N = 0, 10, 20, 25, 50, at 20, 40, 60, 80, 100 kPa.",
    ),
    Study(
        name="identify",
        summary="paper Section VII-A: k_p(P) and f_p(P) identified on FE results",
        run=_RUN,
        options=_SWEEP,
        evaluators=_EVALUATORS,
        figure="identification.png",
        tables=("curves.csv", "identification.csv", "identification.json"),
        replot="softcrawl.studies.epsa.identification:replot_folder",
        help="identify (Section VII-A): the Table 1 ePSA under weights W = 0, 0.5, 1 N on its guided top "
        "at 10-100 kPa; k_p(P) and f_p(P) fitted as the paper does and compared with eqs. 19-24 "
        "(studies/epsa/identification.py).",
    ),
    Study(
        name="optimise-actuator",
        summary="the paper's selection as a constrained optimisation (optuna TPE or NSGA-II)",
        run="softcrawl.studies.epsa.optimiser:run_request",
        options=frozenset(
            {
                "workers",
                "max_memory",
                "storage",
                "simulator",
                "mesh_size",
                "fibers",
                "trials",
                "sampler",
                "seed",
            }
        ),
        evaluators={"epsa-constrained": "softcrawl.studies.epsa.constrained_objective:evaluate_constrained"},
        figure="pareto.png",
        tables=("trials.csv", "optimum.json"),
        replot="softcrawl.studies.epsa.optimiser:replot_folder",
        help="optimise-actuator: the paper's selection as a constrained problem (optuna TPE or NSGA-II "
        "with trial constraints): the least Kevlar thread over r in {2..6} mm and N in 0..50 that "
        "withstands 100 kPa, keeps |dR| within 5 % of R0 and extends within the N rule's tolerance of "
        "the N = 50 design of its radius (studies/epsa/optimiser.py). The Table 1 design (r = 3, "
        "N = 20) is evaluated first and marked.",
    ),
    Study(
        name="kp-mismatch",
        summary="the identify studies under DIR against the confined and unconfined tube stiffness",
        run="softcrawl.studies.epsa.kp_mismatch:run_request",
        folder=".",  # DIR/identify/kp-mismatch.md, beside the identify runs it reads
        default_material=None,
        tables=("kp-mismatch.md", "kp-mismatch.json"),
        in_review=False,
        marker="kp-mismatch.md",
        help="kp-mismatch: the identify studies under DIR against the confined and unconfined tube "
        "stiffness (studies/epsa/kp_mismatch.py), DIR/identify/kp-mismatch.md.",
    ),
)
