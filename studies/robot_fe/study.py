"""The robot-level studies on the tied assembly, declared for the registry (`studies.registry`):
connecting rings (Fig. 11(c)), foot radius d (Section V-C) and the FE workspace (Fig. 11(d))."""

from softcrawl.studies.declaration import Study

#: The calibrated body modulus (`softcrawl calibrate`): the robot studies' default silicone.
ROBOT_MATERIAL = "ecoflex-00-50@mu=0.0638"
_OPTIONS = frozenset({"workers", "max_memory", "storage", "retry_failed", "simulator"})
_EVALUATORS = {"robot": "softcrawl.studies.robot_fe.robot_studies:evaluate_robot"}
_RUN = "softcrawl.studies.robot_fe.robot_studies:run_request"
_REPLOT = "softcrawl.studies.robot_fe.robot_studies:replot_folder"
_TABLES = ("curves.csv", "summary.csv", "decision.json")
_HELP = (
    " The robot studies run on the tied assembly (studies/robot_fe/robot_studies.py, workspace.py), "
    "write to DIR/robot-NAME/MATERIAL[-quick]/ and decide their Table 1 rows by the rules of "
    "studies/robot_fe/rules.py."
)

STUDIES = (
    Study(
        name="rings",
        summary="paper Fig. 11(c): the number of connecting rings",
        run=_RUN,
        folder="robot-rings",
        default_material=ROBOT_MATERIAL,
        options=_OPTIONS,
        evaluators=_EVALUATORS,
        figure="rings.png",
        tables=_TABLES,
        rule=("rings",),
        table1="softcrawl.studies.robot_fe.rows:rings_rows",
        replot=_REPLOT,
        help="rings (Fig. 11(c)): the robot with 1-5 connecting rings under equal and asymmetric "
        "chamber pressures." + _HELP,
    ),
    Study(
        name="foot-radius",
        summary="paper Section V-C: the foot radius d",
        run=_RUN,
        folder="robot-foot-radius",
        default_material=ROBOT_MATERIAL,
        options=_OPTIONS,
        evaluators=_EVALUATORS,
        figure="foot-radius.png",
        tables=_TABLES,
        rule=("foot_radius",),
        table1="softcrawl.studies.robot_fe.rows:foot_radius_rows",
        replot=_REPLOT,
        help="foot-radius (Section V-C): the robot with foot radius d = 11-16 mm under asymmetric "
        "chamber pressures.",
    ),
    Study(
        name="workspace",
        summary="paper Fig. 11(d): the FE workspace against the constant-curvature model",
        run="softcrawl.studies.robot_fe.workspace:run_request",
        folder="robot-workspace",
        default_material=ROBOT_MATERIAL,
        figure="workspace.png",
        tables=("workspace.csv", "summary.json"),
        replot="softcrawl.studies.robot_fe.workspace:replot_folder",
        in_review=False,
        marker="workspace.csv",
        help="workspace (Fig. 11(d)): the tip cloud of the FE robot against the constant-curvature "
        "model, on FE and on eq. 3 lengths (studies/robot_fe/workspace.py); shown in the review's "
        "robot section.",
    ),
)
