"""FElupe side of the softcrawl solver benchmark: pressurised thick tube.

What it does
------------
``solve_tube_felupe(points, cells, ...)`` solves the benchmark problem with
FElupe (11.3) on the *same* linear tetrahedral mesh that softcrawl uses:
1/8 of a thick tube (inner radius A, outer radius B, 0 <= z <= L, quarter
section x >= 0, y >= 0), symmetry planes u_x = 0 on x = 0, u_y = 0 on y = 0,
u_z = 0 on z = 0 and on z = L (plane strain), a nearly incompressible
Neo-Hookean solid and a follower pressure on the inner surface r = A that is
ramped in load steps.  It returns the inner radius at the last step plus
DOF/iteration/timing figures (see the function docstring).

Formulation
-----------
* Mesh: the linear tets are turned into 10-node tets (``tetra10``) by adding
  one node per edge.  Vertices keep their numbers (0..nv-1), edge nodes come
  after them.  Edge nodes of boundary faces that lie completely on r = A or
  r = B are projected radially back onto that cylinder, so the quadratic mesh
  sees the curved geometry (exact up to the P2 interpolation of the surface).
* Field/material: FElupe's three-field Hu-Washizu variation P2/P1/P1
  (``FieldsMixed`` on a ``RegionQuadraticTetra``: quadratic displacement,
  continuous linear pressure p and continuous linear volume ratio J-bar) with
  ``NearlyIncompressible(NeoHooke(mu), bulk=K)``, i.e. exactly
  W = mu/2 (J^-2/3 I1 - 3) + K/2 (J-bar - 1)^2 + p (J - J-bar).
  This is the closest FElupe 11.3 setup to the softcrawl formulation; a pure
  P2 displacement formulation needs load cut-backs at K = 1000 mu.
* Follower pressure (the adapter): FElupe's ``SolidBodyPressure`` (residual
  p * J F^-T N dA and its consistent, non-symmetric tangent) only gets
  boundary regions for quad/hex meshes.  Here every tet that owns a face on
  r = A is re-numbered so that the loaded face is its face (0, 1, 2), i.e.
  the natural face t = 0 of FElupe's ``QuadraticTetra``.  A ``Region`` of these
  re-ordered tets is created with a triangle quadrature rule placed on t = 0,
  so the 3D shape-function gradients (and thus F) are evaluated on the face.
  The area vectors dA = -(dX/dr x dX/ds) w (outward, since vertex 3 lies on
  the +t side of the face) are stored as ``dA``/``dV``/``normals`` - exactly
  the attributes ``SolidBodyPressure`` reads from a ``RegionBoundary``.
* Solver: ``felupe.newtonraphson`` (FElupe defaults: relative residual
  tolerance sqrt(eps), max. 16 iterations per step) with ``pypardiso.spsolve``
  as linear solver (falls back to scipy's spsolve if pypardiso is missing).
  Each pressure value is one load step starting from the previous solution.

Timing: ``assembly_s`` = residual + tangent assembly (measured with plugin
hooks around FElupe's own assembly calls), ``solve_s`` = time inside the
linear solver call; the rest of ``newton_s`` is partitioning of the system
and bookkeeping.  ``wall_s`` = FElupe setup (regions, fields, boundaries) +
all Newton iterations, i.e. everything except building the P2 mesh.

Run standalone (``python bench/felupe_case.py``) to solve a small structured
mesh and print the result together with the analytic plane-strain error.
"""

import time

import felupe as fem
import numpy as np

try:  # PARDISO for a fair comparison with softcrawl's direct solver
    from pypardiso import spsolve as _linear_solver

    _SOLVER_NAME = "pypardiso"
except ImportError:  # pragma: no cover - only if pypardiso is not installed
    from scipy.sparse.linalg import spsolve as _linear_solver

    _SOLVER_NAME = "scipy.spsolve"

# local vertex pairs of the 6 edges of a tet in FElupe/VTK tetra10 order:
# mid-edge nodes 4..9 lie on edges (0,1), (1,2), (2,0), (0,3), (1,3), (2,3)
_TET10_EDGES = np.array([[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]])

# the 4 faces of a tet as (face vertices..., opposite vertex)
_TET_FACES = np.array([[1, 2, 3, 0], [0, 2, 3, 1], [0, 1, 3, 2], [0, 1, 2, 3]])


# --------------------------------------------------------------------------- mesh
def _orient_positive(points, cells):
    "Return a copy of the tets with positive volume (swap two vertices if needed)."
    cells = np.array(cells, dtype=np.int64, copy=True)
    x = points[cells]
    vol = np.einsum("ij,ij->i", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0])
    flip = vol < 0
    cells[flip, 1], cells[flip, 2] = cells[flip, 2], cells[flip, 1].copy()
    return cells


