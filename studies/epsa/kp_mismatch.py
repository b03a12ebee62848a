r"""Why is the FE actuator 1.2-6.5x stiffer against a weight (k_p) than the prototype (eqs. 19-24)?

Three explanations are tested on the identification studies under a results folder
(`softcrawl study identify`, Section VII-A on FE results) and written to
RESULTS/identify/kp-mismatch.md and .json (`softcrawl study kp-mismatch --out RESULTS`; the line-fiber
study is `softcrawl study identify --fibers lines --material ecoflex-00-50@mu=0.0638 --out TMP`
with TMP/identify/ecoflex-00-50@mu=0.0638/ copied to RESULTS/identify/lines/):

1. The winding's confinement. A nearly incompressible tube (radii a < R, length L, shear modulus
   mu) stretched axially by a small strain e has u_r = -e r/2 + D/r. Unconfined (D = 0) its axial
   stiffness is the rod's, k_free = 3 mu A / L with A = pi (R^2 - a^2). With its outer radius held
   (u_r(R) = 0: the near-hoop double helix, 20 turns over 100 mm at R = 9 mm, is 85 degrees from
   the axis and inextensible, so it keeps R), D = e R^2 / 2 and the strain energy per length is
   2 pi mu e^2 [3/4 (R^2 - a^2) + R^4/4 (1/a^2 - 1/R^2)], so

       k_confined = k_free (1 + R^2 / (3 a^2))          (= 4 k_free for R = 9, a = 3 mm).

   If the FE k_p at the lowest pressure is close to k_confined and the prototype's to k_free (or
   below), the FE's tied winding confines the wall and the prototype's does not.
2. The material law: the Yeoh fit scaled to the calibrated modulus (same initial mu, strain
   stiffening on top) against the calibrated Neo-Hookean; at the small strains of a weight at low
   pressure both have the same k_p if the law is not the cause.
3. The winding model: the embedded line fibers (`--fibers lines`, strands tied along lines only:
   the wall can bulge between them) against the smeared sheet.

The boundary condition at the loaded end (the guided ABS seal head, a clamped base) adds end
effects on top of (1); the comparison with the uniform-tube formula bounds them.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.outcome import StudyOutcome

#: The Table 1 actuator (mm).
OUTER_RADIUS, CHAMBER_RADIUS, LENGTH = 9.0, 3.0, 100.0
#: The identification studies compared (label -> (identification.csv under RESULTS, initial mu)):
#: explanation 1 on the two Neo-Hookean moduli, 2 (Yeoh at the calibrated modulus) and 3 (lines).
CASES = {
    "sheet, Neo-Hookean mu = 0.0638 (calibrated)": (
        "identify/ecoflex-00-50@mu=0.0638/identification.csv",
        0.0638,
    ),
    "sheet, Neo-Hookean mu = 0.03 (literature)": ("identify/ecoflex-00-50/identification.csv", 0.03),
    "sheet, Yeoh fit scaled to mu = 0.0638": (
        "identify/ecoflex-00-50-yeoh@mu=0.0638/identification.csv",
        0.0638,
    ),
    "lines, Neo-Hookean mu = 0.0638": ("identify/lines/ecoflex-00-50@mu=0.0638/identification.csv", 0.0638),
}


def tube_stiffness_n_per_m(mu_mpa: float, a=CHAMBER_RADIUS, R=OUTER_RADIUS, L=LENGTH) -> dict:
    """(k_free, k_confined) of explanation 1, in N/m."""
    k_free = 3.0 * mu_mpa * math.pi * (R * R - a * a) / L * 1e3
    return {"k_free": k_free, "k_confined": k_free * (1.0 + R * R / (3.0 * a * a))}


def _first_row(path: Path) -> dict | None:
    try:
        with open(path) as fh:
            return next(csv.DictReader(fh))
    except (OSError, StopIteration):
        return None


def kp_mismatch(results, cases: dict[str, tuple[str, float]]) -> dict:
    """`cases`: label -> (identification.csv path relative to `results`, initial mu in MPa)."""
    rows = []
    for label, (rel, mu) in cases.items():
        first = _first_row(Path(results) / rel)
        if first is None:
            rows.append({"case": label, "source": rel, "missing": True})
            continue
        k_fe = float(first["k_p_fe_n_per_m"])
        theory = tube_stiffness_n_per_m(mu)
        proto = [float(first[f"k_p_epsa{i}_n_per_m"]) for i in (1, 2, 3)]
        rows.append(
            {
                "case": label,
                "source": rel,
                "pressure_kpa": float(first["pressure_kpa"]),
                "mu_mpa": mu,
                "k_p_fe": k_fe,
                "k_free": theory["k_free"],
                "k_confined": theory["k_confined"],
                "fe_over_confined": k_fe / theory["k_confined"],
                "fe_over_free": k_fe / theory["k_free"],
                "prototype_k_p": proto,
                "fe_over_prototype": k_fe / (sum(proto) / 3.0),
            }
        )
    return {"rows": rows, "confinement_factor": 1.0 + OUTER_RADIUS**2 / (3.0 * CHAMBER_RADIUS**2)}


def write_report(results, cases=None) -> tuple[Path, Path]:
    cases = CASES if cases is None else cases
    record = kp_mismatch(results, cases)
    folder = Path(results) / "identify"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "kp-mismatch.json").write_text(json.dumps(record, indent=2) + "\n")
    lines = [
        "# The k_p mismatch: FE against the prototype (eqs. 19-24)",
        "",
        "Generated by `studies/epsa/kp_mismatch.py` from the identification studies named below "
        "(lowest pressure of each, where the weight's strain is smallest). Theory: a nearly "
        "incompressible tube has k_free = 3 mu A / L unconfined and "
        f"k_confined = k_free (1 + R^2/(3 a^2)) = {record['confinement_factor']:.3g} k_free with its "
        "outer radius held by an inextensible hoop winding (module docstring).",
        "",
        "| case | P (kPa) | mu (MPa) | FE k_p (N/m) | k_free | k_confined | FE / k_confined | "
        "prototype k_p (ePSA 1-3) | FE / prototype |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in record["rows"]:
        if r.get("missing"):
            lines.append(f"| {r['case']} | - | - | no study at `{r['source']}` | | | | | |")
            continue
        proto = ", ".join(f"{k:.0f}" for k in r["prototype_k_p"])
        lines.append(
            f"| {r['case']} | {r['pressure_kpa']:g} | {r['mu_mpa']:.4g} | {r['k_p_fe']:.0f} | "
            f"{r['k_free']:.0f} | {r['k_confined']:.0f} | {r['fe_over_confined']:.2f} | {proto} | "
            f"{r['fe_over_prototype']:.1f} |"
        )
    path_md = folder / "kp-mismatch.md"
    path_md.write_text("\n".join(lines) + "\n")
    return path_md, folder / "kp-mismatch.json"


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study kp-mismatch`: reads the identify studies under --out (no FE)."""
    return StudyOutcome(written=tuple(write_report(request.out)))
