r"""`softcrawl study crawl`: stride and anchoring of the FE crawl over pipe diameter and friction.

Grid: pipe diameter D in {55, 60, 65, 70, 75} mm x mu in {0.3, 0.5} (the same mu on the smooth
and the grooved face: `studies.foot.contact_studies` states why 0.5 and the groove study's
lower value 0.3); the "inflate" schedule at 100 kPa, 2 s cycles, 2 cycles, the paper's feet.
The feet: the revolved mesh (`studies.crawl.mesh`), 48 sectors.
--quick: D in {60, 65, 70} x mu in {0.3, 0.5} (mu outermost, so the mu = 0.3 points, which
complete a cycle at 70 mm, come first), 4 insertion steps, 24 sectors, one cycle, and a wall-time budget of
QUICK_WALL_S per point (DEFAULT_WALL_S without --quick), insertion included: a stall in
cut-backs (the retraction at mu = 0.5 before the rounded cone, docs/decisions/054-crawl-tetwild.md) must end
as a
recorded failure, not as a point that never returns. Each point runs
`studies.crawl.files` into OUT/points/D..-mu../ (states.csv, cycles.csv, summary.json,
crawl.png; no VTU) and its summary is kept in points/crawl-D..-mu...json, so a stopped study
resumes and a diverged point is recorded with the last converged state in its reason. Each
converged state of a point is written to points/D..-mu../checkpoints (`studies.crawl.resume`):
a point handed back (Ctrl-C, SIGTERM, a dead worker) restarts from its last converged state
when it is evaluated again, and a point stopped by the memory watchdog (`--max-memory`) names
that state in its failure (``last_state``).

The insertion is frictionless, so the two friction values of one diameter share it: each point
starts from the cached inserted state of its diameter (`studies.crawl.insertion`; the first point
of a diameter computes and writes it, a second worker asking for it meanwhile waits for it), and
records ``insertion_cached``; its ``wall_s`` is then the run after the insertion.

Figures per point: the stride of each cycle and the steady stride (cycles after the first), the
speed, and the anchoring slip ratio of the extension phase, |anchoring foot's motion| / (|rear| +
|front| motion): 0 when the rear foot holds perfectly, 0.5 when both feet move alike.
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl import jsonio
from softcrawl.paper import PIPE_DIAMETERS_MM
from softcrawl.studies.crawl.files import run_and_write
from softcrawl.studies.crawl.mesh import QUICK_SECTORS
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.outputs import steady_stride
from softcrawl.studies.crawl.plot import plot_crawl_study
from softcrawl.studies.crawl.resume import FOLDER, CrawlStore, crawl_options
from softcrawl.studies.crawl.schedule import preset
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.sweeps.memory import OutOfMemory
from softcrawl.studies.sweeps.spec import Evaluation, StudyError, SweepSpec, sweep_spec_from_file
from softcrawl.studies.sweeps.sweep import run_sweep
from softcrawl.studies.sweeps.tables import number_cell, write_csv

NAME = "crawl"
GRID = {"pipe_diameter": PIPE_DIAMETERS_MM, "mu": (0.3, 0.5)}
QUICK_GRID = {"mu": (0.3, 0.5), "pipe_diameter": (60.0, 65.0, 70.0)}
#: 20 min: the whole mu = 0.3 cycle at 70 mm took 506 s with 3-4 FE jobs on the 2 cores.
QUICK_WALL_S = 1200.0
#: 1 h for a default point (8 insertion steps, two cycles): a stall in the insertion or a cycle
#: ends as a recorded failure instead of holding a worker indefinitely.
DEFAULT_WALL_S = 3600.0
EVALUATOR = "crawl"  # its registry name (studies/crawl/study.py)


def point_stem(params: dict) -> str:
    return f"D{float(params['pipe_diameter']):g}-mu{float(params['mu']):g}"


def anchoring_slip_ratio(cycle: dict) -> float:
    rear, front = abs(cycle["extend_rear_moved_mm"]), abs(cycle["extend_front_moved_mm"])
    return rear / (rear + front) if rear + front > 0 else float("nan")


def evaluate_crawl(params: dict, fixed: dict, settings: dict):
    quick = bool(settings.get("quick"))
    mu = float(params["mu"])
    setup = CrawlSetup(
        pipe_diameter=float(params["pipe_diameter"]),
        mu_smooth=mu,
        mu_grooved=mu,
        insert_steps=4 if quick else 8,
        steps=4,
        cycles=int(settings.get("cycles", 2)),
        max_wall_s=QUICK_WALL_S if quick else DEFAULT_WALL_S,
        sectors=QUICK_SECTORS if quick else None,
        copies=int(settings.get("copies", 1)),
    )
    folder = Path(settings["out_dir"]) / "points" / point_stem(params)
    schedule = preset("inflate", 100.0, 2.0)
    store = CrawlStore(folder / FOLDER, crawl_options(setup, schedule, setup.material))
    resumed = store.load()  # another version's checkpoint: a failed point naming it (CheckpointError)
    try:
        result, summary = run_and_write(
            setup, schedule, folder, quick=quick, vtu=False, store=store, resumed=resumed,
            insertion_cache=settings.get("insertion_cache", True),
        )  # fmt: skip
    except OutOfMemory as exc:
        exc.last_state = store.latest_summary()
        raise
    ratios = [anchoring_slip_ratio(c) for c in result.cycles]
    attrs = {
        "converged": result.converged,
        "message": result.message,
        "strides_mm": ";".join(f"{s:.4f}" for s in result.strides),
        "steady_stride_mm": steady_stride(result),
        "speed_mm_s": summary["comparison"]["speed_mm_s"],
        "table2_mm_s": summary["comparison"]["table2_mm_s"],
        "analytic_paper_friction_mm_s": summary["comparison"]["analytic_paper_friction_mm_s"],
        "analytic_fe_friction_mm_s": summary["comparison"]["analytic_fe_friction_mm_s"],
        "anchoring_slip_ratio": ratios[-1] if ratios else float("nan"),
        "fe_friction_n": summary["comparison"]["fe_friction_n"],
        "ground_max_n": result.ground_max_n,
        "momentum_max_n": result.momentum_max_n,
        "n_dofs": result.n_dofs,
        "newton_iterations": result.newton_iterations,
        "wall_s": result.wall_s,
        "resumed_from": resumed.describe() if resumed is not None else "",
        "insertion_cached": summary["insertion_cached"],
    }
    jsonio.write(
        Path(settings["out_dir"]) / "points" / f"crawl-{point_stem(params)}.json", {"params": params} | attrs
    )
    if not result.converged:
        return Evaluation(ok=False, attrs=attrs, message=result.message)
    return Evaluation(ok=True, values=(attrs["steady_stride_mm"],), attrs=attrs)


def run_crawl_study(
    out, *, quick=False, wedge=1, storage=None, workers=1, progress=True, retry=False
) -> StudyOutcome:
    """The study into OUT/crawl/rubber-70a[-quick][-wedgeN] (a wedge of the feet, `wedge` > 1, has
    its own folder and sweep: its points are the whole feet's within the solver's and the contact
    tolerance's path dependence, docs/decisions/083-exact-wedge.md)."""
    tail = ("-quick" if quick else "") + (f"-wedge{wedge}" if wedge > 1 else "")
    folder = Path(out) / NAME / f"rubber-70a{tail}"
    folder.mkdir(parents=True, exist_ok=True)
    spec = SweepSpec(
        name=f"{NAME}-{'quick' if quick else 'default'}" + (f"-wedge{wedge}" if wedge > 1 else ""),
        grid=QUICK_GRID if quick else GRID,
        out_dir=str(folder),
        evaluator=EVALUATOR,
        settings={"quick": bool(quick), "out_dir": str(folder), "cycles": 1 if quick else 2}
        | ({"copies": int(wedge)} if wedge > 1 else {}),
        storage=storage,
        # best = the longest steady stride among points that converged (a failed point is FAIL);
        # the crawl study decides no Table 1 value, so best only ranks (decision 063)
        metric_names=("steady_stride_mm",),
    )
    jsonio.write(folder / "spec.json", spec.to_dict())
    run_sweep(spec, workers=workers, progress=progress, retry=retry)
    return write_study_outputs(spec, folder)


def sliding_feet(cycles_csv: Path) -> dict:
    """Which feet slid (slipping share >= crawl_outputs.SLID_SHARE) in the last cycle's extension
    and retraction: "rear", "front", "both" or "none"; empty without a completed cycle. The
    anchoring slip ratio alone cannot tell a foot that anchors from a pair that does not move."""
    import csv

    if not cycles_csv.exists():
        return {}
    with open(cycles_csv, newline="") as fh:
        last = list(csv.DictReader(fh))[-1]
    out = {}
    for phase in ("extend", "retract"):
        slid = [f for f in ("rear", "front") if last[f"{phase}_{f}_slid"] == "True"]
        out[f"{phase}_slid"] = "both" if len(slid) == 2 else (slid[0] if slid else "none")
    return out


def write_markdown(rows, path: Path) -> Path:
    """summary.md: the study's table for a reader (summary.csv has every column)."""
    head = (
        "| D (mm) | mu | status | stride (mm) | speed (mm/s) | Table 2 (mm/s) | analytic, paper's "
        "friction (mm/s) | analytic, FE friction (mm/s) | FE friction (N) | anchoring slip ratio | "
        "slid: extend / retract | wall (s) |"
    )
    lines = [head, "|" + "---|" * 12]
    for r in rows:
        lines.append(
            f"| {r['pipe_diameter']:g} | {r['mu']:g} | {r['status']} "
            f"| {number_cell(r.get('steady_stride_mm'), '.3f')} "
            f"| {number_cell(r.get('speed_mm_s'), '.3f')} | {number_cell(r.get('table2_mm_s'), 'g')} "
            f"| {number_cell(r.get('analytic_paper_friction_mm_s'), '.2f')} "
            f"| {number_cell(r.get('analytic_fe_friction_mm_s'), '.2f')} "
            f"| {number_cell(r.get('fe_friction_n'), '.2f')} "
            f"| {number_cell(r.get('anchoring_slip_ratio'), '.3f')} "
            f"| {r.get('extend_slid', '-')} / {r.get('retract_slid', '-')} "
            f"| {number_cell(r.get('wall_s'), '.0f')} |"
        )
    lines += [
        "",
        "stride: steady stride (the first cycle's from rest with one cycle); speed = stride / 2 s. "
        "FE friction: the largest axial wall friction on a foot while the pressures rise: the sliding "
        "foot's resistance where a foot slid, a lower bound of both feet's where none slid. Anchoring "
        "slip ratio: |rear| / (|rear| + |front|) motion in the extension (0: the rear anchors).",
    ]
    lines += [""] + [
        f"- D = {r['pipe_diameter']:g}, mu = {r['mu']:g}: {r['message']}"
        for r in rows
        if r["status"] != "completed"
    ]
    path.write_text("\n".join(lines) + "\n")
    return path


def point_rows(spec, folder: Path) -> list[dict]:
    """One row per grid point from the stored point files (done, failed or missing)."""
    rows = []
    for params in spec.points():
        path = folder / "points" / f"crawl-{point_stem(params)}.json"
        data = json.loads(path.read_text()) if path.exists() else {"params": params, "message": "not run"}
        status = "completed" if data.get("converged") else ("failed" if path.exists() else "missing")
        row = dict(params) | {"status": status} | {k: v for k, v in data.items() if k != "params"}
        rows.append(row | sliding_feet(folder / "points" / point_stem(params) / "cycles.csv"))
    return rows


def write_study_outputs(spec, folder: Path) -> StudyOutcome:
    """summary.csv and crawl-study.png from the stored point files (every grid point, done or not)."""
    rows = point_rows(spec, folder)
    written = [
        write_csv(rows, folder / "summary.csv"),
        plot_crawl_study(rows, folder / "crawl-study.png"),
        write_markdown(rows, folder / "summary.md"),
    ]
    lines = [
        f"D = {r['pipe_diameter']:g} mm, mu = {r['mu']:g}: {r['status']}; "
        f"strides {r.get('strides_mm') or '-'} mm, "
        f"anchoring slip ratio {number_cell(r.get('anchoring_slip_ratio'), '.3g')}, "
        f"slid (extend / retract) {r.get('extend_slid', '-')} / {r.get('retract_slid', '-')}"
        for r in rows
    ]
    problems = tuple(
        f"crawl D = {r['pipe_diameter']:g}, mu = {r['mu']:g}: {r['status']}: {r.get('message', '')}"
        for r in rows
        if r["status"] != "completed"
    )
    return StudyOutcome(tuple(lines), tuple(written), not problems, problems)


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study crawl` (the registry's entry point)."""
    return run_crawl_study(
        request.out, quick=request.quick, wedge=request.wedge or 1, **request.sweep_options()
    )


def check_request(request: StudyRequest) -> None:
    """The crawl study's feet are the foot study's rubber."""
    if request.material != "rubber-70a":
        raise StudyError("material", "the crawl study's feet are rubber-70a (the foot study's rubber)")
    sectors = QUICK_SECTORS if request.quick else 48
    wedge = request.wedge or 1
    if sectors % wedge or sectors // wedge < 2:
        raise StudyError(
            "wedge", f"must divide the feet's {sectors} sectors and leave at least 2, got {wedge}"
        )


def replot_folder(folder: Path) -> list[Path]:
    """crawl-study.png from the stored point files."""
    folder = Path(folder)
    return [plot_crawl_study(point_rows(sweep_spec_from_file(folder), folder), folder / "crawl-study.png")]
