r"""`softcrawl study feet`: the FE crawl's speed over the feet's hardness and angle (paper Fig. 21).

Grid (Fig. 21's test, Section VII-C): hardness S in {70A, 60A, 50A} (the rubbers rubber-70a,
rubber-60a, rubber-50a: E from Gent's Shore-A relation, `softcrawl.materials`) x the included
skirt angle a in {120, 90, 60, 30} deg (`geometry.foot_design.FootDesign(angle=a)`: the tip stays
at 39 mm, the hub thickens to t / sin(a / 2) below 97 deg), 70 mm pipe, the forward crawl, the
"inflate" schedule at 100 kPa with 2 s cycles, 2 cycles. 70A and the widest angle come first, so
that a stopped run has decided as much of statement 2 as it could. --quick: S in {70A, 50A} x a in
{120, 60} deg, one cycle.

Friction: not chosen here. mu_smooth and mu_grooved are the identification's
(`studies.foot.identify.study_friction(OUT)`: OUT/identify/feet/feet.json, `softcrawl study
identify-feet`), with their flag ("identified", or "outside the sourced range: its nearer end");
every output states both. They are kept in spec.json, so a resumed study uses the same values.

Mesh: the revolved feet of `softcrawl crawl --quick`, 3 cells through the skirt, 4 insertion
steps, 4 sub-steps per schedule segment, at `geometry.foot_meshers.quick_sectors(foot)` =
max(24, ceil(48 cos(a / 2))) sectors: 24 at 120 deg (82k DOFs for the two feet against 164k at
48), 34 at 90, 42 at 60, 47 at 30 deg. 24 sectors everywhere was the plan, but below 120 deg the
contact faces' quadrature points cannot be placed in their curved P2 elements at 24 sectors (the
first run's 90, 60 and 30 deg points failed so; record 066 measured the least working counts), so
each angle gets the least count the project's rule gives. The default 48 sectors at every angle
would roughly double the unknowns of the 120 deg feet: twelve two-cycle crawls would not fit the
machine's hour. A wall budget per point (`WALL_S`) turns a stall in cut-backs into a recorded
failure. --wedge N: each foot is one wedge of 360/N deg, tied by cyclic symmetry
(`studies.foot.wedge`, docs/decisions/082-crawl-wedge.md), on quick_sectors(foot) rounded up to
a multiple of N (`point_sectors`: at N = 4, 24 / 36 / 44 / 48 at 120 / 90 / 60 / 30 deg), into
OUT/feet/D70[-quick]-wedgeN.

Per point (OUT/feet/D70[-quick]/points/S..-A..): `studies.crawl.files` writes states.csv,
cycles.csv, summary.json, crawl.png (no VTU), each converged state is checkpointed (a stopped point
resumes from it), and points/feet-S..-A...json keeps the point's figures: the first stride (cycle
1, from rest), the steady stride (cycle 2) and speed = steady stride / 2 s (with --quick's one cycle:
the first). The study: feet.csv (every column), summary.md (the table, the mu and their flags, the
statements' verdicts, the failures with their reasons) and feet.png (`studies.crawl.feet_plot`).
The statements' checks: `studies.crawl.feet_statements`.

The per-point crawl is `settings["simulate"]` (default `crawl_point`), called as
``simulate(setup, schedule, folder, quick) -> dict``; the tests give a fake.
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl import jsonio
from softcrawl.geometry.foot_design import FootDesign
from softcrawl.geometry.foot_meshers import quick_sectors
from softcrawl.paper import FIG21_CYCLE_S, FIG21_PIPE_MM
from softcrawl.studies.crawl.crawl_study import anchoring_slip_ratio
from softcrawl.studies.crawl.feet_plot import plot_feet
from softcrawl.studies.crawl.feet_statements import verdicts
from softcrawl.studies.crawl.files import run_and_write
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.resume import FOLDER, CrawlStore, crawl_options
from softcrawl.studies.crawl.schedule import preset
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.foot.identify import STUDY_FILE, study_friction
from softcrawl.studies.foot.wedge import wedge_sectors
from softcrawl.studies.html import esc, figure, markdown
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.sweeps.faults import SweepStopped
from softcrawl.studies.sweeps.memory import OutOfMemory
from softcrawl.studies.sweeps.spec import (
    Evaluation,
    StudyError,
    SweepSpec,
    load_callable,
    sweep_spec_from_file,
)
from softcrawl.studies.sweeps.sweep import run_sweep
from softcrawl.studies.sweeps.tables import number_cell, write_csv

NAME = "feet"
GRID = {"shore_a": (70.0, 60.0, 50.0), "angle_deg": (120.0, 90.0, 60.0, 30.0)}
QUICK_GRID = {"shore_a": (70.0, 50.0), "angle_deg": (120.0, 60.0)}
PRESSURE_KPA = 100.0
#: Wall budget of one point (s), insertion included: 1 h, the crawl study's budget for a default
#: point (`crawl_study.DEFAULT_WALL_S`). At the shared machine's load (10-14 on 2 cores) a worker gets
#: 10-40 % of a core, and the quick 120 deg crawl's single cycle took 12.5 min wall there; a point
#: still turning after an hour is stalled in cut-backs and ends as a recorded failure (its last
#: converged state in the reason) instead of holding a worker for the rest of the study.
WALL_S = 3600.0
SIMULATE = "softcrawl.studies.crawl.feet_study:crawl_point"


def material_of(shore_a: float) -> str:
    """The rubber preset of hardness `shore_a` (rubber-50a, rubber-60a, rubber-70a)."""
    return f"rubber-{float(shore_a):g}a"


def point_stem(params: dict) -> str:
    return f"S{float(params['shore_a']):g}-A{float(params['angle_deg']):g}"


def friction(out) -> dict:
    """The identified mu of both faces and their flags, read from OUT/identify/feet/feet.json."""
    found = study_friction(out)
    keys = ("mu_smooth", "mu_smooth_flag", "mu_grooved", "mu_grooved_flag")
    return {k: found[k] for k in keys} | {"identification": STUDY_FILE.as_posix()}


def point_sectors(foot: FootDesign, copies: int = 1) -> int:
    """quick_sectors(foot), rounded up to a multiple of the wedge count `copies`."""
    return wedge_sectors(quick_sectors(foot), copies)


def point_setup(params: dict, settings: dict) -> CrawlSetup:
    """The crawl of one grid point (module docstring)."""
    foot = FootDesign(angle=float(params["angle_deg"]))
    copies = int(settings.get("copies", 1))
    return CrawlSetup(
        pipe_diameter=FIG21_PIPE_MM,
        mu_smooth=float(settings["mu_smooth"]),
        mu_grooved=float(settings["mu_grooved"]),
        foot=foot,
        material=material_of(params["shore_a"]),
        insert_steps=4,
        steps=4,
        cycles=int(settings.get("cycles", 2)),
        max_wall_s=float(settings.get("wall_s", WALL_S)),
        sectors=point_sectors(foot, copies),
        copies=copies,
    )


def crawl_point(setup: CrawlSetup, schedule, folder: Path, quick: bool) -> dict:
    """One crawl through `studies.crawl.files` with checkpoints (resumed from the newest one)."""
    store = CrawlStore(folder / FOLDER, crawl_options(setup, schedule, setup.material))
    resumed = store.load()
    try:
        result, summary = run_and_write(
            setup,
            schedule,
            folder,
            quick=quick,
            vtu=False,
            store=store,
            resumed=resumed,
            insertion_cache=True,
        )
    except OutOfMemory as exc:
        exc.last_state = store.latest_summary()
        raise
    ratios = [anchoring_slip_ratio(c) for c in result.cycles]
    return {
        "converged": result.converged,
        "message": result.message,
        "strides_mm": list(result.strides),
        "fe_friction_n": summary["comparison"]["fe_friction_n"],
        "anchoring_slip_ratio": ratios[-1] if ratios else float("nan"),
        "n_dofs": result.n_dofs,
        "newton_iterations": result.newton_iterations,
        "wall_s": result.wall_s,
        "resumed_from": resumed.describe() if resumed is not None else "",
    }


def evaluate_feet(params: dict, fixed: dict, settings: dict) -> Evaluation:
    """One grid point: the crawl, then its first and steady stride (module docstring)."""
    setup = point_setup(params, settings)
    folder = Path(settings["out_dir"]) / "points" / point_stem(params)
    simulate = load_callable(settings.get("simulate", SIMULATE), parameter="simulator")
    folder.mkdir(parents=True, exist_ok=True)
    run = simulate(setup, _schedule(), folder, bool(settings.get("quick")))
    strides = [float(s) for s in run["strides_mm"]]
    nan = float("nan")
    steady = strides[1] if len(strides) > 1 else (strides[0] if strides and setup.cycles == 1 else nan)
    attrs = {k: v for k, v in run.items() if k != "strides_mm"} | {
        "material": setup.material,
        "hub_thickness_mm": setup.foot.hub_thickness,
        "strides_mm": ";".join(f"{s:.4f}" for s in strides),
        "first_stride_mm": strides[0] if strides else nan,
        "steady_stride_mm": steady,
        "speed_mm_s": steady / FIG21_CYCLE_S,
    }
    jsonio.write(
        Path(settings["out_dir"]) / "points" / f"feet-{point_stem(params)}.json", {"params": params} | attrs
    )
    if not run["converged"] or len(strides) < setup.cycles:
        return Evaluation(ok=False, attrs=attrs, message=run["message"])
    return Evaluation(ok=True, values=(attrs["speed_mm_s"],), attrs=attrs)


def study_folder(out, quick: bool, wedge: int = 1) -> Path:
    tail = ("-quick" if quick else "") + (f"-wedge{wedge}" if wedge > 1 else "")
    return Path(out) / NAME / f"D{FIG21_PIPE_MM:g}{tail}"


def run_feet_study(
    out, *, quick=False, wedge=1, storage=None, workers=1, progress=True, retry=False, simulate=None
) -> StudyOutcome:
    """Run (or resume) the study into OUT/feet/D70[-quick][-wedgeN]/ (module docstring)."""
    folder = study_folder(out, quick, wedge)
    settings = {"quick": bool(quick), "out_dir": str(folder), "cycles": 1 if quick else 2, "wall_s": WALL_S}
    settings |= {"copies": int(wedge)} if wedge > 1 else {}
    settings |= friction(out)
    if simulate is not None:
        settings["simulate"] = simulate
    folder.mkdir(parents=True, exist_ok=True)
    spec = SweepSpec(
        name=f"{NAME}-{'quick' if quick else 'default'}" + (f"-wedge{wedge}" if wedge > 1 else ""),
        grid=QUICK_GRID if quick else GRID,
        out_dir=str(folder),
        evaluator=NAME,
        settings=settings,
        storage=storage,
        # best = the fastest steady crawl; the study decides no Table 1 value, so best only ranks
        metric_names=("speed_mm_s",),
    )
    jsonio.write(folder / "spec.json", spec.to_dict())
    try:
        table = run_sweep(spec, workers=workers, progress=progress, retry=retry)
    except SweepStopped:  # stopped (a signal, the storage): the tables of what is done, then the stop
        write_study_outputs(spec, folder)
        raise
    return write_study_outputs(spec, folder, table)


def point_rows(spec, folder: Path) -> list[dict]:
    """One row per grid point from the stored point files (completed, failed or missing)."""
    rows = []
    for params in spec.points():
        path = folder / "points" / f"feet-{point_stem(params)}.json"
        data = (
            json.loads(path.read_text())
            if path.exists()
            else {"params": params, "message": _not_run(params, spec, folder)}
        )
        done = data.get("converged") and data.get("steady_stride_mm") == data.get("steady_stride_mm")
        status = "completed" if done else ("failed" if path.exists() else "missing")
        setup = point_setup(params, spec.settings)
        rows.append(
            {"shore_a": params["shore_a"], "angle_deg": params["angle_deg"], "status": status}
            | {"sectors": setup.sectors, "hub_thickness_mm": setup.foot.hub_thickness}
            | {k: v for k, v in data.items() if k != "params"}
            | {k: spec.settings[k] for k in ("mu_smooth", "mu_grooved")}
        )
    return rows


def _not_run(params: dict, spec, folder: Path) -> str:
    """Why a point has no result: never started, or stopped with a checkpoint to resume from."""
    setup = point_setup(params, spec.settings)
    store = CrawlStore(
        folder / "points" / point_stem(params) / FOLDER, crawl_options(setup, _schedule(), setup.material)
    )
    last = store.latest_summary() if store.checkpoints.states() else {}
    if not last:
        return "not run"
    return (
        f"stopped before its cycles ended, resumable from its last converged state: {last['states']} states, "
        f"stage {last.get('stage')!r} at t = {last.get('time_s', float('nan')):.3g} s"
    )


def _schedule():
    return preset("inflate", PRESSURE_KPA, FIG21_CYCLE_S)


def mu_text(settings: dict) -> str:
    """The friction line every output carries: both mu and their flags."""
    return (
        f"mu_smooth = {settings['mu_smooth']:g} ({settings['mu_smooth_flag']}); "
        f"mu_grooved = {settings['mu_grooved']:g} ({settings['mu_grooved_flag']}); "
        f"from {settings['identification']}"
    )


def mu_short(settings: dict) -> str:
    """The friction line of the figure: both mu and the head of their flags."""
    flags = {settings[f"mu_{f}_flag"].split(":")[0] for f in ("smooth", "grooved")}
    return (
        f"mu_smooth = {settings['mu_smooth']:g}, mu_grooved = {settings['mu_grooved']:g} "
        f"({'; '.join(sorted(flags))}; {settings['identification']})"
    )


def write_markdown(rows, settings: dict, path: Path) -> Path:
    """summary.md: the table, the friction, the statements' verdicts and the failures."""
    cycles = int(settings.get("cycles", 2))
    copies = int(settings.get("copies", 1))
    feet = (
        "the revolved feet at quick_sectors(angle) sectors"
        if copies == 1
        else f"the revolved feet at quick_sectors(angle) sectors rounded up to a multiple of {copies}, "
        f"each foot a 1/{copies} wedge tied by cyclic symmetry"
    )
    lines = [
        f"Fig. 21's test in FE: {FIG21_PIPE_MM:g} mm pipe, inflate {PRESSURE_KPA:g} kPa, {FIG21_CYCLE_S:g} s "
        f"cycles, {cycles} cycle(s); {feet}, 3 cells through the skirt.",
        "",
        f"Friction: {mu_text(settings)}.",
        "",
        "| hardness | angle (deg) | hub (mm) | sectors | status | first stride (mm) | steady stride (mm) "
        "| speed (mm/s) | FE friction (N) | anchoring slip ratio | wall (s) |",
        "|" + "---|" * 11,
    ]
    for r in rows:
        lines.append(
            f"| {r['shore_a']:g}A | {r['angle_deg']:g} | {number_cell(r.get('hub_thickness_mm'), '.2f')} "
            f"| {r['sectors']} | {r['status']} "
            f"| {number_cell(r.get('first_stride_mm'), '.3f')} "
            f"| {number_cell(r.get('steady_stride_mm'), '.3f')} "
            f"| {number_cell(r.get('speed_mm_s'), '.3f')} | {number_cell(r.get('fe_friction_n'), '.2f')} "
            f"| {number_cell(r.get('anchoring_slip_ratio'), '.3f')} | {number_cell(r.get('wall_s'), '.0f')} |"
        )
    lines += [
        "",
        "first stride: cycle 1, from rest; steady stride: cycle 2 (with one cycle: cycle 1); speed = "
        f"steady stride / {FIG21_CYCLE_S:g} s.",
        "",
        "Fig. 21's statements (studies/crawl/feet_statements.py):",
        "",
    ]
    lines += [f"- {v.text()}" for v in verdicts(rows)]
    failed = [r for r in rows if r["status"] != "completed"]
    if failed:
        lines += ["", "Not completed:", ""]
        lines += [
            f"- {r['shore_a']:g}A, {r['angle_deg']:g} deg: {r['status']}: {r.get('message', '')}"
            for r in failed
        ]
    path.write_text("\n".join(lines) + "\n")
    return path


