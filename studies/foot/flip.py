r"""The flipped (everted) foot of the backward crawl: the skirt turned inside out by FE, prestress kept.

The paper's backward crawl starts with both feet flipped ("by changing the initial contact surfaces
of each foot ... the forward locomotion can be changed to backward locomotion"): the skirt is turned
inside out, leans forward, and its grooved back face is the one on the pipe wall. The foot is meshed
in its moulded (stress-free) shape, and the flip is computed on that mesh, so that the eversion's
prestress is in the state (docs/decisions/067-flipped-foot.md says why not a stress-free mesh of the
everted shape).

Kinematics. In the (rho, z) half plane of `geometry.foot` (alpha = angle / 2, t the skirt
thickness), the skirt's mid-surface line meets the hub side at the hinge
    H = (r_hub, -t / (2 sin alpha)),
and its direction is u = (sin alpha, -cos alpha). The rotation of the meridian plane about H by
    Delta = pi - 2 alpha        (60 deg for the 120 deg foot)
takes u to (sin alpha, cos alpha): the mid-surface line onto its mirror image about z = H_z (the
skirt now leans forward), and a point at the signed distance e from the mid-surface (e > 0 on the
back face) from rho = rho_m - e cos alpha to rho_m + e cos alpha: the grooved back face goes
outside, the smooth front face inside. The mid-surface keeps its radius, so the flip costs no
membrane hoop strain, only hoop bending, eps_theta = 2 e cos alpha / rho (up to t cos alpha / rho
on the faces: 6.3 % at the root, 3.8 % at the tip of the Table 1 foot), plus the bending of the
root, which the FE resolves.

Path. The hub top is held (the actuators), and the rim (the skirt's end face) is rotated about H in
its meridian plane by phi = s Delta, s in [0, 1] (`EVERT_STEPS` sub-steps, halved on divergence).
The rim passes the flat position, where its radius is largest (the snap-through barrier: hoop
stretch of the tip), and arrives at the everted placement (`fold`; in a pipe, `fold_angle_into`
turns it further, until the rim is inside the wall). `release` then lets the rim go through
springs between the rim's dofs and their held placement (`RimSprings`), softened by sqrt(10) per
step down to `RELEASE_FLOOR` and then removed: a free flipped equilibrium is followed to the end, a
snap back shows as the step where no equilibrium is found. For the Table 1 foot there is none: the
skirt unfolds as the springs soften and snaps back below about 0.005 N/mm per dof (record 067);
a pipe holds the flip, so the foot study and the crawl fold the skirt inside the wall and release
it there (`studies.foot.model._flipped_stages`, `studies.crawl.flipped`).

Checks (`Eversion`): the free state's relative residual (the Newton test), its stability (the
negative eigenvalues of the tangent on the free dofs minus those of the pressure block, counted
from PARDISO's symmetric-indefinite factorisation: inertia(K) = inertia(-C) + inertia(Schur), with
-C the negative definite P1 pressure block of the u-p formulation, so the difference is the number
of unstable displacement modes; 0: a stable equilibrium), where the tip stands (z_tip - z_hub > 0:
ahead of the hub top), and the area-weighted mean radial component of the outward normals of the
grooved back face (< 0 in the moulded foot, > 0 when the grooved face looks at the wall) and of the
smooth front face (the opposite).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.newton import Diverged, NewtonOptions, NewtonSolver
from softcrawl.geometry.foot import foot_profile

#: Sub-steps of the rim's rotation (5 deg each for the 120 deg foot), and halvings of one before the
#: eversion is given up.
EVERT_STEPS = 12
MAX_HALVINGS = 6
#: The release's rim springs (N/mm per dof): from stiff (far above the skirt's, ~10 N/mm) to soft
#: (far below), then none.
RELEASE_STIFFNESS = 1.0e3
RELEASE_FLOOR = 1.0e-3
#: In a pipe, the rim is folded to this clearance (mm) inside the wall before the wall closes.
FOLD_CLEARANCE = 0.5


@dataclass(frozen=True)
class Eversion:
    converged: bool
    message: str
    x: np.ndarray | None = field(repr=False)  # the free flipped state (dofs of the foot's models)
    residual: float  # relative residual of the free state
    unstable_modes: int | None  # negative eigenvalues of the condensed stiffness (None: not counted)
    tip_ahead: float  # mean z of the rim minus mean z of the hub top (mm); > 0: flipped
    grooved_normal: float  # area-weighted mean radial component of the back face's outward normal
    smooth_normal: float  # the same for the front face
    outer_radius: float  # largest radius of the deformed foot's nodes (mm)
    wall_s: float


def hinge(design) -> tuple[np.ndarray, float]:
    """(H, Delta): the hinge point in the (rho, z) plane and the flip's rotation (rad), module docstring."""
    a = math.radians(design.angle / 2)
    return np.array([design.hub_radius, -design.skirt_thickness / (2 * math.sin(a))]), math.pi - 2 * a


