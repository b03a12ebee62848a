r"""The foot studies of paper Fig. 10 as resumable sweeps: grids, stated inputs, evaluators.

    groove (Fig. 10(a)): the groove-segment strip (`studies.foot.groove_model`) under 100 kPa,
            then 5 mm of drag, for groove heights h and friction coefficients mu.
    foot   (Fig. 10(b)): the whole grooved foot (`studies.foot.model`), Shore 70A, angle
            120 deg, inserted into pipes of 55-75 mm and dragged 8 mm forward and backward (5 mm
            with --quick, in 60 and 75 mm pipes).

Stated inputs (no measured friction data exist for the printed foot on a pipe: these are
assumptions, not the paper's values, which it does not give):
  - mu in the groove study: 0.3 and 0.5, the range of dry rubber on smooth plastic or steel
    (engineering tables give ~0.3-0.9; the lower half is taken, a lubricated or dusty pipe).
  - the foot study: mu_smooth = mu_grooved = 0.5 by default (the same rubber on the same wall:
    the groove study finds the Coulomb friction of the grooved face equal to mu N, so the grooves
    add no friction of their own in this model); `--set mu_grooved=...` style overrides go
    through `settings`.

Each evaluation writes its full result (curves, metrics) as JSON to OUT/points/ before it returns,
so the tables and plots are rebuilt from those files whatever the sweep engine keeps; the sweep
itself (`studies.sweeps`: SweepSpec, run_sweep, Evaluation, write_csv) makes the run
resumable and records failures with their reason.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from softcrawl import jsonio
from softcrawl.analytic.pipe import Pipe
from softcrawl.fem.vtu import write_state
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.paper import PIPE_DIAMETERS_MM
from softcrawl.studies.foot.groove_model import GrooveSegment, run_groove
from softcrawl.studies.foot.groove_rule import GrooveRuleInputs
from softcrawl.studies.foot.model import run_foot
from softcrawl.studies.foot.study import FOOT_FRICTION
from softcrawl.studies.sweeps.spec import Evaluation
from softcrawl.units import kpa_to_mpa, mpa_to_kpa

GROOVE = "groove"
FOOT = "foot"
DEFAULT_MATERIAL = "rubber-70a"
PRESSURE_KPA = 100.0
DRAG_MM = {GROOVE: 5.0, FOOT: 8.0}  # the paper's Fig. 10: 5 mm (groove), 5 and 8 mm (foot)

GRIDS = {
    GROOVE: {"groove_height": (0.5, 1.0, 1.5, 2.0), "mu": (0.3, 0.5)},
    FOOT: {"pipe_diameter": PIPE_DIAMETERS_MM},
}
QUICK_GRIDS = {
    GROOVE: {"groove_height": (0.5, 1.0, 2.0), "mu": (0.3,)},
    FOOT: {"pipe_diameter": (60.0, 75.0)},
}
#: What optuna's "best" means per study (decision 063): groove, the largest groove height
#: that passes the groove rule's per-point tests (`groove_constraints`); foot, the backward over
#: forward drag force (the foot's anchoring asymmetry, maximised; the foot study decides no Table 1
#: value, so best only ranks).
OBJECTIVES = {GROOVE: ("groove_height", "maximize"), FOOT: ("friction_ratio_bwd_fwd", "maximize")}
EVALUATORS = {
    GROOVE: "groove",  # registry names (studies/foot/study.py)
    FOOT: "foot",
}


def point_file(out_dir, name: str, params: dict) -> Path:
    stem = "-".join(f"{k}{float(v):g}" for k, v in sorted(params.items()))
    return Path(out_dir) / "points" / f"{name}-{stem}.json"


def _write_json(path: Path, data: dict) -> None:
    """The point's result as strict JSON, written atomically (a reader never sees half a file)."""
    jsonio.write(path, data, indent=1)


def _vtu_writer(settings, stem):
    """on_state(label, model, x, time=None): one VTU per state; states with a time (the drag in
    mm) also go into the series STEM-LABEL.pvd (label without its step number)."""
    vtu_dir = settings.get("vtu_dir")
    if not vtu_dir:
        return None
    from xml.sax.saxutils import quoteattr

    series: dict[str, list] = {}

    def on_state(label, model, x, time=None):
        path = write_state(Path(vtu_dir) / f"{stem}-{label}.vtu", model, x)
        if time is None:
            return
        name = label.rstrip("0123456789_")
        series.setdefault(name, []).append((time, path.name))
        lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
        lines += [f'<DataSet timestep="{t:.6g}" file={quoteattr(f)}/>' for t, f in series[name]]
        lines += ["</Collection>", "</VTKFile>"]
        (Path(vtu_dir) / f"{stem}-{name}.pvd").write_text("\n".join(lines) + "\n")

    return on_state


def _material(settings):
    return solid_law(get_material(settings.get("material", DEFAULT_MATERIAL)), hyperelastic_only=True)


