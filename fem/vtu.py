r"""VTU export of solved states for ParaView (meshio): one file per state plus .pvd series.

Solid (`write_state`). Every scalar P2 node that an element uses is a point (a vertex that the
mesher left outside every element is dropped) and every element a curved quadratic tetrahedron
(VTK type 24, meshio "tetra10"), so the geometry keeps its curved faces and no point is
orphaned. scikit-fem's P2 element numbers its dofs as the 4 vertices, then the 6 edges in the
order (0,1), (1,2), (0,2), (0,3), (1,3), (2,3) of the element's vertices; VTK's quadratic
tetrahedron wants the edges (0,1), (1,2), (2,0), (0,3), (1,3), (2,3): the same edges in the same
order (an edge midpoint has no direction), so the element dofs are written as they are
(tests/fem/test_vtu.py checks every midpoint against its VTK edge).

Point data: the displacement (mm, exact nodal values of the P2 field). Cell data (quadrature
averages, `fem.post`): Cauchy stress as a symmetric tensor with the components XX, YY, ZZ, XY, YZ,
XZ (ParaView's order), von Mises stress, hydrostatic pressure, J, the largest principal stretch, and
the region id. Field data in every file: `pressure_kPa` (chamber pressure, one value per chamber),
`load_factor` (the factor of prescribed displacements and dead loads) and one `region:NAME` array
per region holding the id that the `region` cell array uses for it (meshio cannot read VTK string
arrays, so the names travel as array names). Component names are VTK `ComponentName` attributes,
which meshio does not write: they are added to the XML after meshio wrote it.

Winding (`write_winding`). Where the model has fibers: the smeared sheets as curved quadratic
triangles (VTK type 22) of the wrapped surface with the fiber tension of each family (N per
fiber, the facet's quadrature average of E A (lam - 1)) and their maximum; the embedded lines as
line cells with the segment forces. The points carry the displacement, as in the solid file.

Series (`write_path`). The reference state (0 kPa, load factor 0) is step 0 of every series,
followed by the converged states of the path. The .pvd time of a state is the path parameter of
the ramp (`path_times`): the load travelled, in kPa, s_k = s_(k-1) + max_i |P_i,k - P_i,(k-1)| +
100 |f_k - f_(k-1)|. Up to a limit point with one driving pressure it equals the pressure; past
it, where the pressure falls under volume control, it keeps increasing, as ParaView's sorting by
time needs (decision 063; it was the step index). Each file's `pressure_kPa`,
`load_factor` and `path_parameter` are field data.

A wedge of a cyclic-symmetric body (`write_state(copies=N)`, the FE body's `--wedge 3`) is written
as the whole body: its mesh and fields turned into all N copies (`turned_copies`), `pressure_kPa`
repeated per copy; the regions keep the wedge's names (the copies of ePSA 1 are all `epsa1`).

Precision: float32 by default (points, point and cell data; half the bytes, 7 digits for a view),
``precision=64`` keeps float64 (the commands' ``--vtu-precision 64``).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np

from softcrawl.fem import sheets as sheet_mod
from softcrawl.fem.fibers import fiber_state, segment_forces
from softcrawl.fem.model import SolidModel
from softcrawl.fem.periodic_tie import rotation_z
from softcrawl.fem.post import element_fields
from softcrawl.units import mpa_to_kpa

#: VTK component names of the arrays that have more than one component.
VECTOR = ("X", "Y", "Z")
SYMMETRIC_TENSOR = ("XX", "YY", "ZZ", "XY", "YZ", "XZ")
#: scikit-fem's local edge order of a tetrahedron (vertex pairs), equal to VTK's up to direction.
SKFEM_TET_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))
VTK_TET10_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


#: Bits of the floating-point arrays a VTU gets unless the caller asks otherwise.
DEFAULT_PRECISION = 32


def _float(array, precision: int) -> np.ndarray:
    array = np.asarray(array)
    if array.dtype.kind != "f":
        return array
    return array.astype(np.float32 if precision == 32 else np.float64)


def check_precision(precision: int) -> int:
    if precision not in (32, 64):
        raise ValueError(f"VTU precision is 32 or 64 bits, got {precision!r}")
    return precision


def path_times(pressures_kpa, factors) -> list[float]:
    """The path parameter of each state (module docstring): strictly increasing (a state that
    moves no load gets 1e-6 kPa more than the previous one)."""
    times, last = [], None
    for p, f in zip(pressures_kpa, factors):
        p = np.atleast_1d(np.asarray(p, dtype=float))
        if last is None:
            times.append(0.0)
        else:
            dp = float(np.max(np.abs(p - last[0]))) if p.shape == last[0].shape else float(np.max(np.abs(p)))
            times.append(times[-1] + max(dp + 100.0 * abs(float(f) - last[1]), 1e-6))
        last = (p, float(f))
    return times


def _field_data(model: SolidModel, pressure_mpa, factor: float, time: float | None = None) -> dict:
    pressures = model.pressures(pressure_mpa) if model.chambers else np.atleast_1d(float(pressure_mpa))
    out = {
        "pressure_kPa": mpa_to_kpa(np.asarray(pressures, dtype=float)),
        "load_factor": np.array([float(factor)]),
    }
    if time is not None:
        out["path_parameter"] = np.array([float(time)])
    for k, name in enumerate(sorted(model.mesh.subdomains or {})):
        out[f"region:{name}"] = np.array([k])
    return out


def _write(path: Path, mesh: meshio.Mesh, components: dict[str, tuple[str, ...]], field_data: dict) -> Path:
    """meshio writes the VTU; then each named array gets its VTK ComponentName attributes and the
    grid its FieldData (meshio 5 reads VTU field data but does not write it)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    mesh.write(path)
    tree = ET.parse(path)
    for array in tree.iter("DataArray"):
        for i, label in enumerate(components.get(array.get("Name"), ())):
            array.set(f"ComponentName{i}", label)
    grid = tree.getroot().find("UnstructuredGrid")
    block = ET.Element("FieldData")
    for name, values in field_data.items():
        values = np.atleast_1d(values)
        kind = "Float64" if values.dtype.kind == "f" else "Int64"
        array = ET.SubElement(
            block, "DataArray", type=kind, Name=name, NumberOfTuples=str(values.size), format="ascii"
        )
        array.text = " ".join(repr(float(v)) if kind == "Float64" else str(int(v)) for v in values)
    grid.insert(0, block)
    tree.write(path, xml_declaration=True, encoding="utf-8")
    return path


