r"""`softcrawl study predict-crawl`: Table 2 predicted with the identified feet, never re-fitted
(issue 29 step 6; docs/decisions/070-identify-feet.md, "The prediction").

Inputs, all held fixed: the feet identification that `softcrawl study identify-feet` committed
(DIR/identify/feet/feet.json: mu_smooth and mu_grooved, or the sourced range's end where no mu fits,
`studies.foot.identify.prediction_mu`), Gent's modulus of the Shore 70A preset, the paper's foot,
the prototype's axial law. For every pipe D in Table 2 (55-75 mm), two crawls of 2 cycles of the
"inflate" gait (100 kPa, 2 s), default feet mesh (48 sectors, 8 insertion steps):

    forward:   the paper's feet (skirts lean back), mu_smooth on the smooth face and rim,
               mu_grooved on the grooved face (it does not touch);
    backward:  both feet flipped (`studies.crawl.flipped`, record 067), the grooved face on the wall.

A run is taken from a folder that already holds it, when its summary.json's setup is this one:
with equal mu on both faces, the crawl study's point DIR/crawl/rubber-70a/points/D..-mu../
(forward) or a committed crawl DIR/crawl/{forward,backward}-D-mu..-2cycles/ (`softcrawl crawl`,
results/crawl/README.md); else DIR/predict-crawl/rubber-70a/{forward,backward}-D../, where it is
computed when missing, resumable from its checkpoints (`studies.crawl.resume`).

Compared, per run, in the direction of travel s = +1 (forward) or -1 (backward):

    v = s * (steady stride) / (cycle time)      steady stride: the mean of the cycles after the first
    error = (v - v_Table2) / v_Table2

The issue's goal: v > 0 in every pipe (above MIN_SPEED_MM_S, the contact's resolution), and
|error| <= 30 % at the diameters the identification did not use (all but 70 mm). The trend:
v(75) - v(60) against Table 2's. Outputs: prediction.csv, prediction.md, prediction.png
(`studies.crawl.plot_prediction`, with Fig. 21's statements where the feet study has run),
spec.json.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path

from softcrawl import jsonio
from softcrawl.paper import PIPE_DIAMETERS_MM, table2
from softcrawl.studies.crawl.files import MATERIAL, run_and_write
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.plot_prediction import plot_prediction
from softcrawl.studies.crawl.resume import FOLDER, CrawlStore, crawl_options
from softcrawl.studies.crawl.schedule import preset
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.foot.identify import study_friction
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.sweeps.tables import write_csv

NAME = "predict-crawl"
#: The issue's goal: within this share of Table 2 at the held-out diameters.
TOLERANCE = 0.30
#: A speed counts as "above 0" from this on, mm/s: a stride of 0.01 mm per 2 s cycle, the contact's
#: penetration tolerance (the Uzawa loop's 0.01 mm); the stalled crawls' strides are 1e-7 to 1e-3 mm.
MIN_SPEED_MM_S = 0.005
#: The diameter whose friction measurement (eq. 26) the identification used.
FIT_DIAMETER = 70.0
DIRECTIONS = {"forward": ("paper", 1.0), "backward": ("backward", -1.0)}
CYCLES = 2


@dataclass(frozen=True)
class Prediction:
    """One crawl against Table 2 (module docstring)."""

    pipe_diameter: float
    direction: str
    mu_smooth: float
    mu_grooved: float
    converged: bool
    first_stride_mm: float
    steady_stride_mm: float
    speed_mm_s: float  # in the direction of travel
    table2_mm_s: float
    error: float  # (speed - table2) / table2
    held_out: bool
    source: str  # the run's folder, relative to the results folder


def setup_for(diameter: float, direction: str, mu_smooth: float, mu_grooved: float) -> CrawlSetup:
    return CrawlSetup(
        pipe_diameter=float(diameter),
        mu_smooth=mu_smooth,
        mu_grooved=mu_grooved,
        feet=DIRECTIONS[direction][0],
        cycles=CYCLES,
    )


def _same_setup(summary: dict, setup: CrawlSetup) -> bool:
    """The stored run is this setup's (the wall-time budget is not part of the physics). A field
    that the stored run predates counts as its default (runs stored before it existed had it)."""
    stored = dict(summary.get("setup", {}))
    if not stored:
        return False
    wanted = asdict(setup)
    defaults = asdict(CrawlSetup())
    stored.pop("max_wall_s", None), wanted.pop("max_wall_s", None)
    return all(stored.get(k, defaults[k]) == v for k, v in wanted.items()) and set(stored) <= set(wanted)


def prediction_row(summary: dict, direction: str, source: str) -> Prediction:
    """A `Prediction` from a crawl's summary.json (module docstring's v and error)."""
    setup = summary["setup"]
    sign = DIRECTIONS[direction][1]
    strides = [float(s) for s in summary.get("strides_mm", [])]
    cycle_s = float(summary["schedule"]["cycle_s"])
    steady = sum(strides[1:]) / len(strides[1:]) if len(strides) > 1 else math.nan
    speed = sign * steady / cycle_s
    d = float(setup["pipe_diameter"])
    reference = table2(d, direction)
    return Prediction(
        pipe_diameter=d,
        direction=direction,
        mu_smooth=float(setup["mu_smooth"]),
        mu_grooved=float(setup["mu_grooved"]),
        converged=bool(summary.get("converged", False)) and len(strides) == CYCLES,
        first_stride_mm=strides[0] if strides else math.nan,
        steady_stride_mm=steady,
        speed_mm_s=speed,
        table2_mm_s=reference,
        error=(speed - reference) / reference,
        held_out=d != FIT_DIAMETER,
        source=source,
    )


def goal(rows: list[Prediction]) -> dict:
    """The issue's goal per direction: a speed above 0 in every pipe, and within TOLERANCE of
    Table 2 at every held-out diameter; and the 60 -> 75 mm trend against Table 2's."""
    out = {}
    for direction in DIRECTIONS:
        mine = {r.pipe_diameter: r for r in rows if r.direction == direction}
        if not mine:
            continue
        positive = [d for d, r in mine.items() if r.converged and r.speed_mm_s > MIN_SPEED_MM_S]
        within = [d for d, r in mine.items() if r.held_out and r.converged and abs(r.error) <= TOLERANCE]
        held = [d for d, r in mine.items() if r.held_out]
        trend = None
        if 60.0 in mine and 75.0 in mine:
            trend = {
                "fe_mm_s": mine[75.0].speed_mm_s - mine[60.0].speed_mm_s,
                "table2_mm_s": mine[75.0].table2_mm_s - mine[60.0].table2_mm_s,
            }
        out[direction] = {
            "positive_everywhere": len(positive) == len(mine),
            "positive": sorted(positive),
            "within_tolerance": sorted(within),
            "held_out": sorted(held),
            "met": len(positive) == len(mine) and len(within) == len(held),
            "trend_60_75": trend,
        }
    return out


