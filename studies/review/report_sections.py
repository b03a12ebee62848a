"""The sections of the design review (`studies.review.report`): each is a function of the results
folder that returns its HTML, or a note naming the command that makes what is missing."""

from __future__ import annotations

import json
import math
from pathlib import Path

from softcrawl import materials
from softcrawl.materials import load_tensile
from softcrawl.studies import registry
from softcrawl.studies.declaration import resolve
from softcrawl.studies.html import Html, csv_rows, esc, figure, markdown, missing, number_text, table
from softcrawl.studies.material.plot_fit import plot_fit
from softcrawl.studies.plots.labels import material_label, study_title

CALIBRATE = "softcrawl calibrate --full-mesh --out results/calibration"
RENDERS = (
    'softcrawl epsa --material "ecoflex-00-50@mu=0.0638" --pressures 0:100:50 --render --no-vtu '
    "--out results/epsa-renders"
)
VERIFY = "softcrawl verify --json results/verify/verify.json"
#: The decision records whose measurements the benchmarks section shows (the solver's efficiency).
SOLVER_RECORDS = ("016-solver-pass1.md", "017-solver-pass2.md")


def study_command(name: str, material: str | None = None, quick: bool = False, settings=None) -> str:
    """The `softcrawl study` command line that makes a run of study `name` under results/: only
    the options the study takes (its declaration's `options`), its material, or its default."""
    study = registry.get(name)
    settings = settings or {}
    words = ["softcrawl study", name] + (["--quick"] if quick else [])
    if "workers" in study.options:
        words.append("--workers 2")
    if "fibers" in study.options and settings.get("fibers") not in (None, "sheet"):
        words.append(f"--fibers {settings['fibers']}")
    if "mesh_size" in study.options and settings.get("mesh_size"):
        words.append(f"--mesh-size {settings['mesh_size']:g}")
    material = material or study.default_material
    if material:
        words.append(f'--material "{material}"')
    return " ".join([*words, "--out results/"])


def _num(v):
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


def _materials(results: Path, study: str) -> list[Path]:
    return sorted(p for p in (results / study).glob("*") if (p / "spec.json").exists())


def _design_rows(folder: Path, param: str, value: float) -> list[dict]:
    return [r for r in csv_rows(folder / "curves.csv") if _num(r.get(param)) == value]


def _failure_stretch() -> float | None:
    """Stretch at failure of the shipped Ecoflex 00-50 pull-to-failure test (uniaxial)."""
    try:
        return 1.0 + float(load_tensile("ecoflex-00-50").strain.max())
    except Exception:  # noqa: BLE001 - the data file is optional for the report
        return None


def _limits_row(results: Path, folder: Path) -> dict:
    """One material's answer row from the fiber-turns study (N = 0 and N = 20 at r0 = 3 mm)."""
    material = json.loads((folder / "spec.json").read_text())["settings"].get("material")
    plain = _design_rows(folder, "fiber_turns", 0.0)
    wound = [r for r in _design_rows(folder, "fiber_turns", 20.0) if r.get("row_status") == "converged"]
    top = max(wound, key=lambda r: _num(r["pressure_kpa"]) or 0.0) if wound else {}
    ref = next(
        (r for r in _design_rows(folder, "fiber_turns", 20.0) if r.get("row_status") == "reference"), {}
    )
    row = {
        "material": material_label(material),
        "no winding (N = 0): limit point (kPa)": _num(plain[0].get("limit_pressure_kpa")) if plain else None,
        "N = 20: highest pressure reached (kPa)": _num(top.get("pressure_kpa")),
        "N = 20: limit point (kPa)": _num(top.get("limit_pressure_kpa")),
        "extension there (mm)": (_num(top.get("length_mm")) or 0) - (_num(ref.get("length_mm")) or 100),
        "radius change (mm)": (_num(top.get("outer_radius_mm")) or 0)
        - (_num(ref.get("outer_radius_mm")) or 9),
        "largest principal stretch": _num(top.get("max_principal_stretch")),
        "largest fiber force (N)": _num(top.get("max_fiber_tension_n")),
    }
    return row


