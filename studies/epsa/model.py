r"""The FE model of one ePSA: the swept mesh, the materials, the winding, the end conditions.

    design (EPSADesign) -> swept tetrahedral mesh with the ABS seal head (geometry.swept) -> P2-P1
    solid (fem.model) with the chamber pressure on the chamber wall and ends, the base z = 0 fixed,
    and the Kevlar double helix as fiber sheets or embedded lines

Body and seal head. The body is the silicone `material` (a `materials` preset, `NAME@mu=VALUE`
allowed); the ABS seal head on top is tied to it (one mesh) and is a stiff Neo-Hookean solid with
the ABS shear and bulk moduli: at 20-100 kPa its strains are ~1e-4, so the hyperelastic and the
linear-elastic ABS agree. Each material has its own P1 pressure field (`fem.model`, per-material
pressure groups): a field continuous across the silicone/ABS interface is wrong there
(docs/decisions/044-pressure-fields.md; the length at 100 kPa changes by 1.5e-5).

Winding (`FIBER_MODELS`). "sheet", the default: the double helix smeared over the outer surface
as two fiber families (`fem.sheets`, `geometry.epsa_shape.helix_families`); it converges under
mesh refinement. "lines": the paper's embedded trusses on the helix polylines (`fem.fibers`);
they do not converge (docs/decisions/014-winding.md).

End conditions. The base z = 0 is fixed (glued to the robot's foot). Free: the seal head's top is
free. Blocked: the top is fixed too (the blocked force of the paper's Fig. 19). Guided: the top
keeps to the axis (u_x = u_y = 0, u_z free); the free actuator is a slender pressurised column that
can bend over sideways, and in the robot the rings and the two other actuators hold it, so a guide
is the single-actuator equivalent.

End load (N, the static identification of Section VII-A): a weight W on the seal head, a dead
force -W e_z that opposes the extension (eq. 3 with the load beside m g), with the top guided as a
weight on a guide: an unguided compressive dead load buckles the fixed-free silicone column at the
Euler load pi^2 E I / (4 L^2) ~ 0.1 N (mu = 0.03 MPa), which the paper's weights (~1 N) would have
done. The guide removes that mode and leaves the axial response that eq. 3 describes.

Side load (N): a small dead force +x on the free top, an imperfection that shows whether the free
actuator bends over. The smeared sheet is mirror-symmetric, so without it a Newton path can follow
the straight (unstable) branch past a bending bifurcation; the helix ends of the line fibers are a
built-in imperfection of this kind.

Mesh. `MeshSettings` of the swept mesher; the presets are "default" (the converged mesh of the
convergence study, `softcrawl epsa --convergence`) and "quick" (coarse, for CI and quick sweeps).
An impossible design or option raises `DesignError` (it names the parameter) before anything is
computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from softcrawl.checks import number
from softcrawl.fem.fibers import FiberLines
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.sheets import FiberSheet
from softcrawl.geometry.design import MAX_DIMENSION, DesignError, EPSADesign
from softcrawl.geometry.epsa_shape import helix_families
from softcrawl.geometry.swept import mesh_epsa_swept
from softcrawl.materials import Material, get_material
from softcrawl.materials.fem_law import solid_law

#: Smallest element size of an ePSA mesh (mm): a tenth of a millimetre, 25 times finer than the
#: finest mesh of the convergence study (h = 2.5 mm, whose extension differs from h = 3.33 mm by
#: 0.003-0.09 %). A mesh that fine of any ePSA exceeds MAX_MESH_TETS anyway; the bound keeps the
#: element counts finite (h = 5e-324 overflowed them).
MIN_MESH_SIZE = 0.1
#: Most tetrahedra of an ePSA mesh (estimated before meshing, `estimated_tets`). The finest mesh
#: run so far (h = 2.5 mm, 34k tets, 165k unknowns) took 11 min on 2 cores; a sparse direct solve
#: grows faster than linearly in time and memory, so 200k tets (~1M unknowns) is hours and many GB.
MAX_MESH_TETS = 200_000


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
        h = number(h, "mesh_size", minimum=MIN_MESH_SIZE, maximum=MAX_DIMENSION, unit="mm", error=DesignError)
        wall = design.outer_radius - design.chamber_radius
        n_around = max(12, 4 * math.ceil(2 * math.pi * design.outer_radius / (4 * 0.8 * h)))
        return cls(
            n_around=n_around,
            n_radial=max(1, round(1.5 * wall / h)),
            axial_size=float(h),
            fiber_points_per_turn=max(32, 2 * n_around),
        )


def estimated_tets(settings: MeshSettings, design: EPSADesign) -> float:
    """An upper estimate of the swept mesh's tetrahedra: 6 n_around (n_radial + 1) per axial layer
    (3 tets per prism; the chamber ends fill the chamber too) over L / h + t_s / h + 4 layers. It
    is 1.1-1.6 times the count of the presets and of the h = 2.5 mm mesh."""
    layers = (design.length + design.seal_head_thickness) / settings.axial_size + 4
    return 6.0 * settings.n_around * (settings.n_radial + 1) * layers


def resolve_mesh(
    design: EPSADesign,
    mesh: MeshSettings | str = "default",
    mesh_size: float | None = None,
    quick: bool = False,
) -> MeshSettings:
    """The mesh settings of a run (`mesh_size` wins over `quick`, which wins over `mesh`), checked
    against `MAX_MESH_TETS` before anything is meshed."""
    if mesh_size is not None:
        settings = MeshSettings.from_size(mesh_size, design)
    elif quick:
        settings = MESH_PRESETS["quick"]
    elif isinstance(mesh, MeshSettings):
        settings = mesh
    elif mesh in MESH_PRESETS:
        settings = MESH_PRESETS[mesh]
    else:
        raise DesignError("mesh", f"{mesh!r} is not one of {tuple(MESH_PRESETS)} or MeshSettings")
    tets = estimated_tets(settings, design)
    if tets > MAX_MESH_TETS:
        raise DesignError(
            "mesh_size",
            f"the mesh of this ePSA would have ~{tets:.3g} tetrahedra (h = {settings.axial_size:g} mm, "
            f"L = {design.length:g} mm); at most {MAX_MESH_TETS}: use a larger element size",
        )
    return settings


#: How the Kevlar winding is modelled (`build_model`). The default is the smeared sheet, because
#: it converges under mesh refinement and the lines do not (Table 1 ePSA, mu = 0.0634 MPa, 100 kPa,
#: extension at h = 10 / 5 / 3.33 mm: sheet 56.6 / 57.2 / 57.6 mm, lines 56.8 / 61.7 / 64.3 mm;
#: results/epsa-convergence), and it is 3.5x faster on the default mesh (13 s against 47 s).
#: The lines stay for the paper's embedded-truss (Abaqus "embedded element") model and for fiber
#: tension at the strands.
FIBER_MODELS = ("lines", "sheet")
DEFAULT_FIBERS = "sheet"

MESH_PRESETS = {"default": MeshSettings(), "quick": MeshSettings(n_around=12, n_radial=1, axial_size=10.0)}


def solid_material(name):
    """The `materials` preset (or Material) of the body and its solver law."""
    mat = name if isinstance(name, Material) else get_material(name)
    return mat, solid_law(mat, hyperelastic_only=True)


#: Largest sideways probe (N). The probe is an imperfection (1e-4 N in the studies); the pressure
#: force on the chamber end at 100 kPa is ~2.8 N, so above 0.1 N it is a load, not a probe.
MAX_SIDE_LOAD_N = 0.1
#: Largest end load (N): 100 N, a hundred times the paper's weights (0.5-1 N) and 35 times the
#: actuator's ~2.8 N chamber-end force at 100 kPa.
MAX_END_LOAD_N = 100.0


def check_end_conditions(blocked: bool, guided: bool, end_load_n, side_load_n) -> None:
    """The end conditions of the module docstring exclude each other as stated there."""
    if side_load_n is not None:
        number(
            side_load_n,
            "side_load",
            minimum=0.0,
            min_open=True,
            maximum=MAX_SIDE_LOAD_N,
            unit="N",
            error=DesignError,
        )
    if side_load_n is not None and (blocked or guided or end_load_n is not None):
        raise DesignError(
            "side_load", "the sideways probe is for the free actuator (no guide, block or weight)"
        )
    if blocked and (end_load_n is not None or guided):
        raise DesignError("blocked", "a blocked actuator (top fixed) takes no end load and no guide")
    if end_load_n is not None:
        number(end_load_n, "end_load", minimum=0.0, maximum=MAX_END_LOAD_N, unit="N", error=DesignError)


def _end_conditions(blocked: bool, guided: bool, end_load_n, side_load_n):
    """Dirichlet conditions and dead loads of the end conditions (module docstring)."""
    bcs = [Dirichlet.fixed("end_bottom")] + ([Dirichlet.fixed("seal_top")] if blocked else [])
    dead_loads = None
    if end_load_n is not None or guided:
        bcs.append(Dirichlet("seal_top", (0, 1), (0.0, 0.0)))
    if end_load_n is not None:
        dead_loads = {"seal_top": (0.0, 0.0, -float(end_load_n))}
    if side_load_n is not None:
        dead_loads = {"seal_top": (float(side_load_n), 0.0, 0.0)}
    return bcs, dead_loads


def _winding(design: EPSADesign, fibers: str, tagged, kevlar):
    """(line fibers, fiber sheets) of the winding model `fibers` (one of them is empty)."""
    if fibers == "lines":
        lines = (
            FiberLines(tagged.fibers, kevlar.youngs_modulus, design.fiber_diameter) if tagged.fibers else None
        )
        return lines, ()
    axial = kevlar.youngs_modulus * math.pi * design.fiber_diameter**2 / 4
    return None, [
        FiberSheet("outer", direction, axial, density) for direction, density in helix_families(design)
    ]


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
    """The actuator model of the module docstring: (SolidModel, body Material, MeshSettings)."""
    if fibers not in FIBER_MODELS:
        raise DesignError("fibers", f"{fibers!r} is not one of {FIBER_MODELS}")
    check_end_conditions(blocked, guided, end_load_n, side_load_n)
    settings = resolve_mesh(design, mesh)
    mat, body_law = solid_material(material)
    tagged = mesh_epsa_swept(
        design,
        n_around=settings.n_around,
        n_radial=settings.n_radial,
        axial_size=settings.axial_size,
        fiber_points_per_turn=settings.fiber_points_per_turn,
        seal_head=True,
    )
    bcs, dead_loads = _end_conditions(blocked, guided, end_load_n, side_load_n)
    lines, sheets = _winding(design, fibers, tagged, get_material(fiber_material))
    model = SolidModel(
        tagged.to_skfem(order=2),
        {"epsa": body_law, "seal_head": solid_law(get_material(seal_material))},
        dirichlet=bcs,
        chambers=("chamber_wall", "chamber_ends"),
        fibers=lines,
        dead_loads=dead_loads,
        fiber_sheets=sheets,
    )
    return model, mat, settings