def rotated(points: np.ndarray, design, phi: float) -> np.ndarray:
    """Displacements (3, n) that rotate `points` (3, n) about the hinge circle by `phi` in their
    meridian planes (counter-clockwise in (rho, z): the tip moves towards +z)."""
    H, _ = hinge(design)
    x, y, z = points
    rho = np.hypot(x, y)
    c, s = math.cos(phi), math.sin(phi)
    dr, dz = rho - H[0], z - H[1]
    rho1, z1 = H[0] + c * dr - s * dz, H[1] + s * dr + c * dz
    scale = np.divide(rho1, rho, out=np.ones_like(rho), where=rho > 0)
    return np.vstack([x * scale - x, y * scale - y, z1 - z])


def _outward_radial_normal(model, x, tag: str) -> float:
    """Area-weighted mean radial component of the outward unit normals of the (straight) facets of
    `tag` in the deformed state x."""
    mesh = model.mesh
    nv = mesh.p.shape[1]
    p = mesh.p + model.displacement(x)[:, :nv]
    facets = model.space.boundary(tag)
    tri = mesh.facets[:, facets]
    a, b, c = (p[:, tri[i]] for i in range(3))
    nrm = np.cross((b - a).T, (c - a).T).T  # (3, m), twice the area
    tet = mesh.t[:, mesh.f2t[0, facets]]
    inner = np.array([[v for v in tet[:, j] if v not in tri[:, j]][0] for j in range(tri.shape[1])])
    flip = np.einsum("ij,ij->j", nrm, p[:, inner] - a) > 0
    nrm[:, flip] *= -1
    centre = (a + b + c) / 3
    radial = centre[:2] / np.linalg.norm(centre[:2], axis=0)
    return float(np.einsum("ij,ij->j", nrm[:2], radial).sum() / np.linalg.norm(nrm, axis=0).sum())


def unstable_modes(model, x) -> int | None:
    """Negative eigenvalues of `model`'s tangent at x on the free dofs minus the free pressure
    dofs (module docstring); None when PARDISO is not available."""
    try:
        import pypardiso  # lazy: optional solver, only for this count
    except ImportError:
        return None
    _, K = model.residual_and_tangent(x, np.zeros(1), 0.0)
    K = sp.triu(0.5 * (K + K.T), format="csr")
    K.sort_indices()
    solver = pypardiso.PyPardisoSolver(mtype=-2)
    solver.factorize(K)
    negative = int(solver.iparm[22])
    solver.free_memory(everything=True)
    free = model.free_dofs
    return negative - int(np.count_nonzero(free >= model.n_u))


def _rim_dofs_of(space, tag: str = "rim") -> np.ndarray:
    nodes = space.boundary_nodes(tag)
    return (3 * nodes[:, None] + np.arange(3)).ravel()


def _rim_dofs(model) -> np.ndarray:
    return _rim_dofs_of(model.space)


@dataclass(frozen=True)
class Fold:
    """The foot with its rim held, rotated by `phi` (rad) about the hinge (module docstring)."""

    converged: bool
    message: str
    phi: float
    x: np.ndarray | None = field(repr=False)
    rim_target: np.ndarray | None = field(repr=False)  # the rim dofs' prescribed displacements