def _run(setup: CrawlSetup, folder: Path, progress) -> dict:
    """Compute one crawl into `folder` (resumable from its checkpoints) and return its summary."""
    schedule = preset("inflate", 100.0, 2.0)
    store = CrawlStore(folder / FOLDER, crawl_options(setup, schedule, MATERIAL))
    resumed = store.load()
    _, summary = run_and_write(
        setup, schedule, folder, vtu=False, store=store, resumed=resumed, progress=progress,
        friction_source="the committed feet identification (docs/decisions/070-identify-feet.md)",
    )  # fmt: skip
    return summary


def find_or_run(
    results: Path, out: Path, setup: CrawlSetup, direction: str, progress=None, compute: bool = True
) -> tuple[dict | None, Path]:
    """The run of `setup`: found (module docstring), or computed into out/DIRECTION-D..; with
    `compute` False, (None, that folder) for a run not found."""
    candidates = [out / f"{direction}-D{setup.pipe_diameter:g}"]
    if setup.mu_smooth == setup.mu_grooved:
        d, mu = f"{setup.pipe_diameter:g}", f"{setup.mu_smooth:g}"
        candidates.insert(0, results / "crawl" / f"{direction}-{d}-mu{mu}-{CYCLES}cycles")
        if direction == "forward":
            candidates.insert(0, results / "crawl" / MATERIAL / "points" / f"D{d}-mu{mu}")
    for folder in candidates:
        path = folder / "summary.json"
        if path.is_file():
            summary = json.loads(path.read_text())
            if _same_setup(summary, setup):
                return summary, folder
    if not compute:
        return None, candidates[-1]
    return _run(setup, candidates[-1], progress), candidates[-1]


def missing_row(setup: CrawlSetup, direction: str) -> Prediction:
    """A run that was not computed: NaN speeds, not converged, source "not computed"."""
    nan = math.nan
    d = setup.pipe_diameter
    return Prediction(d, direction, setup.mu_smooth, setup.mu_grooved, False, nan, nan, nan,
                      table2(d, direction), nan, d != FIT_DIAMETER, "not computed")  # fmt: skip