def _fmt(value, spec: str = ".3g") -> str:
    return "n/a" if value is None else format(value, spec)


def _plain_limit(row: dict) -> str:
    """What the unreinforced chamber does, in words (it may have no limit point below 100 kPa)."""
    limit = row["no winding (N = 0): limit point (kPa)"]
    if limit is None:
        return "without the winding the chamber meets no limit point in the studied range."
    return f"without the winding the chamber balloons at a limit point at {limit:.3g} kPa."


def _wound_limit(row: dict, stretch, margin: str) -> str:
    reached = row["N = 20: highest pressure reached (kPa)"]
    limit = row["N = 20: limit point (kPa)"]
    where = "with no limit point" if limit is None else f"with a limit point at {_fmt(limit)} kPa"
    return (
        f"With 20 turns the ramp reaches {_fmt(reached)} kPa {where}; the silicone's largest principal "
        f"stretch there is {_fmt(stretch)}{margin}, the largest fiber force "
        f"{_fmt(row['largest fiber force (N)'])} N."
    )


def answer(results: Path) -> str:
    folders = _materials(results, "fiber-turns")
    if not folders:
        return missing("The fiber-turns study", study_command("fiber-turns"))
    rows = [_limits_row(results, f) for f in folders]
    broke = _failure_stretch()
    parts = [table(rows)]
    lines = []
    for r in rows:
        stretch = r["largest principal stretch"]
        margin = (
            f" ({broke / stretch:.2g}x below the stretch {broke:.3g} at which the tensile test broke)"
            if (broke and stretch)
            else ""
        )
        lines.append(
            f"<li><b>{esc(r['material'])}</b>: {_plain_limit(r)} {_wound_limit(r, stretch, margin)}</li>"
        )
    parts.append(
        "<div class='answer'><p><b>What limits it, and at what pressure.</b></p><ul>" + "".join(lines)
    )
    parts.append(
        "<li>The winding is what makes 100 kPa possible: every unreinforced "
        "chamber radius meets a limit point "
        "below 100 kPa (section Studies). With it the limit is the silicone's stretch (the tensile test is "
        "uniaxial: an indication, not a failure criterion for the wall) and the "
        "bending over of the long, soft "
        "column, which the side-load probe does not show up to 100 kPa (section Benchmarks and convergence, "
        "<code>results/epsa-default-mesh/</code>).</li></ul>"
    )
    parts.append(_how_sure(results, rows))
    return "".join(parts) + "</div>"


def _how_sure(results: Path, rows: list[dict]) -> str:
    items = []
    cal = results / "calibration" / "calibration.json"
    c = json.loads(cal.read_text()) if cal.exists() else None
    if len(rows) >= 2:
        ext = [r["extension there (mm)"] for r in rows]
        text = (
            f"The modulus dominates: the extension at the highest pressure is {max(ext):.3g} mm with the "
            f"softer and {min(ext):.3g} mm with the stiffer material of the table."
        )
        if c and c["pressures_kpa"]:
            text += (
                f" The prototype's eqs. 19-24 give {c['prototype_length_mm'][-1] - 100.0:.3g} mm at "
                f"{c['pressures_kpa'][-1]:g} kPa; the calibrated modulus was fitted to them."
            )
        items.append(text)
    if c:
        items.append(
            f"Calibration: mu = {c['mu_mpa']:.4g} MPa fits the prototype within "
            f"{c['rms_error_mm']:.2g} mm RMS "
            f"at {', '.join(f'{p:g}' for p in c['pressures_kpa'])} kPa."
        )
    conv = sorted((results / "epsa-convergence").glob("convergence-ecoflex-00-50*.csv"))
    for path in conv:
        default = next((r for r in csv_rows(path) if _num(r.get("mesh_size_mm")) == 5.0), None)
        if default:
            items.append(
                f"Mesh: on the default mesh (h = 5 mm) the extension at 100 kPa is "
                f"{abs(_num(default['change_vs_finest_pct'])):.2g} % below the finest mesh's ({path.stem})."
            )
    verify = results / "verify" / "verify.json"
    if verify.exists():
        v = json.loads(verify.read_text())
        items.append(
            f"Solver verification: {sum(c['passed'] for c in v['cases'])} of {len(v['cases'])} cases pass."
        )
    items.append(
        "The paper's own selection rules stay undetermined for r0 and N with "
        "either modulus (section Table 1): "
        "the FE does not reproduce the paper's claim that r0 = 2-4 mm withstand 100 kPa without fibers."
    )
    return "<p><b>How sure we are.</b></p><ul>" + "".join(f"<li>{esc(i)}</li>" for i in items) + "</ul>"


