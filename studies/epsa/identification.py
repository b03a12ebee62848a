r"""The paper's static identification (Section VII-A) run on finite element results.

FE experiment (one sweep point per weight W in `LOADS_N`): the Table 1 ePSA with its base fixed and
a weight W on the guided seal head (a dead force -W e_z, see `studies.epsa.model.build_model`) is
ramped through `PRESSURES_KPA` (10 to 100 kPa in 10 kPa steps, as the paper's step (2)). The weight
goes on first, at 0 kPa. The extension y is the FE length minus the unloaded 0 kPa length.

Identification (`analytic.identification`, the paper's two least-squares steps): at each pressure
where every weight converged under pressure control, the line y = a + b W gives

    k_p = -1/b,     f_p = a k_p          (eq. 3, k_p y + m g + W = f_p, with m g = 0: no gravity in the FE)

then k_p(P) and f_p(P) are each fitted by two lines split at 60 kPa, the form of eqs. 19-24 (one
line when fewer than two pressures lie on a side). The comparison with the prototype ePSAs 1-3
(eqs. 19-24) is per pressure, in the paper's units (k_p in N/m, f_p in N).

Not used, and listed with the reason (so a missing pressure is visible, not silently dropped):
pressures past a limit point (volume-controlled states) or not reached, and pressures above the
longest state of any weight: a loaded soft actuator can stop extending and shorten as the
pressure rises (it bulges or folds under the weight), which is not the spring-and-thrust
behaviour of eq. 3 that the identification fits.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcrawl import jsonio
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.identification import identify
from softcrawl.analytic.prototype import prototype_epsa
from softcrawl.studies.epsa.plot_curves import plot_curves
from softcrawl.studies.epsa.plot_identification import plot_identification
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.plots.labels import material_label, study_title
from softcrawl.studies.sweeps.spec import read_spec
from softcrawl.studies.sweeps.tables import read_csv, write_csv

#: Weights on the seal head, N (0, 51 and 102 g): within the paper's measured output force range
#: (8.42 N blocked at 100 kPa) and small enough to keep the response linear in W.
LOADS_N = (0.0, 0.5, 1.0)
#: The paper's pressure steps (Section VII-A, step 2).
PRESSURES_KPA = tuple(float(p) for p in range(10, 101, 10))


@dataclass(frozen=True)
class FEIdentification:
    table: tuple[tuple[float, float, float], ...]  # (P kPa, W N, y mm) used in the fit
    pressures_kpa: tuple[float, ...]  # pressures with every weight converged
    skipped: tuple[tuple[float, str], ...]  # (P kPa, why) not used
    result: object | None  # analytic.identification.Identification
    message: str = ""


def load_extension_table(rows) -> tuple[list[tuple[float, float, float]], list[tuple[float, str]]]:
    """(P, W, y) from the sweep's curve rows (runner.collect), and the pressures left out."""
    by_load: dict[float, dict[float, float]] = {}
    length0: dict[float, float] = {}
    status: dict[float, dict[float, str]] = {}
    for r in rows:
        if r.get("pressure_kpa") in ("", None):
            continue
        # landed targets read e.g. 79.9995 kPa (volume control): group them with the target
        w, p = float(r["end_load_n"]), round(float(r["pressure_kpa"]), 2)
        st = r.get("row_status", "")
        if st == "reference":
            length0[w] = float(r["length_mm"])
            continue
        status.setdefault(w, {})[p] = st
        if st == "converged" and r.get("length_mm") not in ("", None) and p > 0:
            by_load.setdefault(w, {})[p] = float(r["length_mm"])
    loads = sorted(status)
    pressures = sorted({p for s in status.values() for p in s if p > 0})
    collapsed = {w: _collapse_pressure(by_load.get(w, {})) for w in loads}
    table, skipped = [], []
    for p in pressures:
        missing = [w for w in loads if p not in by_load.get(w, {}) or w not in length0]
        if missing:
            skipped.append(
                (
                    p,
                    "no equilibrium at this pressure for W = "
                    + ", ".join(f"{w:g} N ({status.get(w, {}).get(p, 'missing')})" for w in missing),
                )
            )
            continue
        fallen = [w for w in loads if collapsed[w] is not None and p > collapsed[w]]
        if fallen:
            skipped.append(
                (
                    p,
                    "the loaded actuator shortens as the pressure rises (past its longest "
                    "state, eq. 3 no longer describes it) for W = "
                    + ", ".join(f"{w:g} N (longest at {collapsed[w]:g} kPa)" for w in fallen),
                )
            )
            continue
        table += [(p, w, by_load[w][p] - length0[w]) for w in loads]
    return table, skipped


def _collapse_pressure(lengths: dict[float, float]) -> float | None:
    """The pressure of the longest state if the length falls at a higher pressure, else None."""
    ps = sorted(lengths)
    if not ps:
        return None
    top = max(ps, key=lambda p: lengths[p])
    return top if top < ps[-1] else None


def identify_from_rows(rows, breakpoint: float = 60.0) -> FEIdentification:
    table, skipped = load_extension_table(rows)
    loads = sorted({w for _, w, _ in table})
    pressures = sorted({p for p, _, _ in table})
    if len(loads) < 2 or not pressures:
        return FEIdentification(
            tuple(table),
            tuple(pressures),
            tuple(skipped),
            None,
            "needs at least two weights converged at one pressure",
        )
    P, W, y = (np.array(c) for c in zip(*table))
    lo = sum(p <= breakpoint for p in pressures)
    piecewise = lo >= 2 and len(pressures) - lo >= 2
    try:
        result = identify(
            P, W, y, mass_t=0.0, breakpoint=breakpoint if piecewise else None, piecewise=piecewise
        )
    except ModelInputError as exc:
        return FEIdentification(tuple(table), tuple(pressures), tuple(skipped), None, str(exc))
    note = (
        ""
        if piecewise
        else f"one line per parameter: fewer than two pressures on a side of {breakpoint:g} kPa"
    )
    return FEIdentification(tuple(table), tuple(pressures), tuple(skipped), result, note)