def write_state(
    path,
    model: SolidModel,
    x: np.ndarray,
    *,
    pressure_mpa=0.0,
    factor: float = 0.0,
    extra_cell_data: dict | None = None,
    time: float | None = None,
    precision: int = DEFAULT_PRECISION,
    extra_field_data: dict | None = None,
    copies: int = 1,
) -> Path:
    """The solid at state `x` under chamber pressure `pressure_mpa` and load factor `factor`;
    `time`, the state's path parameter (`path_times`), goes into the field data too, and so do
    `extra_field_data` (name -> numbers; they replace a default of the same name). A model with
    contacts gets `contact_pressure_MPa` and `slip` (1 slipping, 0 sticking or free) at its points:
    the largest over the contact facets that share the point. `copies` > 1: the model is one wedge
    of 2 pi / copies of a cyclic-symmetric body (`fem.periodic_tie`), written as the whole body
    (`turned_copies`)."""
    check_precision(precision)
    path = Path(path)
    mesh = model.mesh
    space = model.space
    fields = element_fields(model, x)
    s = fields.cauchy
    cell = {
        "cauchy_stress_MPa": np.stack([s[0, 0], s[1, 1], s[2, 2], s[0, 1], s[1, 2], s[0, 2]], axis=1),
        "von_mises_MPa": fields.von_mises,
        "hydrostatic_pressure_MPa": fields.pressure,
        "J": fields.jacobian,
        "max_principal_stretch": fields.max_stretch,
    }
    if mesh.subdomains:
        region = np.full(mesh.t.shape[1], -1)
        for k, name in enumerate(sorted(mesh.subdomains)):
            region[mesh.subdomains[name]] = k
        cell["region"] = region
    for k, v in (extra_cell_data or {}).items():
        cell[k] = np.asarray(v)
    used, cells = _compact(space.elem_nodes)  # a mesher may leave a vertex that no element uses
    point = {"displacement_mm": model.displacement(x)[:, used].T}
    point |= {k: v[used] for k, v in contact_fields(model, x).items()}
    out = meshio.Mesh(
        _float(space.nodes[:, used].T, precision),
        [("tetra10", cells)],
        point_data={k: _float(v, precision) for k, v in point.items()},
        cell_data={k: [_float(v, precision)] for k, v in cell.items()},
    )
    components = {"displacement_mm": VECTOR, "cauchy_stress_MPa": SYMMETRIC_TENSOR}
    out = turned_copies(out, copies, {"displacement_mm"}, {"cauchy_stress_MPa"})
    field_data = _field_data(model, pressure_mpa, factor, time)
    field_data["pressure_kPa"] = np.tile(field_data["pressure_kPa"], copies)  # each copy's chambers
    field_data |= {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in (extra_field_data or {}).items()}
    return _write(path, out, components, field_data)