def table1(results: Path) -> str:
    path = results / "table1.md"
    if not path.exists():
        return missing("results/table1.md", "softcrawl table1 --out results/")
    return markdown(path.read_text())


def renders(results: Path) -> str:
    folder = results / "epsa-renders"
    files = [folder / f"render-{p}kPa.png" for p in (0, 50, 100)]
    if not all(f.exists() for f in files):
        return missing("The 3D renders at 0, 50 and 100 kPa", RENDERS)
    figs = "".join(figure(f, f"P = {f.stem.split('-')[1]}") for f in files)
    return f"<p>Command: <code>{esc(RENDERS)}</code></p><div class='wide'>{figs}</div>"


def _study_names() -> dict[str, str]:
    """Results folder -> the `softcrawl study` name that makes it (the first study declared for a
    folder: identify/ is the identify study's, which kp-mismatch reads)."""
    names: dict[str, str] = {}
    for study in registry.studies():
        names.setdefault(study.folder, study.name)
    return names


def _study_block(folder: Path, name: str) -> str:
    spec = json.loads((folder / "spec.json").read_text())
    # a sweep's spec keeps its settings apart; a study that is not a sweep (skirt) writes them flat
    settings = spec.get("settings", spec)
    material = settings.get("material")
    quick = bool(settings.get("quick")) or settings.get("mesh") == "quick"
    head = f"<h3>{esc(study_title(name, material, quick))}</h3>"
    command = study_command(_study_names().get(name, name), material, quick, settings)
    body = [f"<p>Material {esc(material_label(material))}. Command: <code>{esc(command)}</code></p>"]
    for png in sorted(folder.glob("*.png")):
        body.append(figure(png, f"{folder.relative_to(folder.parents[1])}/{png.name}"))
    for name_csv in ("summary.csv", "identification.csv", "pareto.csv", "skirt.csv"):
        if (folder / name_csv).exists():
            body.append(f"<p><code>{name_csv}</code></p>" + table(csv_rows(folder / name_csv)))
    return head + "".join(body)


def studies(results: Path) -> str:
    """One block per run of every study that the registry puts in this section, in its order; a
    study's own `report` function, where it declares one, replaces the generic block."""
    out = []
    for study in registry.studies():
        if not study.in_review:
            continue
        folders = study.results_folders(results)
        if not folders:
            out.append(missing(f"The {study.folder} study", study_command(study.name)))
        block = resolve(study.report) if study.report else lambda f, s=study: _study_block(f, s.folder)
        out.extend(block(f) for f in folders)
    return "".join(out)