def _groove_run(h: float, mu: float, settings: dict, on_state=None):
    """The groove strip of depth h pressed at 100 kPa and dragged at friction mu, with the
    study's settings (cell, drag steps, material)."""
    seg = GrooveSegment(groove_height=h, cell=float(settings.get("cell", 0.2)))
    return run_groove(
        seg,
        _material(settings),
        mu,
        pressure=kpa_to_mpa(PRESSURE_KPA),
        drag=DRAG_MM[GROOVE],
        drag_steps=int(settings.get("drag_steps", 20)),
        on_state=on_state,
    )


#: The groove rule's strain at each (h, mu, settings) this process has solved: its own points and
#: the other friction coefficients' runs that the "at every mu" constraint needs (`rule_strain`).
_STRAINS: dict[tuple, float] = {}


def _strain_key(h: float, mu: float, settings: dict) -> tuple:
    keep = {k: v for k, v in settings.items() if k not in ("vtu_dir", "out_dir", "objective", "rule_mus")}
    return (float(h), float(mu), jsonio.dumps(keep, sort_keys=True))


def _rule_strain(r) -> float:
    """The p99 strain the groove rule judges; NaN when the drag did not complete ("cannot
    withstand": the rule does not allow the height)."""
    return float(r.metrics.get("max_principal_strain_p99", math.nan)) if r.converged else math.nan


def rule_strain(h: float, mu: float, settings: dict) -> float:
    """The p99 strain of (h, mu), solved by this process if it has not been (cached)."""
    key = _strain_key(h, mu, settings)
    if key not in _STRAINS:
        _STRAINS[key] = _rule_strain(_groove_run(h, mu, settings))
    return _STRAINS[key]


def evaluate_groove(params: dict, fixed: dict, settings: dict):
    h, mu = float(params["groove_height"]), float(params["mu"])
    stem = f"groove-h{h:g}-mu{mu:g}"
    r = _groove_run(h, mu, settings, on_state=_vtu_writer(settings, stem))
    _STRAINS[_strain_key(h, mu, settings)] = _rule_strain(r)
    summary = {
        "converged": r.converged,
        "message": r.message,
        "normal_force_n": r.normal_force,
        "normal_force_error": r.normal_error,
        "plateau_n": r.plateau,
        "plateau_over_mu_n": r.plateau_over_mu_n,
        "contact_fraction_pressed": float(r.contact_fraction[0]) if r.contact_fraction.size else float("nan"),
        "contact_fraction_end": float(r.contact_fraction[-1]) if r.contact_fraction.size else float("nan"),
        "slip_fraction_end": float(r.slip_fraction[-1]) if r.slip_fraction.size else float("nan"),
        "drag_reached_mm": float(r.drag[-1]) if r.drag.size else 0.0,
        "newton_per_increment": float(np.mean(r.iterations)) if r.iterations else float("nan"),
        "n_dofs": r.n_dofs,
        "wall_s": r.wall_s,
    } | r.metrics
    curve = {
        "drag_mm": r.drag,
        "friction_n": r.friction,
        "normal_n": r.normal,
        "contact_fraction": r.contact_fraction,
    }
    _write_json(
        point_file(settings["out_dir"], GROOVE, params),
        {"params": params, "summary": summary, "curve": curve},
    )
    if not r.converged:
        return Evaluation(ok=False, attrs=summary, message=r.message)
    if settings.get("objective") == GROOVE:
        mus = [float(m) for m in settings.get("rule_mus", (mu,))]
        strains = {m: rule_strain(h, m, settings) for m in mus}  # this point's own is cached above
        return Evaluation(ok=True, values=(h,), attrs=summary | groove_constraints(h, strains))
    return Evaluation(ok=True, values=(r.plateau,), attrs=summary)


def groove_constraints(h: float, strains: dict[float, float]) -> dict:
    """The groove rule's tests on one height as optuna constraints (<= 0 feasible): h >= 0.5 mm,
    and the p99 strain after the drag <= 10 % at EVERY friction coefficient of the study
    (``strains``: mu -> strain, NaN where the drag did not complete). The trial solves the other
    friction coefficients itself (cached per process, as the fiber-turns trials solve their
    reference design), so best_trial is the rule's height (decision 063)."""

    rule = GrooveRuleInputs()
    values = list(strains.values())
    worst = max(values) if values and all(map(math.isfinite, values)) else math.nan
    c_strain = worst - rule.strain_limit if math.isfinite(worst) else 1.0
    return {
        "constraints": [rule.min_height - h, c_strain],
        "constraint_names": ["min_height", "strain_p99"],
        "rule_strain_p99_by_mu": {f"{m:g}": v for m, v in strains.items()},
    }


#: The foot study's mesher: on the revolved mesh (`geometry.foot_revolved`, three cells through
#: the skirt) every pipe of 55-75 mm inserts and drags forward, and the backward drags that stop do
#: so past a limit point; on the pytetwild mesh (about one cell through the skirt) the 55 and 75 mm
#: drags stalled without one, and two meshes were 5 % apart (docs/decisions/041-revolved-foot.md). A
#: spec.json without the key predates the revolved mesh and means pytetwild.
FOOT_MESHER = "revolved"