def turned_copies(mesh: meshio.Mesh, copies: int, vectors=(), tensors=()) -> meshio.Mesh:
    """A wedge's mesh and fields turned into all `copies` wedges about z, k = 0..copies-1: points
    R^k X, cells offset by k times the point count, the `vectors` (n, 3) turned, R^k v, the
    `tensors` (n, 6 in `SYMMETRIC_TENSOR` order) turned, R^k s R^-k, other fields repeated. The
    cuts' points appear once in each neighbouring wedge (ParaView's Clean merges them)."""
    if copies == 1:
        return mesh
    turns = [rotation_z(2 * np.pi * k / copies) for k in range(copies)]
    n = len(mesh.points)

    def turned(name, v, R):
        v = np.asarray(v)
        if name in vectors:
            return (v @ R.T).astype(v.dtype)
        if name in tensors:
            i, j = np.array([0, 1, 2, 0, 1, 0]), np.array([0, 1, 2, 1, 2, 2])
            full = np.zeros((len(v), 3, 3))
            full[:, i, j] = v
            full[:, j, i] = v
            full = R @ full @ R.T
            return full[:, i, j].astype(v.dtype)
        return v

    points = np.vstack([(mesh.points @ R.T).astype(mesh.points.dtype) for R in turns])
    cells = [(block.type, np.vstack([block.data + k * n for k in range(copies)])) for block in mesh.cells]
    point = {k: np.concatenate([turned(k, v, R) for R in turns]) for k, v in mesh.point_data.items()}
    cell = {
        k: [np.concatenate([turned(k, block, R) for R in turns]) for block in v]
        for k, v in mesh.cell_data.items()
    }
    return meshio.Mesh(points, cells, point_data=point, cell_data=cell)


def contact_fields(model: SolidModel, x: np.ndarray) -> dict:
    """{"contact_pressure_MPa", "slip"} at every P2 node of a model with contacts ({} without):
    each contact facet's averages (`ContactReport.facet_pressure`, `facet_slip`) on its six nodes,
    the largest where facets share a node."""
    contacts = getattr(model, "contacts", None) or ()
    if not contacts:
        return {}
    n = model.space.nodes.shape[1]
    pressure, slip = np.zeros(n), np.zeros(n)
    for term in contacts:
        report = term.report(x)
        nodes = _facet_triangle6(model.mesh, term.facets)
        np.maximum.at(pressure, nodes, np.repeat(report.facet_pressure[:, None], 6, axis=1))
        np.maximum.at(slip, nodes, np.repeat(report.facet_slip[:, None], 6, axis=1))
    return {"contact_pressure_MPa": pressure, "slip": slip}


def _facet_triangle6(mesh, facets: np.ndarray) -> np.ndarray:
    """(n, 6) P2 node numbers of boundary facets in VTK's quadratic-triangle order: the vertices,
    then the midpoints of (0,1), (1,2), (2,0). scikit-fem numbers the edge nodes n_vertices + edge."""
    verts = np.sort(mesh.facets[:, facets].T, axis=1)
    edges = np.sort(mesh.edges.T, axis=1)
    key = {(int(a), int(b)): k for k, (a, b) in enumerate(edges)}
    pairs = ((0, 1), (1, 2), (0, 2))  # (2, 0) as a sorted pair
    mids = [[mesh.nvertices + key[(int(t[i]), int(t[j]))] for i, j in pairs] for t in verts]
    return np.hstack([verts, np.array(mids, dtype=int).reshape(-1, 3)])


def _compact(cells: np.ndarray):
    """Only the points that the cells use: (used point indices, renumbered cells)."""
    used, inverse = np.unique(cells, return_inverse=True)
    return used, inverse.reshape(cells.shape)


