"""VTU export of solved states for ParaView (meshio), one file per step plus a .pvd time series.

The P2 displacement is written at the mesh vertices (exact nodal values) on the linear
tetrahedra; stresses and stretches as cell data (quadrature averages, `fem.post`).
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np

from fem.model import SolidModel
from fem.post import element_fields


def write_state(path, model: SolidModel, x: np.ndarray, extra_cell_data: dict | None = None) -> Path:
    path = Path(path)
    mesh = model.mesh
    n_v = mesh.p.shape[1]
    u = model.displacement(x)[:, :n_v].T
    fields = element_fields(model, x)
    s = fields.cauchy
    cell = {
        "von_mises_MPa": fields.von_mises,
        "cauchy_MPa": np.stack([s[0, 0], s[1, 1], s[2, 2], s[0, 1], s[1, 2], s[0, 2]], axis=1),
        "max_principal_stretch": fields.max_stretch,
        "hydrostatic_pressure_MPa": fields.pressure,
        "J": fields.jacobian,
    }
    if mesh.subdomains:
        region = np.full(mesh.t.shape[1], -1)
        for k, (_name, elems) in enumerate(sorted(mesh.subdomains.items())):
            region[elems] = k
        cell["region"] = region
    for k, v in (extra_cell_data or {}).items():
        cell[k] = np.asarray(v)
    out = meshio.Mesh(
        mesh.p.T,
        [("tetra", mesh.t.T)],
        point_data={"displacement_mm": u},
        cell_data={k: [v] for k, v in cell.items()},
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    out.write(path)
    return path


def write_path(directory, model: SolidModel, result, stem="step") -> list[Path]:
    """One VTU per converged step and `{stem}.pvd` (time value = pressure in kPa)."""
    directory = Path(directory)
    files = []
    for k, step in enumerate(result.steps):
        files.append(write_state(directory / f"{stem}_{k:03d}.vtu", model, step.x))
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
    for f, step in zip(files, result.steps):
        lines.append(f'<DataSet timestep="{step.pressure * 1e3:.6g}" file={quoteattr(f.name)}/>')
    lines += ["</Collection>", "</VTKFile>"]
    (directory / f"{stem}.pvd").write_text("\n".join(lines) + "\n")
    return files
