"""Mesh convergence of the ePSA model: extension and radius at the last pressure against h.

`mesh_convergence` runs the same design on meshes of element size h (coarse to fine, `MeshSettings.
from_size`); the relative change against the finest mesh is the discretisation error estimate
(`softcrawl epsa --convergence`, results/epsa-convergence).
"""

from __future__ import annotations

from dataclasses import dataclass

from softcrawl.geometry.design import EPSADesign
from softcrawl.studies.epsa.model import DEFAULT_FIBERS, MeshSettings
from softcrawl.studies.epsa.response import simulate_epsa


@dataclass(frozen=True)
class ConvergenceRow:
    mesh_size_mm: float
    n_dofs: int
    extension_mm: float
    outer_radius_mm: float
    wall_s: float
    status: str


def mesh_convergence(
    design: EPSADesign,
    *,
    material="ecoflex-00-50",
    pressure_kpa=100.0,
    sizes=(10.0, 5.0, 2.5),
    steps: int = 5,
    progress=None,
    fibers: str = DEFAULT_FIBERS,
) -> list[ConvergenceRow]:
    """Extension and outer radius at `pressure_kpa` against the element size (coarse to fine).

    The ramp to `pressure_kpa` uses `steps` equal targets. The relative change against the finest
    mesh is the discretisation error estimate; `softcrawl epsa --convergence` writes the table.
    """
    rows = []
    targets = tuple(pressure_kpa * (k + 1) / steps for k in range(steps))
    for h in sizes:
        curve = simulate_epsa(
            design,
            material=material,
            pressures_kpa=targets,
            mesh=MeshSettings.from_size(h, design),
            fibers=fibers,
        )
        last = curve.rows[-1]
        ok = curve.converged and abs(last.pressure_kpa - pressure_kpa) < 1e-6 * pressure_kpa
        rows.append(
            ConvergenceRow(
                h,
                curve.n_dofs,
                last.length_mm - design.length,
                last.outer_radius_mm,
                curve.wall_s,
                "converged" if ok else f"failed: {curve.message}",
            )
        )
        if progress is not None:
            progress(
                f"h = {h:g} mm: {curve.n_dofs} DOFs, extension {rows[-1].extension_mm:.4g} mm, "
                f"{curve.wall_s:.1f} s ({rows[-1].status})"
            )
    return rows


def convergence_table(rows: list[ConvergenceRow]) -> list[dict[str, object]]:
    """convergence.csv rows, with the change of the extension against the finest mesh (%)."""
    finest = rows[-1]
    return [
        {
            "mesh_size_mm": r.mesh_size_mm,
            "dofs": r.n_dofs,
            "extension_mm": f"{r.extension_mm:.6g}",
            "outer_radius_mm": f"{r.outer_radius_mm:.6g}",
            "change_vs_finest_pct": f"{100 * (r.extension_mm / finest.extension_mm - 1):.3g}",
            "wall_s": f"{r.wall_s:.1f}",
            "status": r.status,
        }
        for r in rows
    ]