def _winding_mesh(model: SolidModel, x: np.ndarray, precision: int = DEFAULT_PRECISION):
    """(meshio.Mesh, component names) of the fiber sheets or lines at x; None without fibers."""
    u = x[: model.n_u].reshape(-1, 3)
    if model.sheets is not None:
        sq = model.sheets
        force = sheet_mod.fiber_forces(sq, u).mean(axis=1)  # (F,) facet averages
        facets = np.unique(sq.facets)
        row = {int(f): k for k, f in enumerate(facets)}
        n_fam = int(sq.family.max()) + 1
        tension = np.zeros((facets.size, n_fam))
        tension[[row[int(f)] for f in sq.facets], sq.family] = force
        used, cells = _compact(_facet_triangle6(model.mesh, facets))
        # one array per family as well as the two-component array with its ComponentNames:
        # readers that drop VTK's ComponentName (pyvista, meshio) still see which family is which
        families = {
            f"fiber_tension_family{k + 1}_N": [_float(tension[:, k], precision)] for k in range(n_fam)
        }
        mesh = meshio.Mesh(
            _float(model.nodes[:, used].T, precision),
            [("triangle6", cells)],
            point_data={"displacement_mm": _float(u[used], precision)},
            cell_data={
                "fiber_tension_N": [_float(tension, precision)],
                "max_fiber_tension_N": [_float(tension.max(axis=1), precision)],
            }
            | families,
        )
        return mesh, {"fiber_tension_N": tuple(f"family {k + 1}" for k in range(n_fam))}
    if model.fibers is not None:
        fibers = model.fibers
        current = fiber_state(fibers, u)
        force = segment_forces(fibers, current)[0]
        mesh = meshio.Mesh(
            _float(fibers.points, precision),
            [("line", fibers.segments)],
            point_data={"displacement_mm": _float(current - fibers.points, precision)},
            cell_data={"fiber_tension_N": [_float(force, precision)], "fiber": [fibers.fiber_of_segment]},
        )
        return mesh, {}
    return None


def write_winding(
    path,
    model: SolidModel,
    x: np.ndarray,
    *,
    pressure_mpa=0.0,
    factor: float = 0.0,
    time: float | None = None,
    precision: int = DEFAULT_PRECISION,
):
    """The winding at state x (module docstring); None (nothing written) for a model without fibers."""
    built = _winding_mesh(model, x, check_precision(precision))
    if built is None:
        return None
    mesh, components = built
    field_data = {k: v for k, v in _field_data(model, pressure_mpa, factor, time).items() if ":" not in k}
    return _write(Path(path), mesh, {"displacement_mm": VECTOR} | components, field_data)


def write_pvd(path, files, times=None) -> Path:
    """A ParaView collection of `files` (Path, in order) at `times` (strictly increasing; default:
    the index of each)."""
    path = Path(path)
    times = list(range(len(files))) if times is None else [float(t) for t in times]
    if len(times) != len(files) or any(b <= a for a, b in zip(times, times[1:])):
        raise ValueError("a series needs one strictly increasing time per file")
    lines = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1">', "<Collection>"]
    for t, f in zip(times, files):
        lines.append(f'<DataSet timestep="{t!r}" file={quoteattr(Path(f).name)}/>')
    lines += ["</Collection>", "</VTKFile>"]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_path(
    directory,
    model: SolidModel,
    result,
    stem="step",
    winding_stem="winding",
    precision: int = DEFAULT_PRECISION,
) -> list[Path]:
    """The reference state and every converged step of a `fem.path.PathResult`: `{stem}_NNN.vtu`
    and `{stem}.pvd`, and for a model with fibers `{winding_stem}_NNN.vtu` and `{winding_stem}.pvd`,
    at the path parameter of each state (`path_times`). Returns the solid files."""
    directory = Path(directory)
    states = [(0.0, 0.0, model.initial_state())] + [(s.pressure, s.factor, s.x) for s in result.steps]
    times = path_times(
        [mpa_to_kpa(np.asarray(p, dtype=float)) for p, _, _ in states], [f for _, f, _ in states]
    )
    files, winding = [], []
    for k, ((pressure, factor, x), t) in enumerate(zip(states, times)):
        load = {"pressure_mpa": pressure, "factor": factor, "time": t, "precision": precision}
        files.append(write_state(directory / f"{stem}_{k:03d}.vtu", model, x, **load))
        w = write_winding(directory / f"{winding_stem}_{k:03d}.vtu", model, x, **load)
        if w is not None:
            winding.append(w)
    write_pvd(directory / f"{stem}.pvd", files, times)
    if winding:
        write_pvd(directory / f"{winding_stem}.pvd", winding, times)
    return files