def material(results: Path) -> str:
    import tempfile

    data = materials.load_tensile("ecoflex-00-50")
    fit = materials.fit_tensile(data, "neo-hookean")
    with tempfile.TemporaryDirectory() as tmp:
        fig = figure(
            plot_fit(data, fit, Path(tmp) / "fit.png"), "Neo-Hookean fit to the shipped tensile test"
        )
    presets = []
    for name in ("ecoflex-00-50", "ecoflex-00-50-fit", "kevlar", "abs"):
        m = materials.get_material(name)
        presets.append({"preset": name, "model": m.model, "mu (MPa)": m.mu, "source": m.source})
    return (
        "<p>Command: <code>softcrawl material fit --data ecoflex-00-50 --out "
        "DIR</code>. The studies run with "
        "the preset mu = 0.03 MPa (literature value) and with the calibrated "
        "0.0638 MPa; the tensile fit of the "
        f"shipped data gives {dict(zip(fit.param_names, fit.values))['mu']:.4g} MPa.</p>"
        + fig
        + table(presets)
    )


def calibration(results: Path) -> str:
    folder = results / "calibration"
    if not (folder / "calibration.json").exists():
        return missing("The calibration", CALIBRATE)
    c = json.loads((folder / "calibration.json").read_text())
    rows = [
        {"P (kPa)": p, "prototype length (mm)": a, "FE length (mm)": b}
        for p, a, b in zip(c["pressures_kpa"], c["prototype_length_mm"], c["fe_length_mm"])
    ]
    fig = figure(folder / "calibration.png", "calibration") if (folder / "calibration.png").exists() else ""
    return (
        f"<p>Command: <code>{CALIBRATE}</code>. mu = {c['mu_mpa']:.4g} MPa (base {esc(c['base_material'])}, "
        f"{esc(c['mesh'])} mesh, {esc(c.get('fibers', ''))} winding), RMS error "
        f"{c['rms_error_mm']:.3g} mm.</p>" + fig + table(rows)
    )


def verify(results: Path) -> str:
    path = results / "verify" / "verify.json"
    if not path.exists():
        return missing("The verification table", VERIFY)
    data = json.loads(path.read_text())
    rows = [
        {
            "case": c["case"],
            "error": format(c["error"], ".3g"),
            "tolerance": format(c["tolerance"], ".3g"),
            "result": "pass" if c["passed"] else "FAIL",
            "time (s)": c.get("seconds"),
            "details": Html(
                "<br>".join(f"{esc(k)} = {esc(_detail(v))}" for k, v in (c.get("details") or {}).items())
            ),
        }
        for c in data["cases"]
    ]
    passed = sum(c["passed"] for c in data["cases"])
    return f"<p>Command: <code>{VERIFY}</code>. {passed} of {len(rows)} cases pass.</p>" + table(rows)


def _detail(value) -> str:
    """A verification detail as text: numbers to 4 significant digits, lists item by item."""
    if isinstance(value, (list, tuple)):
        return ", ".join(_detail(v) for v in value)
    if isinstance(value, dict):
        return "; ".join(f"{k} {_detail(v)}" for k, v in value.items())
    return number_text(value)


def benchmarks(results: Path) -> str:
    out = []
    for path in sorted((results / "epsa-convergence").glob("*.csv")):
        out.append(f"<h3>Mesh convergence: {esc(path.stem)}</h3>" + table(csv_rows(path)))
    if not out:
        out.append(
            missing("The mesh convergence study", "softcrawl epsa --convergence 10,5,4,3.33,2.5 --out DIR")
        )
    bench = sorted((results / "bench").glob("*.txt")) if (results / "bench").exists() else []
    for path in bench:
        out.append(f"<h3>{esc(path.name)}</h3><pre>{esc(path.read_text())}</pre>")
    for record in SOLVER_RECORDS:
        path = results.parent / "docs" / "decisions" / record
        if path.exists():
            out.append(
                f"<h3>Recorded measurements (docs/decisions/{record})</h3>" + markdown(path.read_text())
            )
    if not bench:
        out.append(
            missing(
                "A benchmark printout under results/bench/",
                "python bench/solver_bench.py > results/bench/solver_bench.txt",
            )
        )
    probe = results / "epsa-default-mesh" / "README.md"
    if probe.exists():
        out.append("<h3>Bending-over probe (results/epsa-default-mesh)</h3>" + markdown(probe.read_text()))
    return "".join(out)