def fold(
    mesh,
    material,
    design,
    phi: float,
    *,
    steps: int = EVERT_STEPS,
    options: NewtonOptions | None = None,
    hub: str = "hub_top",
) -> Fold:
    """Rotate the rim about the hinge by `phi` (rad), the hub face `hub` held (module docstring,
    "Path"; the crawl's front foot is held by its "hub_bottom", the face its actuators act on)."""
    opt = options or NewtonOptions()
    held = SolidModel(mesh, material, dirichlet=[Dirichlet.fixed(hub), Dirichlet.fixed("rim")])
    rim_nodes = held.boundary_nodes("rim")
    where = np.searchsorted(held.constraints.fixed_dofs, _rim_dofs(held))
    solver = NewtonSolver(held, opt)
    P = np.zeros(1)
    x, prev, s, h, cuts = held.initial_state(), None, 0.0, 1.0 / steps, 0
    while s < 1.0 - 1e-12:
        h = min(h, 1.0 - s)
        s1 = s + h
        held.constraints.fixed_values[where] = rotated(held.nodes[:, rim_nodes], design, s1 * phi).T.ravel()
        guess = x if prev is None else x + (x - prev[1]) * (h / (s - prev[0]))
        try:
            x1, record = solver.load_step(guess, P, 1.0, start=x)
        except Diverged as exc:
            h, cuts = 0.5 * h, cuts + 1
            if cuts > MAX_HALVINGS:
                message = f"the fold diverged with the rim at {math.degrees(s1 * phi):.3g} deg ({exc})"
                return Fold(False, message, phi, None, None)
            continue
        prev, x, s, cuts = (s, x), x1, s1, 0
        if record.iterations <= 6:
            h = min(2 * h, 1.0 / steps)
    return Fold(True, "folded", phi, x, x[_rim_dofs(held)].copy())


def fold_angle_into(design, points: np.ndarray, radius: float) -> float:
    """The least rotation phi >= Delta (rad) that brings the rim's nodes `points` (3, n), rotated
    rigidly about the hinge, inside `radius` (mm); the flip alone (Delta) when it already does.
    At most pi - alpha, where the skirt points along the axis (further, it would fold over the
    hub): a ValueError when even that leaves the rim outside."""
    _, delta = hinge(design)
    alpha = math.radians(design.angle / 2)

    def outer(phi):
        d = rotated(points, design, phi)
        return float(np.hypot(points[0] + d[0], points[1] + d[1]).max())

    if outer(delta) <= radius:
        return delta
    lo, hi = delta, math.pi - alpha
    if outer(hi) > radius:
        raise ValueError(f"the flipped rim cannot be folded inside a radius of {radius:g} mm")
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if outer(mid) > radius else (lo, mid)
    return hi


def flipped_min_diameter(design) -> float:
    """The smallest pipe (mm) a flipped foot can be folded into: twice the rim's largest radius
    with the skirt along the axis (phi = pi - alpha, the most `fold_angle_into` turns it), plus the
    clearance on both sides."""
    prof, tags = foot_profile(design)
    i = tags.index("rim")
    rim = np.array([prof[i], prof[(i + 1) % len(prof)]])  # a straight edge: its ends bound its radii
    pts = np.vstack([rim[:, 0], np.zeros(2), rim[:, 1]])
    moved = pts + rotated(pts, design, math.pi - math.radians(design.angle / 2))
    return 2.0 * (float(np.hypot(moved[0], moved[1]).max()) + FOLD_CLEARANCE)


def evert(mesh, material, design, *, steps: int = EVERT_STEPS, options: NewtonOptions | None = None,
          count_modes: bool = True) -> Eversion:  # fmt: skip
    """The free flipped foot on `mesh` (skfem MeshTet2 with the foot's tags): the rim rotated by
    Delta, then released (module docstring)."""
    started = time.perf_counter()
    opt = options or NewtonOptions()
    folded = fold(mesh, material, design, hinge(design)[1], steps=steps, options=opt)
    if not folded.converged:
        nan = float("nan")
        return Eversion(
            False, folded.message, None, nan, None, nan, nan, nan, nan, time.perf_counter() - started
        )
    return release(mesh, material, folded.x, opt, count_modes, started)


