"""The first screen of the design review (`studies.review.report`): the answer in a few lines.

Every number is read from the committed files: the design basis is the calibrated modulus of
results/calibration/calibration.json (the modulus that reproduces the prototype's measured
extension, so the one the design is judged with); its fiber-turns run gives what limits the Table 1
actuator and at what pressure; the mesh error, the calibration RMS, the verification count
(results/verify/verify.json) and the spread of the extension across the moduli of the table say how
sure. The robot and the crawl get one line each.
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl.studies.html import csv_rows, esc
from softcrawl.studies.plots.labels import material_label
from softcrawl.studies.review import report_sections as S

#: The basis when no calibration is committed: the preset the studies run with.
FALLBACK_BASIS = "ecoflex-00-50"
#: The crawl run the verdict quotes (results/crawl/RUN; `studies.robot_fe.report.CRAWL` makes it).
CRAWL_RUN = "forward-70-mu0.3-2cycles"


def _json(path: Path) -> dict | None:
    return json.loads(path.read_text()) if path.exists() else None


def design_basis(results: Path) -> tuple[str, str]:
    """The material the design is based on, and why (one sentence)."""
    c = _json(results / "calibration" / "calibration.json")
    if not c:
        return FALLBACK_BASIS, "the studies' preset (no calibration is committed)"
    material = f"{c['base_material']}@mu={c['mu_mpa']:.3g}"
    why = (
        "this modulus reproduces the prototype's extension "
        f"(eqs. 19-24, {', '.join(f'{p:g}' for p in c['pressures_kpa'])} kPa) within "
        f"{c['rms_error_mm']:.2g} mm RMS; the other moduli of the tables bound it"
    )
    return material, why


def _basis_row(results: Path, material: str) -> dict | None:
    folder = results / "fiber-turns" / material
    return S._limits_row(results, folder) if (folder / "spec.json").exists() else None


def _sure(results: Path, material: str) -> list[str]:
    out = []
    conv = results / "epsa-convergence" / f"convergence-{material}.csv"
    default = (
        next((r for r in csv_rows(conv) if S._num(r.get("mesh_size_mm")) == 5.0), None)
        if conv.exists()
        else None
    )
    if default:
        out.append(
            f"mesh error {abs(S._num(default['change_vs_finest_pct'])):.2g} % (h = 5 mm against the finest)"
        )
    c = _json(results / "calibration" / "calibration.json")
    if c:
        out.append(f"calibration {c['rms_error_mm']:.2g} mm RMS")
    v = _json(results / "verify" / "verify.json")
    if v:
        out.append(
            f"solver verification {sum(x['passed'] for x in v['cases'])} of {len(v['cases'])} cases pass"
        )
    rows = [S._limits_row(results, f) for f in S._materials(results, "fiber-turns")]
    ext = [r["extension there (mm)"] for r in rows if r["N = 20: highest pressure reached (kPa)"]]
    if len(ext) >= 2:
        out.append(
            f"across the {len(ext)} moduli of the tables the extension at the top pressure spans "
            f"{min(ext):.3g} to {max(ext):.3g} mm: the modulus matters more than anything else"
        )
    return out


def robot_verdict(results: Path) -> str:
    states = results / "robot-table1" / "states.csv"
    rows = csv_rows(states) if states.exists() else []
    if not rows:
        return "Robot: no committed run (section Robot names the command)."
    last = rows[-1]
    text = (
        f"Robot: the tied Table 1 robot converges up to P = ({float(last['P1_kpa']):g}, "
        f"{float(last['P2_kpa']):g}, {float(last['P3_kpa']):g}) kPa, bending "
        f"{float(last['theta_deg']):.3g} deg"
    )
    ws = sorted((results / "robot-workspace").glob("*/summary.json"))
    full = [s for s in (json.loads(p.read_text()) for p in ws) if s.get("mesh") == "default"] or [
        json.loads(p.read_text()) for p in ws
    ]
    if full:
        s = full[0]
        text += (
            f"; the constant-curvature model overstates its workspace {s['hull_ratio_cc_fe']:.3g}x "
            f"(median tip error {100 * s['median_err_cc_fe_rel']:.2g} %)"
        )
    return text + "."


def crawl_verdict(results: Path) -> str:
    s = _json(results / "crawl" / CRAWL_RUN / "summary.json")
    if not s:
        return "Crawl: no committed run (section Crawl names the command)."
    c = s["comparison"]
    return (
        f"Crawl: in the 70 mm pipe ({CRAWL_RUN}) the robot moves {c['direction']} {c['stride_mm']:.3g} mm "
        f"per cycle, {c['speed_mm_s']:.3g} mm/s at a {c['cycle_s']:g} s cycle, against Table 2's "
        f"{c['table2_mm_s']:g} mm/s and the analytic {c['analytic_fe_friction_mm_s']:.3g} mm/s with the "
        "FE friction."
    )


def headline(results: Path) -> str:
    """The answer block (HTML) that opens the page."""
    material, why = design_basis(results)
    items = [f"<b>Design basis</b>: {esc(material_label(material))}, because {esc(why)}."]
    row = _basis_row(results, material)
    if row:
        plain = row["no winding (N = 0): limit point (kPa)"]
        limit = row["N = 20: limit point (kPa)"]
        stretch = row["largest principal stretch"]
        items.append(
            "<b>What limits the Table 1 actuator</b> (r0 = 3 mm, N = 20): "
            + (
                f"without the winding the chamber balloons at a limit point at {plain:.3g} kPa; "
                if plain
                else "without the winding the chamber meets no limit point in the studied range; "
            )
            + f"with it the ramp reaches {row['N = 20: highest pressure reached (kPa)']:.3g} kPa "
            + ("with no limit point" if limit is None else f"with a limit point at {limit:.3g} kPa")
            + f", and the limit is the silicone's stretch: {stretch:.3g} at the top pressure "
            f"(extension {row['extension there (mm)']:.3g} mm, largest fiber force "
            f"{row['largest fiber force (N)']:.3g} N)."
        )
    sure = _sure(results, material)
    if sure:
        items.append("<b>How sure</b>: " + esc("; ".join(sure)) + ".")
    items.append(esc(robot_verdict(results)))
    items.append(esc(crawl_verdict(results)))
    return (
        '<div class="headline" id="headline"><h2>The answer</h2><ul>'
        + "".join(f"<li>{i}</li>" for i in items)
        + "</ul></div>"
    )
