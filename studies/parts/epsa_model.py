"""The ePSA evaluator: one pure entry point from a design to its pressure-response curve.

    design (EPSADesign) -> swept tetrahedral mesh with the ABS seal head (geometry.swept) -> P2-P1
    solid model with the chamber pressure, the end z = 0 fixed (and the seal head's top fixed too
    for the blocked force) and the Kevlar double helix as embedded trusses (fem) -> pressure ramp with
    limit-point continuation
    (fem.path) -> one CurveRow per converged state (fem.post).

Everything the sweeps, the optimiser and the CLI know about an actuator comes from here. A solve
that diverges is not an exception: the curve comes back with `converged = False`, the rows it
reached, a "failed" row for every pressure it did not reach, and the solver's message. An
impossible design raises `DesignError` (it names the parameter) before anything is computed.

Mesh. `MeshSettings` of the swept mesher; the presets are "default" (the converged mesh of the
convergence study, `softcrawl epsa --convergence`) and "quick" (coarse, for CI and quick sweeps).
Material: a preset name of `materials` (Neo-Hookean), converted to MPa constants here.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field

import numpy as np

from geometry.design import DesignError, EPSADesign

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


@dataclass(frozen=True, kw_only=True)
class MeshSettings:
    n_around: int = 16
    n_radial: int = 2
    axial_size: float = 5.0  # mm
    fiber_points_per_turn: int = 32

    @classmethod
    def from_size(cls, h: float, design: EPSADesign) -> MeshSettings:
        """A mesh of element size about h (mm): axial h, at most 0.8 h around the outer surface
        (a multiple of 4 cells, at least 12), ~h/1.5 across the wall, and at least two fiber
        points per cell around. For the Table 1 ePSA, h = 10 and 5 mm give the "quick" and
        "default" presets, so a convergence study over sizes contains both."""
        if not (isinstance(h, (int, float)) and h > 0 and math.isfinite(h)):
            raise DesignError("mesh_size", f"must be a positive length in mm, got {h}")
        wall = design.outer_radius - design.chamber_radius
        n_around = max(12, 4 * math.ceil(2 * math.pi * design.outer_radius / (4 * 0.8 * h)))
        return cls(
            n_around=n_around,
            n_radial=max(1, round(1.5 * wall / h)),
            axial_size=float(h),
            fiber_points_per_turn=max(32, 2 * n_around),
        )


#: How the Kevlar winding is modelled (`build_model`). The default is the smeared sheet, because
#: it converges under mesh refinement and the lines do not (Table 1 ePSA, mu = 0.0634 MPa, 100 kPa,
#: extension at h = 10 / 5 / 3.33 mm: sheet 56.6 / 57.2 / 57.6 mm, lines 56.8 / 61.7 / 64.3 mm;
#: results/epsa-convergence), and it is 3.5x faster on the default mesh (13 s against 47 s).
#: The lines stay for the paper's embedded-truss (Abaqus "embedded element") model and for fiber
#: tension at the strands.
FIBER_MODELS = ("lines", "sheet")
DEFAULT_FIBERS = "sheet"

MESH_PRESETS = {"default": MeshSettings(), "quick": MeshSettings(n_around=12, n_radial=1, axial_size=10.0)}


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


def solid_material(name):
    """The `materials` preset (or Material) of the body and its solver law."""
    from materials import Material, get_material
    from materials.fem_law import solid_law

    mat = name if isinstance(name, Material) else get_material(name)
    return mat, solid_law(mat, hyperelastic_only=True)


def build_model(
    design: EPSADesign,
    material="ecoflex-00-50",
    mesh: MeshSettings | str = "default",
    blocked: bool = False,
    fiber_material: str = "kevlar",
    seal_material: str = "abs",
    end_load_n: float | None = None,
    guided: bool = False,
    fibers: str = DEFAULT_FIBERS,
    side_load_n: float | None = None,
):
    """The actuator model: body (Neo-Hookean `material`), ABS seal head on top (tied, stiff
    Neo-Hookean with the ABS shear and bulk moduli: at 20-100 kPa its strains are ~1e-4, so the
    hyperelastic and linear-elastic ABS agree), Kevlar fibers, base z = 0 fixed (glued to the
    robot's foot); with `blocked`, the seal head's top face is fixed too. With `guided`, the seal
    head's top keeps to the axis (u_x = u_y = 0, u_z free): the free actuator is a slender
    pressurised column that can bend over sideways (see `simulate_epsa`); in the robot the rings and
    the two other actuators hold it, and a guide is the single-actuator equivalent.

    `end_load_n` (N, the static identification of Section VII-A): a weight W on the seal head,
    a dead force -W e_z that opposes the extension (eq. 3 with the load beside m g). The seal
    head's top is then guided (u_x = u_y = 0, u_z free), as a weight on a guide: an unguided
    compressive dead load buckles the fixed-free silicone column already at the Euler load
    pi^2 E I / (4 L^2) ~ 0.1 N (mu = 0.03 MPa), which the paper's weights (~1 N) would have done.
    The guide removes that mode and leaves the axial response that eq. 3 describes.

    `fibers` (see FIBER_MODELS): "lines", the paper's embedded trusses on the helix polylines
    (`fem.fibers`), or "sheet", the double helix smeared over the outer surface as two fiber
    families (`fem.sheets`, `geometry.epsa_shape.helix_families`).

    `side_load_n` (N): a small dead force +x on the seal head's top, an imperfection that shows
    whether the free actuator bends over. The smeared sheet is mirror-symmetric, so without it a
    Newton path can follow the straight (unstable) branch past a bending bifurcation; the helix
    ends of the line fibers are a built-in imperfection of this kind."""
    from fem.fibers import FiberLines
    from fem.model import Dirichlet, SolidModel
    from fem.sheets import FiberSheet
    from geometry.epsa_shape import helix_families
    from geometry.swept import mesh_epsa_swept
    from materials import get_material
    from materials.fem_law import solid_law

    if fibers not in FIBER_MODELS:
        raise DesignError("fibers", f"{fibers!r} is not one of {FIBER_MODELS}")
    if side_load_n is not None and not (math.isfinite(side_load_n) and side_load_n > 0):
        raise DesignError("side_load", f"must be a small force > 0 N, got {side_load_n}")
    if side_load_n is not None and (blocked or guided or end_load_n is not None):
        raise DesignError(
            "side_load", "the sideways probe is for the free actuator (no guide, block or weight)"
        )
    settings = MESH_PRESETS[mesh] if isinstance(mesh, str) else mesh
    mat, neo = solid_material(material)
    tagged = mesh_epsa_swept(
        design,
        n_around=settings.n_around,
        n_radial=settings.n_radial,
        axial_size=settings.axial_size,
        fiber_points_per_turn=settings.fiber_points_per_turn,
        seal_head=True,
    )
    if blocked and (end_load_n is not None or guided):
        raise DesignError("blocked", "a blocked actuator (top fixed) takes no end load and no guide")
    if end_load_n is not None and not (math.isfinite(end_load_n) and end_load_n >= 0):
        raise DesignError("end_load", f"must be a weight >= 0 N, got {end_load_n}")
    bcs = [Dirichlet.fixed("end_bottom")] + ([Dirichlet.fixed("seal_top")] if blocked else [])
    dead_loads = None
    if end_load_n is not None or guided:
        bcs.append(Dirichlet("seal_top", (0, 1), (0.0, 0.0)))
    if end_load_n is not None:
        dead_loads = {"seal_top": (0.0, 0.0, -float(end_load_n))}
    if side_load_n is not None:
        dead_loads = {"seal_top": (float(side_load_n), 0.0, 0.0)}
    kevlar, abs_ = get_material(fiber_material), get_material(seal_material)
    materials = {"epsa": neo, "seal_head": solid_law(abs_)}
    axial = kevlar.youngs_modulus * math.pi * design.fiber_diameter**2 / 4
    lines = fibers == "lines"
    sheets = (
        ()
        if lines
        else [FiberSheet("outer", direction, axial, density) for direction, density in helix_families(design)]
    )
    model = SolidModel(
        tagged.to_skfem(order=2),
        materials,
        dirichlet=bcs,
        chambers=("chamber_wall", "chamber_ends"),
        fibers=FiberLines(tagged.fibers, kevlar.youngs_modulus, design.fiber_diameter)
        if lines and tagged.fibers
        else None,
        dead_loads=dead_loads,
        fiber_sheets=sheets,
    )
    return model, mat, settings


def parse_pressures(spec: str) -> tuple[float, ...]:
    """'0:100:20' -> (20, 40, 60, 80, 100) (kPa; the 0 kPa reference row is always written);
    '10,30,50' -> (10, 30, 50)."""
    try:
        if ":" in spec:
            a, b, s = (float(v) for v in spec.split(":"))
            if s <= 0 or b <= a:
                raise ValueError
            values = np.arange(a, b + 1e-9 * s, s)
        else:
            values = np.array([float(v) for v in spec.split(",")])
    except ValueError:
        raise DesignError("pressures", f"{spec!r} is not START:STOP:STEP or a comma list (kPa)") from None
    values = values[values > 0]
    if values.size == 0 or np.any(np.diff(values) <= 0) or values.max() > 1000:
        raise DesignError("pressures", f"{spec!r}: give increasing pressures in (0, 1000] kPa")
    return tuple(float(v) for v in values)


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
    """Simulate the closed actuator under a pressure ramp. Returns an `ActuatorCurve`
    (or `Solved` with the model and path when `keep_model`).

    Every row records the sideways displacement of the top face (`tip_lateral_mm`). A free
    actuator whose top sways by more than `SWAY_WARNING` of its length gets an event that says
    so: the long, soft, pressurised tube bending over like an Euler strut (an asymmetric, bending
    bifurcation of the inflated tube; see Haughton & Ogden, J. Mech. Phys. Solids 27, 1979, for
    such modes of inflated thick tubes). The smeared sheet is mirror-symmetric, so a run that
    should be checked for such a mode needs `side_load_n`, a small sideways imperfection.
    Measured (Table 1 ePSA, mu = 0.03 MPa, default mesh): with the sheet and a 1e-4 / 1e-3 N probe
    the tip moves 0.39 / 4.0 mm at 60 kPa and 1.4 / 10.5 mm at 100 kPa (290 mm long): the sway
    follows the probe, the straight path is stable to 100 kPa. The line fibers instead bend over
    (tip 3.6 / 34.5 mm off the axis at 40 / 60 kPa, limit point 69.1 kPa; guided, the path fails at
    57.3 kPa): their unconverged bulging between strands softens the wall, and their strand
    crossings all lie in one plane, so we take that as an artefact of the line model.

    With `end_load_n` or `side_load_n` (see `build_model`) the load is put on first, at 0 kPa (a
    "converged" row at 0 kPa), and stays on through the ramp."""
    from fem.path import load_path
    from fem.post import actuator_length, max_principal_stretch, outer_radius_at

    t0 = time.perf_counter()
    if quick:
        mesh = "quick"
    if mesh_size is not None:
        mesh = MeshSettings.from_size(mesh_size, design)
    pressures = tuple(float(p) for p in pressures_kpa)
    if not pressures or min(pressures) <= 0:
        raise DesignError("pressures", "give positive pressures in kPa")
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
    top_nodes = model.boundary_nodes("end_top")
    factor = 0.0 if end_load_n is None and side_load_n is None else 1.0

    def row(step, status):
        x = step.x
        tension = model.fiber_tension(x)
        force = -model.reaction(x, "seal_top", step.pressure)[2] if blocked else float("nan")
        sway = float(np.hypot(*model.displacement(x)[:2, top_nodes].mean(axis=1)))
        return CurveRow(
            step.pressure * 1e3,
            actuator_length(model, x),
            outer_radius_at(model, x, design.length / 2),
            step.volume,
            max_principal_stretch(model, x),
            float(tension.max()) if tension.size else 0.0,
            status,
            float(force),
            sway,
        )

    def on_step(step):
        if progress is not None:
            progress(
                f"P = {step.pressure * 1e3:7.2f} kPa  ({step.control} control, "
                f"{step.newton.iterations} Newton iterations)"
            )

    targets = [(p * 1e-3, factor) for p in pressures]
    result = load_path(model, ([(0.0, 1.0)] if factor else []) + targets, on_step=on_step)
    x0 = model.initial_state()
    from fem.path import NewtonRecord, Step

    rows = [
        row(Step(0.0, 0.0, model.chamber_volume(x0), x0, "pressure", NewtonRecord((0.0,), True)), "reference")
    ]
    rows += [row(s, "volume-control" if s.past_limit else "converged") for s in result.steps]
    reached = max([s.pressure for s in result.steps if not s.past_limit], default=0.0) * 1e3
    nan = float("nan")
    if not result.converged:
        rows += [
            CurveRow(p, nan, nan, nan, nan, nan, "failed")
            for p in pressures
            if p > reached and not same_pressure(reached, p)
        ]
    limit = None if result.limit_pressure is None else result.limit_pressure * 1e3
    events = tuple(result.events) + _sway_events(rows)
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
