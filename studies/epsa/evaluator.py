"""The ePSA evaluator of the sweeps and the optimiser: one design and its settings -> a result.

`evaluate_epsa(params, fixed, settings)` builds an `EPSADesign` from the grid point, calls the
simulator (``settings["simulate"]``, default `studies.epsa.response.simulate_epsa`; tests inject
fast fakes), and returns an `Evaluation` whose attributes are the curve rows, the design and scalar
metrics (extension, radial expansion, fiber length, mass). A diverged curve is a failed evaluation
with its reason; it never raises into the sweep.

`EPSA_TABLE` and `SEARCH_METRICS` say how the sweep engine lays out the tables of these
evaluations (the engine itself knows nothing of actuators).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from softcrawl.fem.vtu import write_state, write_winding
from softcrawl.files import atomic_path
from softcrawl.geometry.design import EPSADesign
from softcrawl.materials import get_material
from softcrawl.studies.epsa.response import same_pressure
from softcrawl.studies.sweeps.faults import machine_fault
from softcrawl.studies.sweeps.spec import Evaluation, TableLayout, load_callable
from softcrawl.studies.sweeps.spec import jsonable as _jsonable

#: The evaluator, as the sweep engine imports it in its worker processes.
EPSA_EVALUATOR = "epsa"  # its registry name (studies/epsa/study.py)
#: Columns of an ActuatorCurve row, in CSV order.
CURVE_COLUMNS = (
    "pressure_kpa",
    "length_mm",
    "outer_radius_mm",
    "chamber_volume_mm3",
    "max_principal_stretch",
    "max_fiber_tension_n",
    "status",
    "tip_lateral_mm",
)
#: The sweep table (curves.csv): one row per design and curve row; the undeformed length and
#: radius of the design; the scalar metrics an evaluation stores.
EPSA_TABLE = TableLayout(
    settings_columns=("material",),
    reference="design",
    reference_columns=("length", "outer_radius"),
    point_columns=("converged", "limit_pressure_kpa"),
    rows="rows",
    row_columns=CURVE_COLUMNS,
    renamed={"status": "row_status"},
    scalar_columns=("wall_s", "n_dofs", "message", "worker_pid", "vtu"),
)
#: Evaluation attributes in the optimiser's trials.csv, after the objectives.
SEARCH_METRICS = (
    "extension_mm",
    "radial_expansion_mm",
    "top_pressure_kpa",
    "limit_pressure_kpa",
    "fiber_length_mm",
    "mass_g",
    "wall_s",
)
#: Default simulator.
EPSA_SIMULATOR = "softcrawl.studies.epsa.response:simulate_epsa"
#: Grid or fixed parameters that go to the simulator as keywords instead of into the design.
SIMULATOR_PARAMS = ("end_load_n",)
#: Pressures of the paper's ePSA studies (kPa), Section V-A.
PAPER_PRESSURES_KPA = (20.0, 40.0, 60.0, 80.0, 100.0)


def curve_to_attrs(curve) -> dict[str, Any]:
    """JSON-able user attributes of an ActuatorCurve (duck-typed on the contract's fields)."""
    rows = []
    for row in curve.rows:
        rows.append({col: _jsonable(getattr(row, col, None)) for col in CURVE_COLUMNS})
    return {
        "rows": rows,
        "converged": bool(curve.converged),
        "limit_pressure_kpa": _jsonable(curve.limit_pressure_kpa),
        "message": str(getattr(curve, "message", "")),
        "wall_s": _jsonable(getattr(curve, "wall_s", None)),
        "n_dofs": getattr(curve, "n_dofs", None),
        "material": getattr(curve, "material", None),
        "material_law": getattr(curve, "material_law", None),
    }


def response_at(
    rows: Sequence[Mapping[str, Any]], pressure_kpa: float | None = None
) -> Mapping[str, Any] | None:
    """The equilibrium ("converged") row at ``pressure_kpa`` (default: the highest such pressure),
    matched with `same_pressure` (a target landed on by volume control reads e.g. 99.9999 kPa).
    Volume-controlled states past a limit point are not used."""
    good = [r for r in rows if r.get("status") == "converged"]
    if not good:
        return None
    if pressure_kpa is None:
        return max(good, key=lambda r: r["pressure_kpa"])
    for r in good:
        if same_pressure(r["pressure_kpa"], pressure_kpa):
            return r
    return None


def _packed(attrs: dict[str, Any]) -> dict[str, Any]:
    """Few user attributes (each is one database commit): rows, design, metrics (scalars) and,
    for a constrained optimisation, the constraints (optuna's constraints_func reads them)."""
    top = ("rows", "design", "constraints", "constraint_names")
    return {k: attrs[k] for k in top if k in attrs} | {
        "metrics": {k: v for k, v in attrs.items() if k not in top}
    }


def evaluate_epsa(
    params: Mapping[str, Any], fixed: Mapping[str, Any], settings: Mapping[str, Any]
) -> Evaluation:
    """Evaluate one ePSA design (parameters named in ``SIMULATOR_PARAMS``, e.g. the end load of
    the identification study, go to the simulator as keywords). ``settings``: material,
    pressures_kpa, quick, mesh_size,
    simulate ("module:function", default ``studies.epsa.response:simulate_epsa``), objectives
    ("sweep": extension at the highest computed pressure; "pareto": extension and radial
    expansion at the highest requested pressure, plus the fiber length of both helices; the
    optimiser's constrained objective wraps this, `studies.epsa.constrained_objective`).

    A curve with ``converged = False`` fails the trial (its rows are kept). In "pareto" mode a
    design that does not reach the highest pressure fails too: it does not meet the requirement.
    """
    merged = {**fixed, **params}
    load = {k: merged.pop(k) for k in SIMULATOR_PARAMS if k in merged}
    design = EPSADesign(**merged)
    simulate = load_callable(settings.get("simulate", EPSA_SIMULATOR), parameter="simulator")
    pressures = tuple(float(p) for p in settings.get("pressures_kpa", PAPER_PRESSURES_KPA))
    kwargs = {
        "material": settings.get("material", "ecoflex-00-50"),
        "pressures_kpa": pressures,
        "mesh_size": settings.get("mesh_size"),
        "quick": bool(settings.get("quick", False)),
    }
    kwargs |= {k: float(v) for k, v in load.items()}
    if "fibers" in settings and "fibers" in _parameters(simulate):
        kwargs["fibers"] = settings["fibers"]
    vtu_path = None
    if settings.get("vtu_dir") and "keep_model" in _parameters(simulate):
        kwargs["keep_model"] = True
        tag = "_".join(
            f"{k}-{v:g}" if isinstance(v, (int, float)) else f"{k}-{v}" for k, v in sorted(params.items())
        )
        vtu_path = Path(settings["vtu_dir"]) / f"{tag}.vtu"
    solved = simulate(design, **kwargs)
    curve = getattr(solved, "curve", solved)
    attrs = curve_to_attrs(curve)
    if vtu_path is not None:
        attrs["vtu"] = _write_shape(solved, vtu_path)
    attrs |= {
        "design": design.to_dict(),
        "mass_g": design_mass_g(design, kwargs["material"]),
        "fiber_length_mm": fiber_length_mm(design),
    }
    length0, radius0 = design.length, design.outer_radius
    for row in attrs["rows"]:  # the FE's own undeformed measure (may include the seal head)
        if row.get("status") == "reference" and row.get("length_mm") is not None:
            length0, radius0 = row["length_mm"], row["outer_radius_mm"]
    top = response_at(attrs["rows"])
    if top is None and attrs["converged"] and attrs["limit_pressure_kpa"] is not None:
        # a limit point below the first target pressure: the result is the path up to it
        path = [
            r
            for r in attrs["rows"]
            if r.get("status") in ("converged", "volume-control") and r.get("length_mm") is not None
        ]
        top = max(path, key=lambda r: r["pressure_kpa"], default=None)
    if top is not None:
        attrs["extension_mm"] = top["length_mm"] - length0
        attrs["radial_expansion_mm"] = top["outer_radius_mm"] - radius0
        attrs["top_pressure_kpa"] = top["pressure_kpa"]
    if not attrs["converged"]:
        return Evaluation(
            ok=False, attrs=_packed(attrs), message=f"diverged: {attrs['message'] or 'no reason given'}"
        )
    if top is None:
        return Evaluation(ok=False, attrs=_packed(attrs), message="no computed state")
    if settings.get("objectives", "sweep") == "pareto":
        target = max(pressures)
        at = response_at(attrs["rows"], target)
        if at is None or (attrs["limit_pressure_kpa"] is not None and attrs["limit_pressure_kpa"] < target):
            return Evaluation(
                ok=False,
                attrs=_packed(attrs),
                message=(f"does not reach {target:g} kPa (limit pressure {attrs['limit_pressure_kpa']} kPa)"),
            )
        # the radius should stay at its design value: growing presses on a pipe wall, shrinking
        # loosens the robot's body; so the objective is the size of the change, |dR|
        values = (at["length_mm"] - length0, abs(at["outer_radius_mm"] - radius0), attrs["fiber_length_mm"])
        return Evaluation(ok=True, values=values, attrs=_packed(attrs))
    return Evaluation(ok=True, values=(attrs["extension_mm"],), attrs=_packed(attrs))


def _parameters(fn) -> set[str]:
    import inspect

    try:
        return set(inspect.signature(fn).parameters)
    except (TypeError, ValueError):
        return set()


def _write_shape(solved, path: Path) -> str:
    """VTU of the last computed state of a ``Solved`` (curve, model, path), with its pressure and
    load factor as field data, and of its winding beside it (``NAME.winding.vtu``); "" if
    unavailable. The path is returned relative to the study folder (``vtu/NAME.vtu``), so that
    the tables hold no path of the machine that made them. Both files are written atomically (no
    partial file). A shape that cannot be written never fails the evaluation, except for a fault
    of the machine (a full disk, an unwritable folder), which the sweep engine turns into a
    handed-back point."""
    try:
        steps = solved.path.steps
        if not steps:
            return ""
        last = steps[-1]
        load = {"pressure_mpa": last.pressure, "factor": last.factor}
        with atomic_path(path) as temp:
            write_state(temp, solved.model, last.x, **load)
        with atomic_path(path.with_suffix(".winding.vtu")) as temp:
            write_winding(temp, solved.model, last.x, **load)
        return f"{path.parent.name}/{path.name}"
    except Exception as exc:  # a shape that cannot be written is noted in the table
        if machine_fault(exc) is not None:
            raise
        return f"not written: {type(exc).__name__}: {exc}"


def fiber_length_mm(design) -> float:
    """Kevlar thread of the double helix (both helices; 0 without fibers)."""
    return 2.0 * design.helix_length if design.fiber_turns > 0 else 0.0


def design_mass_g(design, material: str) -> float | None:
    """Silicone body plus Kevlar thread (g); None if the material is unknown to materials."""
    try:
        rho = get_material(material).density
        kevlar = get_material("kevlar").density
    except Exception:  # noqa: BLE001 - a fake material in tests
        return None
    thread = fiber_length_mm(design) * math.pi * design.fiber_diameter**2 / 4
    return (rho * design.body_volume + kevlar * thread) * 1e6  # t -> g