class RimSprings:
    """Springs of stiffness k (N/mm, per dof) that pull the dofs of the rims `tags` to `target`
    (their displacements, mm, in the order of `rim_dofs`): r = k (u - target), K = k I.
    `stiffness` is set along the release. A model term spec and its term at once."""

    def __init__(self, target: np.ndarray, tags: tuple[str, ...] = ("rim",)) -> None:
        self.target = target
        self.tags = tags
        self.stiffness = 0.0

    def build(self, space):
        self.rim_dofs = np.concatenate([_rim_dofs_of(space, tag) for tag in self.tags])
        self.dofs = self.rim_dofs[None, :]
        return self

    def ramp(self, start: float, decades: float = 6.0):
        """drive(s) of a stage: k = start (10^(-decades s) - 10^-decades) / (1 - 10^-decades),
        from `start` at s = 0 down to exactly 0 at s = 1."""
        floor = 10.0**-decades

        def drive(s: float) -> None:
            self.stiffness = start * (10.0 ** (-decades * s) - floor) / (1.0 - floor)

        return drive

    def axial_force(self, x) -> float:
        """The springs' total force on the body along z (N): -k sum (u_z - target_z)."""
        z = self.rim_dofs % 3 == 2
        return float(-self.stiffness * np.sum(x[self.rim_dofs[z]] - self.target[z]))

    def arrays(self, x, pressures=None, with_tangent=True):
        r = self.stiffness * (x[self.dofs] - self.target[None, :])
        K = np.full((self.dofs.shape[1], 1, 1), self.stiffness) if with_tangent else None
        return r, K


def release(mesh, material, x, options, count_modes: bool = True, started: float | None = None) -> Eversion:
    """From the state x with the rim held, let the rim go: springs between the rim and its held
    placement whose stiffness falls by sqrt(10) per step from `RELEASE_STIFFNESS` to
    `RELEASE_FLOOR`, then none (a free equilibrium is followed, a snap back is a failure)."""
    started = time.perf_counter() if started is None else started
    springs = RimSprings(np.zeros(0))
    free = SolidModel(mesh, material, dirichlet=[Dirichlet.fixed("hub_top")], extra_terms=[springs])
    springs.target = x[_rim_dofs(free)].copy()
    solver = NewtonSolver(free, options)
    P = np.zeros(1)
    ladder = [
        RELEASE_STIFFNESS * 10 ** (-j / 2)
        for j in range(int(2 * math.log10(RELEASE_STIFFNESS / RELEASE_FLOOR)) + 1)
    ]
    for k in ladder + [0.0]:
        springs.stiffness = k
        try:
            x, record = solver.load_step(x, P, 0.0)
        except Diverged as exc:
            nan = float("nan")
            message = (
                f"the released flipped skirt found no equilibrium at rim springs of {k:.3g} N/mm ({exc})"
            )
            return Eversion(
                False, message, None, nan, None, nan, nan, nan, nan, time.perf_counter() - started
            )
    return describe(free, x, record.residuals[-1], count_modes, time.perf_counter() - started)


def describe(model, x, residual: float, count_modes: bool = True, wall_s: float = 0.0) -> Eversion:
    """The checks of the module docstring on the state x of the foot `model` (hub top held)."""
    u = model.displacement(x)
    z = model.nodes[2] + u[2]
    tip, hub = model.boundary_nodes("rim"), model.boundary_nodes("hub_top")
    deformed = model.nodes + u
    return Eversion(
        True,
        "flipped",
        x,
        float(residual),
        unstable_modes(model, x) if count_modes else None,
        float(z[tip].mean() - z[hub].mean()),
        _outward_radial_normal(model, x, "back"),
        _outward_radial_normal(model, x, "front"),
        float(np.hypot(deformed[0], deformed[1]).max()),
        wall_s,
    )