def predict(results: Path, progress=None, compute: bool = True) -> tuple[list[Prediction], dict]:
    """Every Table 2 crawl with the identification under `results` (module docstring); with
    `compute` False, the runs not found are rows "not computed" instead of being run (a table of
    what exists, e.g. while the missing runs are computed elsewhere)."""
    found = study_friction(results)
    (mu_s, how_s), (mu_g, how_g) = ((found[f"mu_{f}"], found[f"mu_{f}_flag"]) for f in ("smooth", "grooved"))
    out = results / NAME / MATERIAL
    rows = []
    for d in PIPE_DIAMETERS_MM:
        for direction in DIRECTIONS:
            setup = setup_for(d, direction, mu_s, mu_g)
            summary, folder = find_or_run(results, out, setup, direction, progress, compute)
            if summary is None:
                rows.append(missing_row(setup, direction))
            else:
                rows.append(prediction_row(summary, direction, folder.relative_to(results).as_posix()))
    inputs = {
        "mu_smooth": mu_s,
        "mu_smooth_is": how_s.split(" (")[0],
        "mu_grooved": mu_g,
        "mu_grooved_is": how_g.split(" (")[0],
    }
    return rows, inputs


def write_tables(rows: list[Prediction], inputs: dict, folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    write_csv([asdict(r) for r in rows], folder / "prediction.csv")
    verdict = goal(rows)
    spec = {"study": NAME, "inputs": inputs, "goal": verdict, "tolerance": TOLERANCE, "cycles": CYCLES}
    (folder / "spec.json").write_text(jsonio.dumps(spec, indent=1) + "\n")
    lines = [
        "# Table 2 predicted with the identified feet (softcrawl study predict-crawl)",
        "",
        f"mu_smooth = {inputs['mu_smooth']:g} ({inputs['mu_smooth_is']}); "
        f"mu_grooved = {inputs['mu_grooved']:g} ({inputs['mu_grooved_is']}).",
        "",
        "| D (mm) | direction | FE speed (mm/s) | Table 2 (mm/s) | error | first stride (mm) | held out "
        "| run |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r.pipe_diameter:g} | {r.direction} | {_num(r.speed_mm_s, '.3f')} | {r.table2_mm_s:g} "
            f"| {_num(100 * r.error, '+.1f', ' %')} | {_num(r.first_stride_mm, '.3f')} "
            f"| {'yes' if r.held_out else 'no (fit)'} "
            f"| `{r.source}` |"
        )
    lines.append("")
    for direction, v in verdict.items():
        trend = v["trend_60_75"]
        text = (
            ""
            if trend is None
            else (
                f"; 60 -> 75 mm: FE {_num(trend['fe_mm_s'], '+.2f', ' mm/s')}, "
                f"Table 2 {trend['table2_mm_s']:+.2f} mm/s"
            )
        )
        n = sum(r.direction == direction for r in rows)
        lines.append(
            f"- {direction}: goal {'met' if v['met'] else 'not met'} (above {MIN_SPEED_MM_S:g} mm/s in "
            f"{len(v['positive'])} of {n} pipes; within {100 * TOLERANCE:g} % of Table 2 at "
            f"{len(v['within_tolerance'])} of {len(v['held_out'])} held-out diameters){text}"
        )
    (folder / "prediction.md").write_text("\n".join(lines) + "\n")
    return [folder / "prediction.csv", folder / "prediction.md", folder / "spec.json"]


def _num(value: float, spec: str, unit: str = "") -> str:
    return "n/a" if math.isnan(value) else f"{value:{spec}}{unit}"


def read_rows(folder: Path) -> list[Prediction]:
    """The committed table back as `Prediction`s (for replot and the review)."""
    with open(folder / "prediction.csv", newline="") as fh:
        return [Prediction(**{k: _parse(v) for k, v in r.items()}) for r in csv.DictReader(fh)]


def _parse(value: str):
    if value in ("True", "False"):
        return value == "True"
    try:
        return float(value)
    except ValueError:
        return value


def replot_folder(folder: Path) -> list[Path]:
    return [plot_prediction(read_rows(folder), folder.parent.parent, folder / "prediction.png")]


def run_request(request: StudyRequest) -> StudyOutcome:
    results = Path(request.out)
    rows, inputs = predict(results, progress=print if request.progress else None)
    folder = results / NAME / MATERIAL
    written = write_tables(rows, inputs, folder)
    written.append(plot_prediction(rows, results, folder / "prediction.png"))
    text = (folder / "prediction.md").read_text().splitlines()
    return StudyOutcome(tuple(text), tuple(written))
