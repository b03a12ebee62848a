"""`softcrawl study identify-feet`: the friction coefficients of the feet fitted to eq. 26's two
measurements in the 70 mm pipe, one sliding foot's share (eq. 26 / 3, record 062)
(`studies.foot.identify`), written to DIR/identify/feet/feet.json (the file the prediction
commands read) and DIR/identify/feet/feet.md (the values, their sourced ranges,
every solve and the residuals).

One solve is the foot of the foot study (revolved mesh, Shore 70A, angle 120 deg; `--quick`: 24
sectors, 5 mm of drag) inserted into the 70 mm pipe without friction and dragged with friction mu
on both faces: forward for mu_smooth (the smooth front face is the only one on the wall, record
062); for mu_grooved the flipped foot of the backward crawl (`run_foot(flipped=True)`, record 067:
the grooved face carries the whole normal force) dragged backward, the way it slides in a
backward crawl.
"""

from __future__ import annotations

import math
from pathlib import Path

from softcrawl import jsonio
from softcrawl.analytic.pipe import Pipe
from softcrawl.files import write_text_atomic
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.foot import identify
from softcrawl.studies.foot.model import run_foot
from softcrawl.studies.outcome import StudyOutcome

FOLDER = "identify"
#: The foot study's drag (8 mm, 8 steps) and the quick one (5 mm, 5 steps, 24 sectors).
SETTINGS = {"drag_mm": 8.0, "drag_steps": 8, "sectors": None, "angle": 120.0}
QUICK_SETTINGS = {"drag_mm": 5.0, "drag_steps": 5, "sectors": 24, "angle": 120.0}


def drag_resistance(settings: dict, direction: str = "forward", flipped: bool = False):
    """mu -> the largest resistance (N) of a drag of the foot (`flipped`: the flipped foot) in the
    70 mm pipe (NaN: the drag did not converge)."""
    design = FootDesign(angle=float(settings["angle"]))
    mesh = mesh_foot_with(design, "revolved", sectors=settings["sectors"]).to_skfem(2)
    material = solid_law(get_material(identify.MATERIAL), hyperelastic_only=True)
    pipe = Pipe(diameter=identify.DIAMETER_MM)

    def resistance(mu: float) -> float:
        r = run_foot(
            mesh,
            material,
            design,
            pipe,
            mu_smooth=mu,
            mu_grooved=mu,
            drag=float(settings["drag_mm"]),
            drag_steps=int(settings["drag_steps"]),
            directions=(direction,),
            flipped=flipped,
            max_wall_s=None,
        )
        curve = r.forward if direction == "forward" else r.backward
        ok = curve is not None and curve.converged and curve.resistance.size
        print(f"  mu = {mu:.4f}: F_{direction} = {curve.peak if ok else math.nan:.3f} N", flush=True)
        return curve.peak if ok else math.nan

    return resistance


def write(result: identify.FeetIdentification, folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    json_path = jsonio.write(folder / "feet.json", result.to_dict())
    lines = [
        "# The feet's inputs, identified (`softcrawl study identify-feet`)",
        "",
        f"Material {result.material}: Shore {result.shore_a:g}A, E = {result.youngs_mpa:.3f} MPa from "
        f"{result.youngs_source} (published relation, not fitted).",
        "",
        f"Friction coefficients fitted in the {result.diameter_mm:g} mm pipe to the sliding resistance "
        "of one foot, eq. 26 / 3 (docs/decisions/062-crawl-reconciliation.md), inside the sourced range "
        f"{result.mu_range[0]:g}-{result.mu_range[1]:g} ({result.mu_source}). Table 2 and Fig. 21 are "
        "not read: they are held out.",
        "",
        "| face | target F = eq. 26 / 3 (N) | mu | F at mu (N) | residual (N) | in range "
        "| solves (mu: F) | note |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for f in result.fits:
        solves = "; ".join(f"{m:.4f}: {v:.2f}" for m, v in f.solves)
        mu = "-" if f.mu is None else f"{f.mu:.4f}"
        lines.append(
            f"| {f.face} | {f.target_n:g} | {mu} | {f.resistance_n:.3f} | {f.residual_n:+.3f} | "
            f"{'yes' if f.in_range else 'no'} | {solves} | {f.note} |"
        )
    lines += ["", "Settings: " + ", ".join(f"{k} = {v}" for k, v in result.settings.items()), ""]
    md_path = write_text_atomic(folder / "feet.md", "\n".join(lines))
    return [json_path, Path(md_path)]


def run_request(request: StudyRequest) -> StudyOutcome:
    settings = dict(QUICK_SETTINGS if request.quick else SETTINGS)
    backward = drag_resistance(settings, "backward", flipped=True)
    forward = drag_resistance(settings, "forward")
    result = identify.identify(forward, backward, settings | {"quick": request.quick})
    folder = Path(request.out) / FOLDER / ("feet-quick" if request.quick else "feet")
    written = write(result, folder)
    lines = tuple(
        f"mu_{f.face} = {'-' if f.mu is None else f'{f.mu:.4f}'} (F = {f.resistance_n:.2f} N against "
        f"{f.target_n:g} N{'' if f.in_range else ', outside the sourced range'})"
        for f in result.fits
    )
    return StudyOutcome(lines, tuple(written), ok=all(f.mu is not None for f in result.fits))
