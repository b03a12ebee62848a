"""The summary of results/table1.md: one row per material assumption, and which conclusions of the
paper survive which assumption.

A material's role comes from its name and the committed studies: `ecoflex-00-50` is the
literature Neo-Hookean value, `-fit` the tensile Neo-Hookean fit (strain 0-100 %), `-yeoh` and
`-gent` the full-range fits, `NAME@mu=V` the calibrated modulus when V is the one of
`results/calibration/calibration.json`, and the window centres of
`results/paper-material/paper-material.json` the paper's-material window.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

from softcrawl.materials import get_material
from softcrawl.studies.epsa import rules

PAPER = {"chamber_radius": 3.0, "fiber_turns": 20.0}
#: "The ePSA length with an air chamber radius of r = 4 mm or r = 2 mm fluctuates" (Section V-A).
PAPER_FLUCTUATING_RADII = (2.0, 4.0)
#: The order of the assumptions in the summary.
ROLE_ORDER = ("literature", "tensile", "calibrated", "Yeoh fit", "Gent fit", "paper's-material")
#: The literature shear modulus of Ecoflex 00-50 (preset `ecoflex-00-50`, docs/decisions/001-materials.md).
LITERATURE_MU = 0.030


def material_role(results: str | Path, material: str) -> str:
    base, _, override = material.partition("@")
    centres = _json(Path(results) / "paper-material" / "paper-material.json").get("centres", {})
    for law, c in centres.items():
        if c.get("material") == material:
            lo, hi = c["window_mu"]
            return f"paper's-material window centre ({law}, window mu {lo:.3g}-{hi:.3g} MPa)"
    calibrated = _json(Path(results) / "calibration" / "calibration.json").get("mu_mpa")
    if override.startswith("mu=") and calibrated is not None:
        try:
            if math.isclose(float(override[3:]), calibrated, rel_tol=2e-3):
                return "calibrated to the prototype (eqs. 19-24)"
        except ValueError:
            pass
    if override:
        return "rescaled preset"
    return {
        "ecoflex-00-50": "literature Neo-Hookean",
        "ecoflex-00-50-fit": "tensile Neo-Hookean fit (strain 0-100 %)",
        "ecoflex-00-50-yeoh": "Yeoh fit (full tensile range)",
        "ecoflex-00-50-gent": "Gent fit (full tensile range)",
    }.get(base, "other")


def _json(path: Path) -> dict:
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return {}


def _law(material: str) -> str:
    try:
        return get_material(material).law_label
    except Exception:  # noqa: BLE001 - a material unknown to materials
        return "unknown law"


def paper_note(param: str, sel: rules.Selection) -> str:
    """Why the paper chose otherwise, where the paper says it (the disagreement's reason)."""
    v = sel.value
    if v is None or param not in PAPER or abs(v - PAPER[param]) < 1e-9:
        return ""
    if param == "chamber_radius" and v in PAPER_FLUCTUATING_RADII:
        return f"; the paper excluded r = {v:g} as fluctuating, which this FE does not show (monotone length)"
    if param == "fiber_turns" and v < PAPER[param]:
        return (
            f"; here N = {v:g} already differs little from N = 50, where the paper's Fig. 9 shows fewer "
            "turns reinforcing less"
        )
    if param == "fiber_turns":
        return (
            f"; the paper's N = 20 falls short of N = 50 by more than {rules.SIMILAR_EXTENSION_REL:.0%} here"
        )
    return ""


def _order(results, m: str) -> int:
    role = material_role(results, m)
    return next(
        (i for i, key in enumerate(ROLE_ORDER) if role.startswith(key) or key in role), len(ROLE_ORDER)
    )


def _verdict(sel: rules.Selection, param: str) -> str:
    if sel.value is None:
        return f"- ({sel.status})"
    mark = "agree" if abs(sel.value - PAPER[param]) < 1e-9 else "disagree"
    return f"{sel.value:g} ({mark})"


def markdown_cell(text: str) -> str:
    """`text` as one Markdown table cell: pipes escaped, line breaks as spaces."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def summary_table(
    results, materials: Sequence[str], selections: Mapping[str, Mapping], quick=frozenset()
) -> list[str]:
    """One row per material; `quick`: materials whose studies ran on the quick mesh."""
    lines = [
        "## Summary per material assumption",
        "",
        "| assumption | material and law | r0 (paper 3 mm) | why | N (paper 20) | why "
        "| fibers closer to linear |",
        "|---|---|---|---|---|---|---|",
    ]
    for m in sorted(materials, key=lambda m: _order(results, m)):
        sel = selections[m]
        r0, n = sel["chamber_radius"], sel["fiber_turns"]
        lin = sel.get("linearity")
        lin_text = "-" if lin is None or lin.value is None else f"{lin.value:.0%} of designs ({lin.reason})"
        why_r0 = markdown_cell(r0.reason + paper_note("chamber_radius", r0))
        why_n = markdown_cell(n.reason + paper_note("fiber_turns", n))
        lines.append(
            f"| {material_role(results, m)} | {markdown_cell(m)}: {markdown_cell(_law(m))}"
            f"{' (quick mesh)' if m in quick else ''} | "
            f"{_verdict(r0, 'chamber_radius')} | {why_r0} | {_verdict(n, 'fiber_turns')} | {why_n} | "
            f"{markdown_cell(lin_text)} |"
        )
    return lines + [""]


_LIMIT = re.compile(r"^r = ([0-9.]+): does not withstand: limit point at ([0-9.e+-]+) kPa", re.M)
_EXTENSION = re.compile(r"^N = ([0-9.]+): extension ([0-9.e+-]+) mm", re.M)


def _monotone(text: str, pattern, falling: bool) -> bool:
    """True if the (key, value) pairs the pattern finds in the evidence (at least two) never
    rise (never fall) with the key and do change overall (the evidence rounds to 3 digits)."""
    pairs = sorted((float(k), float(v)) for k, v in pattern.findall(text))
    steps = [b[1] - a[1] for a, b in zip(pairs, pairs[1:])]
    sign = -1.0 if falling else 1.0
    return len(pairs) >= 2 and all(sign * d >= 0 for d in steps) and sign * sum(steps) > 0


def _names(materials, test) -> str:
    chosen = [m for m in materials if test(m)]
    return ", ".join(f"`{m}`" for m in chosen) if chosen else "none"


def robot_evidence(robot_rows: Mapping, paper_table: Mapping) -> list[str]:
    """The evidence of the rows decided by the foot and robot-level studies (the same for every
    silicone, so written once): the groove rule's table, and each robot rule's candidates."""
    lines = ["## Rows decided by the foot and robot-level studies", ""]
    lines += [*robot_rows["groove_height"].evidence_lines, ""]
    for param in ("foot_radius", "rings"):
        row = robot_rows[param]
        sel = row.selection
        shown = "pending" if sel.value is None else f"{sel.value:g}"
        mesh = " (quick mesh)" if row.quick else ""
        label, paper, unit = paper_table[param]
        unit = f" {unit}" if unit else ""
        lines += [f"{label}: {shown}{unit} ({row.material}{mesh}; paper {paper:g}{unit}). {sel.reason}.", ""]
        lines += [f"Source: {row.source}" if row.source else "Source: none", ""]
        lines += [f"- {e}" for e in sel.evidence] or ["- (none)"]
        lines += [""]
    return lines


def closing(results, materials: Sequence[str], selections: Mapping[str, Mapping]) -> list[str]:
    """Which of the paper's conclusions survive which material assumption (data-driven)."""

    def value(m, p):
        return selections[m][p].value

    def evidence(m, p):
        return "\n".join(selections[m][p].evidence)

    r3 = _names(materials, lambda m: value(m, "chamber_radius") == 3.0)
    r_none = _names(materials, lambda m: value(m, "chamber_radius") is None)
    n20 = _names(materials, lambda m: value(m, "fiber_turns") == 20.0)
    n_other = _names(materials, lambda m: value(m, "fiber_turns") not in (None, 20.0))
    lin = _names(materials, lambda m: (selections[m].get("linearity") or rules.pending("x", "")).value == 1.0)
    fluct = _names(materials, lambda m: "withstands; fluctuating" in evidence(m, "chamber_radius"))
    burst = _names(materials, lambda m: _monotone(evidence(m, "chamber_radius"), _LIMIT, falling=True))
    more = _names(materials, lambda m: _monotone(evidence(m, "fiber_turns"), _EXTENSION, falling=False))
    centres = _json(Path(results) / "paper-material" / "paper-material.json").get("centres", {})
    window = [c["window_mu"] for c in centres.values()]
    lo, hi = (min(w[0] for w in window), max(w[1] for w in window)) if window else (None, None)
    stiffer = (
        f"a shear modulus of {lo:.3g}-{hi:.3g} MPa ({lo / LITERATURE_MU:.1f}-{hi / LITERATURE_MU:.1f}x "
        f"the literature {LITERATURE_MU:g} MPa)"
        if window
        else "a stiffer silicone (run `softcrawl study paper-material`)"
    )
    return [
        "## Which conclusions of the paper survive which material assumption",
        "",
        f"- r0 = 3 mm is selected by the paper's own reasons with: {r3}. Undetermined (no radius "
        f"withstands {rules.TARGET_PRESSURE_KPA:g} kPa without fibers) with: {r_none}. The chamber "
        f"radius row therefore rests on the paper's silicone having {stiffer}: the window of the "
        "paper's own Fig. 8 limit pressures for every law scanned (`results/paper-material/`); the "
        "full-range Yeoh and Gent fits of the tensile data stiffen too little at the stretches where "
        "the tube bursts to move its limit points there (their windows are those of Neo-Hookean "
        "within a few per cent).",
        f'- The paper\'s r = 2 and 4 mm "fluctuate"; a fluctuating length appears in: {fluct}. No '
        "hyperelastic law W(I1) gives it (the closed-end tube's length grows monotonically with "
        "pressure up to its limit point), so where r = 2 withstands 100 kPa the rule keeps it, and "
        "it expands least: the paper's choice of 3 mm over 2 mm rests on an observation this FE "
        "does not reproduce.",
        f"- N = 20 (the fewest turns within {rules.SIMILAR_EXTENSION_REL:.0%} of N = 50) with: {n20}; "
        f"another N with: {n_other} (each material's evidence gives every design's shortfall "
        "against N = 50: the softer the silicone, the more the turns matter).",
        f'- "Fibers bring the length-pressure relation closer to linear" (relative to N = 0, over the '
        f"pressures both reach) holds for every fibered design with: {lin}.",
        f"- Larger chambers burst first (limit pressure never rising with r) with: {burst}; more "
        f"turns extend more (extension never falling with N, to 3 digits) with: {more}.",
        "",
    ]