def record_failures(spec, folder: Path, table) -> None:
    """A point whose evaluation raised (no point file): its point file, with the sweep's reason
    (the exception's line), so the tables and a later replot keep it."""
    for params, row in zip(spec.points(), table):
        path = folder / "points" / f"feet-{point_stem(params)}.json"
        if row.get("trial_status") == "failed" and row.get("reason") and not path.exists():
            jsonio.write(path, {"params": params, "converged": False, "message": row["reason"]})


def write_study_outputs(spec, folder: Path, table=()) -> StudyOutcome:
    """feet.csv, summary.md and feet.png from the stored point files (every grid point); `table`:
    the sweep's rows, whose failure reasons are kept for the points that raised."""
    record_failures(spec, folder, table)
    rows = point_rows(spec, folder)
    written = [
        write_csv(rows, folder / "feet.csv"),
        write_markdown(rows, spec.settings, folder / "summary.md"),
        plot_feet(rows, folder / "feet.png", mu_short(spec.settings)),
    ]
    lines = [
        f"{r['shore_a']:g}A, {r['angle_deg']:g} deg: {r['status']}; first stride "
        f"{number_cell(r.get('first_stride_mm'), '.3f')} mm, "
        f"speed {number_cell(r.get('speed_mm_s'), '.3f')} mm/s"
        for r in rows
    ]
    lines += [f"friction: {mu_text(spec.settings)}"] + [v.text() for v in verdicts(rows)]
    problems = tuple(
        f"feet {r['shore_a']:g}A, {r['angle_deg']:g} deg: {r['status']}: {r.get('message', '')}"
        for r in rows
        if r["status"] != "completed"
    )
    return StudyOutcome(tuple(lines), tuple(written), not problems, problems)


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study feet` (the registry's entry point)."""
    return run_feet_study(
        request.out, quick=request.quick, wedge=request.wedge or 1, **request.sweep_options()
    )


def check_request(request: StudyRequest) -> None:
    """The hardness is the study's grid; the friction must have been identified."""
    if request.material != "rubber-70a":
        raise StudyError("material", "the feet study's rubbers are its grid (rubber-50a, -60a, -70a)")
    if (request.wedge or 1) > 12:
        raise StudyError(
            "wedge", f"at most 12 (the 120 deg feet's 24 sectors in wedges of 2), got {request.wedge}"
        )
    friction(request.out)


def replot_folder(folder: Path) -> list[Path]:
    """feet.png from the stored point files."""
    folder = Path(folder)
    spec = sweep_spec_from_file(folder)
    return [plot_feet(point_rows(spec, folder), folder / "feet.png", mu_short(spec.settings))]


def report_block(folder: Path) -> str:
    """The study in the design review: its command, friction, verdicts, table and figure."""
    quick = "-quick" in folder.name
    wedge = folder.name.split("-wedge")[1] if "-wedge" in folder.name else ""
    options = (" --quick" if quick else "") + (f" --wedge {wedge}" if wedge else "")
    command = f"softcrawl study feet{options} --workers 2 --out results/"
    head = f"<h3>Feet: speed over hardness and angle (Fig. 21){' (quick)' if quick else ''}</h3>"
    body = f"<p>Command: <code>{esc(command)}</code></p>"
    if (folder / "summary.md").exists():
        body += markdown((folder / "summary.md").read_text())
    if (folder / "feet.png").exists():
        body += figure(folder / "feet.png", f"feet/{folder.name}/feet.png")
    return head + body