def comparison_rows(ident: FEIdentification) -> list[dict]:
    """Per pressure: FE k_p (N/m), f_p (N) and the fit residual, beside eqs. 19-24 for ePSAs 1-3."""
    protos = {i: prototype_epsa(i) for i in (1, 2, 3)}
    out = []
    if ident.result is None:
        return out
    per = ident.result.per_pressure
    for p, k, f, rms in zip(per.pressure_kpa, per.k_p, per.f_p, per.rms_mm):
        row = {
            "pressure_kpa": float(p),
            "k_p_fe_n_per_m": 1e3 * float(k),
            "f_p_fe_n": float(f),
            "fit_rms_mm": float(rms),
            "k_p_fe_fit_n_per_m": 1e3 * float(ident.result.k_p(p)),
            "f_p_fe_fit_n": float(ident.result.f_p(p)),
        }
        for i, a in protos.items():
            row[f"k_p_epsa{i}_n_per_m"] = 1e3 * float(a.k_p(p))
            row[f"f_p_epsa{i}_n"] = float(a.f_p(p))
        out.append(row)
    return out


def fitted_laws(ident: FEIdentification) -> dict:
    """The identified laws in the paper's printed form (k_p in N/m, f_p in N, P in kPa)."""
    if ident.result is None:
        return {"message": ident.message}

    def lines(pw, factor):
        return [
            {
                "p_max_kpa": None if hi is None or not np.isfinite(hi) else float(hi),
                "slope": factor * line.slope,
                "intercept": factor * line.intercept,
            }
            for _, hi, line in pw.branches()
        ]

    return {
        "k_p_n_per_m": lines(ident.result.k_p, 1e3),
        "f_p_n": lines(ident.result.f_p, 1.0),
        "pressures_kpa": list(ident.pressures_kpa),
        "skipped": [{"pressure_kpa": p, "reason": why} for p, why in ident.skipped],
        "message": ident.message,
    }


def draw_identify_curves(settings: Mapping, rows, folder) -> Path:
    """identify.png: length against pressure under each weight (also from curves.csv alone)."""
    title = study_title("identify", settings.get("material"), bool(settings.get("quick")))
    return plot_curves(rows, "end_load_n", Path(folder) / "identify.png", label="W", unit=" N", title=title)


def draw_identification(settings: Mapping, table, laws: Mapping, folder) -> Path:
    """identification.png: the FE's k_p(P), f_p(P) beside eqs. 19-24 (also from the files alone)."""
    quick = ", coarse (quick) mesh" if settings.get("quick") else ""
    title = (
        f"Static identification on FE results (paper Section VII-A): "
        f"{material_label(settings.get('material'))}{quick}, against the prototype"
    )
    return plot_identification(table, Path(folder) / "identification.png", title=title, laws=laws)


def write_outputs(spec, rows, folder) -> StudyOutcome:
    """curves.csv, identify.png (length per weight), identification.csv/.json and
    identification.png (k_p, f_p against eqs. 19-24)."""
    write_csv(rows, folder / "curves.csv")
    material = spec.settings.get("material")
    draw_identify_curves(spec.settings, rows, folder)
    ident = identify_from_rows(rows)
    table = comparison_rows(ident)
    laws = fitted_laws(ident) | {"material": material, "quick": bool(spec.settings.get("quick"))}
    jsonio.write(folder / "identification.json", laws)
    written = [folder / "curves.csv", folder / "identify.png", folder / "identification.json"]
    lines = [f"  P = {p:g} kPa not used: {why}" for p, why in ident.skipped]
    if not table:
        return StudyOutcome(
            tuple(lines), tuple(written), False, (f"identify: no identification: {ident.message}",)
        )
    write_csv(table, folder / "identification.csv")
    draw_identification(spec.settings, table, laws, folder)
    written += [folder / "identification.csv", folder / "identification.png"]
    for name, key in (("k_p (N/m)", "k_p_n_per_m"), ("f_p (N)", "f_p_n")):
        text = "; ".join(
            f"{b['slope']:.4g} P {'-' if b['intercept'] < 0 else '+'} {abs(b['intercept']):.4g}"
            + ("" if b["p_max_kpa"] is None else f" (P <= {b['p_max_kpa']:g})")
            for b in laws[key]
        )
        lines.append(f"identify: FE {name} = {text}")
    if ident.message:
        lines.append(f"identify: {ident.message}")
    return StudyOutcome(tuple(lines), tuple(written), True)


def replot_folder(folder: Path) -> list[Path]:
    """identify.png and identification.png of an identify run from its files alone."""
    if not (folder / "curves.csv").exists():
        return []
    settings = read_spec(folder).get("settings", {})
    written = [draw_identify_curves(settings, read_csv(folder / "curves.csv"), folder)]
    if (folder / "identification.csv").exists() and (folder / "identification.json").exists():
        laws = json.loads((folder / "identification.json").read_text())
        written.append(draw_identification(settings, read_csv(folder / "identification.csv"), laws, folder))
    return written
