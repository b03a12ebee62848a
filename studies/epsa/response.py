r"""The ePSA under a pressure ramp: one pure entry point from a design to its response curve.

    design -> `studies.epsa.model.build_model` -> pressure ramp with limit-point continuation
    (fem.path) -> one `CurveRow` per computed state (fem.post)

Everything the sweeps, the optimiser and the CLI know about an actuator's response comes from
here. A solve that diverges is not an exception: the curve comes back with `converged = False`,
the rows it reached, a "failed" row for every pressure it did not reach, and the solver's message.

Bending over. Every row records the sideways displacement of the top face (`tip_lateral_mm`). A
free actuator whose top sways by more than `SWAY_WARNING` of its length gets an event that says
so: the long, soft, pressurised tube bending over like an Euler strut (an asymmetric, bending
bifurcation of the inflated tube; Haughton & Ogden, J. Mech. Phys. Solids 27, 1979, treat such
modes of inflated thick tubes). The smeared sheet is mirror-symmetric, so a run that should be
checked for such a mode needs a side load, a small sideways imperfection. Measured (Table 1 ePSA,
mu = 0.03 MPa, default mesh): with the sheet and a 1e-4 / 1e-3 N probe the tip moves 0.39 / 4.0 mm
at 60 kPa and 1.4 / 10.5 mm at 100 kPa (290 mm long): the sway follows the probe, the straight
path is stable to 100 kPa. The line fibers instead bend over (tip 3.6 / 34.5 mm off the axis at
40 / 60 kPa, limit point 69.1 kPa; guided, the path fails at 57.3 kPa): their unconverged bulging
between strands softens the wall, and their strand crossings all lie in one plane, so we take
that as an artefact of the line model.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from softcrawl.fem.path import NewtonRecord, Step, load_path
from softcrawl.fem.post import actuator_length, max_principal_stretch, outer_radius_at, volumetric_error
from softcrawl.geometry.design import DesignError, EPSADesign
from softcrawl.studies.epsa.model import DEFAULT_FIBERS, MeshSettings, build_model, resolve_mesh
from softcrawl.units import kpa_to_mpa, mpa_to_kpa

#: Row statuses: "reference" the undeformed 0 kPa state; "converged" the equilibrium at a requested
#: pressure (under pressure control, or landed on by volume control when pressure control stalled
#: on a rising path); "volume-control" a state past a limit point (the pressure falls there);
#: "failed" a requested pressure the solve did not reach.
STATUSES = ("reference", "converged", "volume-control", "failed")
#: A state "is at" a requested pressure within this relative tolerance: volume control lands on
#: a target to 1e-5 (fem.path), so a landed 100 kPa state may read 99.9999 kPa.
PRESSURE_MATCH_REL = 1e-4


def same_pressure(a: float, b: float) -> bool:
    """True when two pressures (kPa) name the same requested load (see PRESSURE_MATCH_REL)."""
    return abs(float(a) - float(b)) <= PRESSURE_MATCH_REL * max(1.0, abs(float(b)))


@dataclass(frozen=True)
class CurveRow:
    pressure_kpa: float
    length_mm: float
    outer_radius_mm: float
    chamber_volume_mm3: float
    max_principal_stretch: float
    max_fiber_tension_n: float
    status: str
    blocked_force_n: float = float("nan")
    tip_lateral_mm: float = float("nan")  # sideways displacement of the top face's centroid


@dataclass(frozen=True)
class ActuatorCurve:
    rows: tuple[CurveRow, ...]
    converged: bool
    limit_pressure_kpa: float | None
    message: str
    wall_s: float
    n_dofs: int
    material: str
    mu_mpa: float
    design: dict = field(default_factory=dict)
    mesh: dict = field(default_factory=dict)
    events: tuple[str, ...] = ()
    fibers: str = ""  # the winding model (FIBER_MODELS), "" when not recorded
    material_law: str = ""  # the constitutive law and its constants (Material.law_label)
    #: |J - 1 - p/K| per computed state: [pressure_kpa, max, volume average] (fem.post)
    volumetric_error: tuple[tuple[float, float, float], ...] = ()

    def to_dict(self) -> dict:
        out = asdict(self)
        out["rows"] = [asdict(r) for r in self.rows]
        return out

    def column(self, name: str) -> np.ndarray:
        return np.array([getattr(r, name) for r in self.rows], dtype=float)

    def table(self, blocked: bool = False) -> list[dict[str, str]]:
        """curve.csv rows: numbers to 6 significant digits; the blocked force when `blocked`."""
        out = []
        for r in self.rows:
            row = {
                "pressure_kPa": r.pressure_kpa,
                "length_mm": r.length_mm,
                "outer_radius_mm": r.outer_radius_mm,
                "chamber_volume_mm3": r.chamber_volume_mm3,
                "max_principal_stretch": r.max_principal_stretch,
                "max_fiber_tension_N": r.max_fiber_tension_n,
            }
            row = {k: f"{float(v):.6g}" for k, v in row.items()}
            row |= {"status": r.status, "tip_lateral_mm": f"{r.tip_lateral_mm:.6g}"}
            if blocked:
                row["blocked_force_N"] = f"{r.blocked_force_n:.6g}"
            out.append(row)
        return out


@dataclass(frozen=True)
class Solved:
    """The curve plus what a caller needs to export shapes (model, path result)."""

    curve: ActuatorCurve
    model: object
    path: object


def simulate_epsa(
    design: EPSADesign,
    *,
    material="ecoflex-00-50",
    pressures_kpa=(20, 40, 60, 80, 100),
    mesh: MeshSettings | str = "default",
    mesh_size: float | None = None,
    quick: bool = False,
    blocked: bool = False,
    progress=None,
    keep_model: bool = False,
    end_load_n: float | None = None,
    guided: bool = False,
    fibers: str = DEFAULT_FIBERS,
    side_load_n: float | None = None,
):
    """Simulate the closed actuator under a pressure ramp. Returns an `ActuatorCurve` (or
    `Solved` with the model and path when `keep_model`). With `end_load_n` or `side_load_n`
    (`studies.epsa.model`) the load is put on first, at 0 kPa (a "converged" row at 0 kPa),
    and stays on through the ramp."""
    t0 = time.perf_counter()
    mesh = resolve_mesh(design, mesh, mesh_size, quick)
    pressures = tuple(float(p) for p in pressures_kpa)
    if not pressures or not all(math.isfinite(p) and p > 0 for p in pressures):
        raise DesignError("pressures", "give positive, finite pressures in kPa")
    model, mat, settings = build_model(
        design,
        material,
        mesh,
        blocked,
        end_load_n=end_load_n,
        guided=guided,
        fibers=fibers,
        side_load_n=side_load_n,
    )
    factor = 0.0 if end_load_n is None and side_load_n is None else 1.0
    row = _row_builder(model, design, blocked)

    def on_step(step):
        if progress is not None:
            progress(
                f"P = {mpa_to_kpa(step.pressure):7.2f} kPa  ({step.control} control, "
                f"{step.newton.iterations} Newton iterations)"
            )

    targets = [(kpa_to_mpa(p), factor) for p in pressures]
    result = load_path(model, ([(0.0, 1.0)] if factor else []) + targets, on_step=on_step)
    x0 = model.initial_state()
    rows = [
        row(Step(0.0, 0.0, model.chamber_volume(x0), x0, "pressure", NewtonRecord((0.0,), True)), "reference")
    ]
    rows += [row(s, "volume-control" if s.past_limit else "converged") for s in result.steps]
    reached = mpa_to_kpa(max([s.pressure for s in result.steps if not s.past_limit], default=0.0))
    nan = float("nan")
    if not result.converged:
        rows += [
            CurveRow(p, nan, nan, nan, nan, nan, "failed")
            for p in pressures
            if p > reached and not same_pressure(reached, p)
        ]
    limit = None if result.limit_pressure is None else mpa_to_kpa(result.limit_pressure)
    events = tuple(result.events) + _sway_events(rows)
    volumetric = tuple(row.volumetric)
    curve = ActuatorCurve(
        tuple(rows),
        bool(result.converged),
        limit,
        result.message,
        time.perf_counter() - t0,
        int(model.n_dofs),
        mat.name,
        float(mat.mu),
        design.to_dict(),
        asdict(settings),
        events,
        fibers,
        mat.law_label,
        volumetric,
    )
    return Solved(curve, model, result) if keep_model else curve


#: Tip sway (lateral top displacement) above this fraction of the current length (a tilt of ~3 deg)
#: is reported as bending. The helix ends alone tilt the Table 1 ePSA by ~1-2 % of its length.
SWAY_WARNING = 0.05


def _sway_events(rows) -> tuple[str, ...]:
    length0 = rows[0].length_mm
    for r in rows[1:]:
        ext = r.length_mm - length0
        if np.isfinite(r.tip_lateral_mm) and r.tip_lateral_mm > SWAY_WARNING * r.length_mm:
            return (
                f"the top sways sideways by {r.tip_lateral_mm:.3g} mm at P = {r.pressure_kpa:.4g} kPa "
                f"(extension {ext:.3g} mm): the free actuator bends over (Euler-type bending of "
                "an inflated tube); the length is then the axial projection. --guided keeps "
                "the top on the axis",
            )
    return ()


def _row_builder(model, design: EPSADesign, blocked: bool):
    """row(step, status) -> CurveRow of a computed state of `model`."""
    top_nodes = model.boundary_nodes("end_top")

    def row(step, status):
        x = step.x
        row.volumetric.append((mpa_to_kpa(step.pressure), *volumetric_error(model, x)))
        tension = model.fiber_tension(x)
        force = -model.reaction(x, "seal_top", step.pressure)[2] if blocked else float("nan")
        sway = float(np.hypot(*model.displacement(x)[:2, top_nodes].mean(axis=1)))
        return CurveRow(
            mpa_to_kpa(step.pressure),
            actuator_length(model, x),
            outer_radius_at(model, x, design.length / 2),
            step.volume,
            max_principal_stretch(model, x),
            float(tension.max()) if tension.size else 0.0,
            status,
            float(force),
            sway,
        )

    row.volumetric = []
    return row