def _foot_mesh(settings):
    design = FootDesign(angle=float(settings.get("angle", 120.0)))
    mesher = settings.get("mesher", "tetwild")
    edge = settings.get("edge_length") if mesher == "tetwild" else None
    mesh = mesh_foot_with(design, mesher, edge_length=edge, cache_dir=settings.get("mesh_cache"))
    return design, mesh.to_skfem(2)


def _curves(r, prefix: str = "") -> dict:
    curves = {}
    for c in (r.forward, r.backward):
        if c is not None:
            curves[prefix + c.direction] = {
                "drag_mm": c.drag,
                "resistance_n": c.resistance,
                "tip_ahead_mm": c.tip_ahead,
                "grooved_share": c.grooved_share,
                "converged": c.converged,
                "message": c.message,
                "flipped_at_mm": c.flipped_at,
                "limit_point_mm": c.limit_point[0] if c.limit_point else None,
                "limit_point_n": c.limit_point[1] if c.limit_point else None,
            }
    return curves


def _limit_at(curve):
    return curve.limit_point[0] if curve is not None and curve.limit_point else None


def _flipped_summary(r) -> dict:
    """The flipped foot's columns (`studies.foot.flip`): the backward crawl's foot, grooved face on
    the wall; f_bwd is its sliding resistance (the backward crawl's), f_fwd its anchoring."""
    normal = r.face_forces
    return {
        "flipped_converged": r.converged,
        "flipped_message": r.message,
        "flipped_normal_force_n": r.normal_force,
        "flipped_normal_smooth_n": normal.get("smooth", float("nan")),
        "flipped_normal_grooved_n": normal.get("grooved", float("nan")),
        "flipped_f_fwd_n": r.forward.peak if r.forward else float("nan"),
        "flipped_f_bwd_n": r.backward.peak if r.backward else float("nan"),
        "flipped_limit_fwd_at_mm": _limit_at(r.forward),
        "flipped_limit_bwd_at_mm": _limit_at(r.backward),
        "flipped_wall_s": r.wall_s,
    }


def evaluate_foot(params: dict, fixed: dict, settings: dict):
    """The paper's foot (skirt leaning back, smooth face on the wall) and, unless the setting
    `flipped` is False, the flipped foot of the backward crawl, in the pipe of `pipe_diameter`."""
    D = float(params["pipe_diameter"])
    mu_s = float(settings.get("mu_smooth", FOOT_FRICTION["mu_smooth"]))
    mu_g = float(settings.get("mu_grooved", FOOT_FRICTION["mu_grooved"]))
    design, mesh = _foot_mesh(settings)
    runs = {}
    for flipped in (False, True) if settings.get("flipped", True) else (False,):
        runs[flipped] = run_foot(
            mesh,
            _material(settings),
            design,
            Pipe(diameter=D),
            mu_smooth=mu_s,
            mu_grooved=mu_g,
            drag=float(settings.get("drag_mm", DRAG_MM[FOOT])),
            drag_steps=int(settings.get("drag_steps", 8)),
            on_state=_vtu_writer(settings, f"foot-D{D:g}" + ("-flipped" if flipped else "")),
            flipped=flipped,
        )
    r = runs[False]
    curves = _curves(r) | (_curves(runs[True], "flipped_") if True in runs else {})
    summary = (
        {
            "converged": r.converged,
            "message": r.message,
            "mu_smooth": mu_s,
            "mu_grooved": mu_g,
            "normal_force_n": r.normal_force,
            "contact_area_mm2": r.contact_area,
            "mean_pressure_kpa": mpa_to_kpa(r.mean_pressure),
            "max_pressure_kpa": mpa_to_kpa(r.max_pressure),
            "f_fwd_n": r.forward.peak if r.forward else float("nan"),
            "f_bwd_n": r.backward.peak if r.backward else float("nan"),
            "ratio_bwd_fwd": r.ratio,
            "flipped_bwd_at_mm": r.backward.flipped_at if r.backward else None,
            "flipped_fwd_at_mm": r.forward.flipped_at if r.forward else None,
            "limit_bwd_at_mm": r.backward.limit_point[0] if r.backward and r.backward.limit_point else None,
            "limit_fwd_at_mm": r.forward.limit_point[0] if r.forward and r.forward.limit_point else None,
            "n_dofs": r.n_dofs,
            "wall_s": r.wall_s,
        }
        | {f"normal_{k}_n": v for k, v in r.face_forces.items()}
        | r.metrics
        | (_flipped_summary(runs[True]) if True in runs else {})
    )
    data = {"params": params, "summary": summary, "curves": curves, "iterations": r.iterations}
    _write_json(point_file(settings["out_dir"], FOOT, params), data)
    failed = [
        run.message if not f else f"flipped: {run.message}" for f, run in runs.items() if not run.converged
    ]
    if failed:
        return Evaluation(ok=False, attrs=summary, message="; ".join(failed))
    return Evaluation(ok=True, values=(r.ratio,), attrs=summary)