class _EdgeNumbering:
    "Global numbering of the mid-edge nodes: node id = nv + index of the edge."

    def __init__(self, cells, nv):
        pairs = np.sort(cells[:, _TET10_EDGES].reshape(-1, 2), axis=1)
        self.nv = nv
        self.keys, inverse = np.unique(pairs[:, 0] * nv + pairs[:, 1], return_inverse=True)
        self.pairs = np.stack([self.keys // nv, self.keys % nv], axis=1)
        self.cell_edges = nv + inverse.reshape(len(cells), 6)

    def lookup(self, i, j):
        "Global mid-edge node ids of the edges (i, j) (arrays of vertex ids)."
        lo, hi = np.minimum(i, j), np.maximum(i, j)
        return self.nv + np.searchsorted(self.keys, lo * self.nv + hi)


def boundary_faces(cells):
    "Faces that belong to exactly one tet: (tet index, local face index)."
    faces = cells[:, _TET_FACES[:, :3]].reshape(-1, 3)
    _, index, counts = np.unique(np.sort(faces, axis=1), axis=0, return_index=True, return_counts=True)
    once = index[counts == 1]
    return once // 4, once % 4


def _build_quadratic_mesh(points, cells, inner, outer, tol):
    """Create the tetra10 mesh from the linear tets, project the mid-edge nodes of
    curved boundary faces radially onto r = inner / r = outer and collect the
    re-ordered tets of the loaded (inner) faces."""
    points = np.asarray(points, dtype=float)
    cells = _orient_positive(points, cells)
    nv = len(points)
    if len(np.unique(cells)) != nv:
        # unused vertices would give empty rows (u, p and J-bar) -> singular system
        raise ValueError("the tet mesh contains vertices which belong to no cell")

    edges = _EdgeNumbering(cells, nv)
    midpoints = points[edges.pairs].mean(axis=1)
    points2 = np.vstack([points, midpoints])
    cells2 = np.hstack([cells, edges.cell_edges])

    # boundary faces lying completely on one of the two cylinders
    radius = np.hypot(points[:, 0], points[:, 1])
    on_inner = np.abs(radius - inner) < tol
    on_outer = np.abs(radius - outer) < tol
    tet, face = boundary_faces(cells)
    local = _TET_FACES[face]  # (nfaces, 4): 3 face vertices + opposite vertex
    verts = cells[tet[:, None], local]  # global vertex ids

    n_projected = 0
    for on_surface, r_target in [(on_inner, inner), (on_outer, outer)]:
        sel = on_surface[verts[:, :3]].all(axis=1)
        v = verts[sel, :3]
        mids = np.unique(
            np.concatenate([edges.lookup(v[:, a], v[:, b]) for a, b in [(0, 1), (1, 2), (2, 0)]])
        )
        rm = np.hypot(points2[mids, 0], points2[mids, 1])
        points2[mids, :2] *= (r_target / rm)[:, None]
        n_projected += len(mids)

    # tets of the loaded faces, re-numbered: loaded face -> local face (0, 1, 2)
    sel = on_inner[verts[:, :3]].all(axis=1)
    a, b, c, d = verts[sel].T
    x = points2
    vol = np.einsum("ij,ij->i", np.cross(x[b] - x[a], x[c] - x[a]), x[d] - x[a])
    b, c = np.where(vol > 0, b, c), np.where(vol > 0, c, b)  # keep positive volume
    pairs = [(a, b), (b, c), (c, a), (a, d), (b, d), (c, d)]
    cells_loaded = np.stack([a, b, c, d] + [edges.lookup(i, j) for i, j in pairs], axis=1)

    mesh = fem.Mesh(points2, cells2, cell_type="tetra10")
    return mesh, cells_loaded, on_inner, n_projected


# ------------------------------------------------------------- pressure adapter
def _face_region(mesh, cells_loaded, order=5):
    """A FElupe region which integrates on the local face (0, 1, 2) of re-ordered
    tetra10 cells and carries the outward area vectors like a ``RegionBoundary``."""
    tri = fem.TriangleQuadrature(order=order)
    scheme = fem.quadrature.Scheme(
        np.pad(tri.points, ((0, 0), (0, 1))),
        tri.weights,  # (r, s, t = 0)
    )
    mesh_faces = fem.Mesh(mesh.points, cells_loaded, cell_type="tetra10")
    region = fem.Region(mesh_faces, fem.QuadraticTetra(), scheme, grad=True)

    # dXdr has shape (3, 3, nq, ncells); tangents along r and s span the face
    dA = -np.cross(region.dXdr[:, 0], region.dXdr[:, 1], axis=0) * tri.weights[:, None]
    region.dA = dA
    region.dV = np.linalg.norm(dA, axis=0)
    region.normals = dA / region.dV
    return region


# ----------------------------------------------------------------- bookkeeping
class _Timer(fem.Plugin):
    "Accumulates the assembly time of newtonraphson() via its event hooks."

    def __init__(self):
        self.assembly = 0.0
        self._t = None

    def before_newton(self, context, state):  # initial residual follows
        self._t = time.perf_counter()

    def before_iteration(self, context, state):  # residual done, tangent follows
        if self._t is not None:
            self.assembly += time.perf_counter() - self._t
            self._t = None
        self._t_jac = time.perf_counter()

    def before_linear_solve(self, context, state):  # tangent assembled
        self.assembly += time.perf_counter() - self._t_jac

    def after_linear_solve(self, context, state):  # update + residual follow
        self._t = time.perf_counter()

    def after_iteration(self, context, state):
        self.assembly += time.perf_counter() - self._t
        self._t = None


class _TimedSolver:
    "Wraps the sparse linear solver and sums up the time spent inside it."

    def __init__(self, solver):
        self.solver = solver
        self.seconds = 0.0
        self.calls = 0

    def __call__(self, A, b):
        t0 = time.perf_counter()
        x = self.solver(A, b)
        self.seconds += time.perf_counter() - t0
        self.calls += 1
        return x


# ------------------------------------------------------------------------ API
def _felupe_model(mesh, cells_loaded, mu, k_over_mu, length, outer):
    """FElupe fields, solid, follower pressure and the symmetry/plane-strain partition."""
    tol_r = 1e-6 * outer  # geometric tolerances (relative to the model size)
    tol_z = 1e-6 * max(length, outer)
    region = fem.RegionQuadraticTetra(mesh)  # default tetra quadrature (order 2)
    field = fem.FieldsMixed(region, n=3)  # u (P2), p (P1), J-bar (P1)
    umat = fem.NearlyIncompressible(fem.NeoHooke(mu=mu), bulk=k_over_mu * mu)
    solid = fem.SolidBody(umat, field)
    region_p = _face_region(mesh, cells_loaded)
    pressure = fem.SolidBodyPressure(fem.FieldContainer([fem.Field(region_p, dim=3)]), pressure=0.0)
    x, y, z = mesh.points.T
    u = field[0]
    boundaries = {
        "sym-x": fem.Boundary(u, mask=np.abs(x) < tol_r, skip=(0, 1, 1)),
        "sym-y": fem.Boundary(u, mask=np.abs(y) < tol_r, skip=(1, 0, 1)),
        "sym-z": fem.Boundary(u, mask=np.abs(z) < tol_z, skip=(1, 1, 0)),
        "plane-strain": fem.Boundary(u, mask=np.abs(z - length) < tol_z, skip=(1, 1, 0)),
    }
    dof0, dof1 = fem.dof.partition(field, boundaries)
    ext0 = fem.dof.apply(field, boundaries, dof0)  # all zero
    return field, solid, pressure, (dof0, dof1, ext0)


def _ramp(field, solid, pressure, partition, pressures):
    """One FElupe Newton solve per pressure; returns (field, iterations per step, converged,
    failure message, assembly timer, linear-solver timer)."""
    dof0, dof1, ext0 = partition
    timer = _Timer()
    solver = _TimedSolver(_linear_solver)
    iterations, converged, failure = [], True, ""
    for p in pressures:
        pressure.update(p)
        try:
            res = fem.newtonraphson(
                items=[solid, pressure],
                x0=field,
                dof1=dof1,
                dof0=dof0,
                ext0=ext0,
                solver=solver,
                verbose=0,
                plugins=[timer],
            )
        except fem.NewtonConvergenceError as err:
            converged, failure = False, f"step p={p}: {err}".strip()
            break
        iterations.append(res.iterations)
        converged = converged and bool(res.success)
        field = res.x
    return field, iterations, converged, failure, timer, solver


def _notes(mesh, points, n_projected, cells_loaded, inner, outer, n_steps, inner_vertices, failure):
    notes = (
        f"FElupe {fem.__version__}: tetra10 P2/P1/P1 FieldsMixed + "
        f"NearlyIncompressible(NeoHooke), {len(mesh.points)} P2 nodes "
        f"({len(points)} vertices), {n_projected} mid-edge nodes projected onto "
        f"r={inner:g}/{outer:g}; follower pressure = SolidBodyPressure on "
        f"{len(cells_loaded)} re-ordered boundary tets (face quadrature "
        f"TriangleQuadrature(order=5)); linear solver {_SOLVER_NAME}; "
        f"{n_steps} load steps, Newton tol sqrt(eps) (FElupe default, "
        f"relative residual), inner radius = mean over {inner_vertices.sum()} "
        f"inner-surface vertices."
    )
    return notes + (" NOT CONVERGED: " + failure if failure else "")


def solve_tube_felupe(
    points,
    cells,
    *,
    inner=3.0,
    outer=9.0,
    length=50.0,
    mu=0.03,
    k_over_mu=1000.0,
    pressures=(0.004, 0.008, 0.012, 0.016, 0.02),
):
    """Solve the pressurised 1/8 tube with FElupe (P2/P1/P1, follower pressure).

    Parameters
    ----------
    points : (n, 3) array of float
        Vertices of the linear tet mesh of the quarter tube section (mm).
    cells : (m, 4) array of int
        Linear tetrahedra (any orientation).
    inner, outer, length : float
        Inner/outer radius and half-length of the tube (mm).
    mu : float
        Shear modulus (MPa); the bulk modulus is ``k_over_mu * mu``.
    pressures : sequence of float
        Inner pressure (MPa) at the end of each load step.

    Returns
    -------
    dict
        dofs, dofs_active, newton_iterations (total), iterations_per_step,
        wall_s (setup + Newton, without P2-mesh building), setup_s, newton_s,
        assembly_s, solve_s, mesh_s, inner_radius_mm (mean deformed radius of
        the inner-surface vertices at the last converged step), converged,
        solver, notes.
    """
    points = np.asarray(points, dtype=float)
    cells = np.asarray(cells, dtype=np.int64)

    t0 = time.perf_counter()  # the quadratic mesh is not timed as solve time
    mesh, cells_loaded, inner_vertices, n_projected = _build_quadratic_mesh(
        points, cells, inner, outer, 1e-6 * outer
    )
    mesh_s = time.perf_counter() - t0

    t_setup = time.perf_counter()
    field, solid, pressure, partition = _felupe_model(mesh, cells_loaded, mu, k_over_mu, length, outer)
    setup_s = time.perf_counter() - t_setup

    t_newton = time.perf_counter()
    field, iterations, converged, failure, timer, solver = _ramp(field, solid, pressure, partition, pressures)
    newton_s = time.perf_counter() - t_newton

    xv = mesh.points[: len(points)] + field[0].values[: len(points)]
    radius = np.hypot(xv[inner_vertices, 0], xv[inner_vertices, 1])
    notes = _notes(
        mesh, points, n_projected, cells_loaded, inner, outer, len(pressures), inner_vertices, failure
    )
    return {
        "dofs": int(np.sum(field.fieldsizes)),
        "dofs_active": int(len(partition[1])),
        "newton_iterations": int(sum(iterations)),
        "iterations_per_step": iterations,
        "wall_s": setup_s + newton_s,
        "setup_s": setup_s,
        "newton_s": newton_s,
        "assembly_s": timer.assembly,
        "solve_s": solver.seconds,
        "factorizations": solver.calls,
        "mesh_s": mesh_s,
        "inner_radius_mm": float(radius.mean()),
        "converged": bool(converged and len(iterations) == len(pressures)),
        "solver": _SOLVER_NAME,
        "notes": notes,
    }


# ------------------------------------------------------------------ standalone
def _quarter_tube_mesh(inner=3.0, outer=9.0, length=50.0, nr=4, nt=6, nz=2):
    """Structured linear tet mesh of the quarter tube: a hexahedral grid in
    (r, theta, z), split into tets by FElupe, mapped to Cartesian coordinates."""
    grid = fem.Cube(a=(inner, 0, 0), b=(outer, np.pi / 2, length), n=(nr + 1, nt + 1, nz + 1))
    tets = grid.triangulate()
    r, t, z = tets.points.T
    points = np.stack([r * np.cos(t), r * np.sin(t), z], axis=1)
    points[np.isclose(t, np.pi / 2), 0] = 0.0  # exact symmetry plane x = 0
    return points, tets.cells


if __name__ == "__main__":
    import sys

    n = [int(v) for v in sys.argv[1:4]] if len(sys.argv) >= 4 else (4, 6, 2)
    pts, tets = _quarter_tube_mesh(nr=n[0], nt=n[1], nz=n[2])
    print(f"mesh: {len(pts)} vertices, {len(tets)} tets (nr, ntheta, nz = {n})")
    result = solve_tube_felupe(pts, tets)
    for key, value in result.items():
        print(f"{key:>20}: {value}")

    from softcrawl.fem.analytic import tube_inner_stretch  # the project's closed form

    a = tube_inner_stretch(0.03, 0.02, 3.0, 9.0) * 3.0
    ua, uh = a - 3.0, result["inner_radius_mm"] - 3.0
    print(f"{'analytic radius':>20}: {a:.6f} mm")
    print(f"{'error u_r(A)':>20}: {100 * (uh - ua) / ua:+.3f} %")
