r"""Verification cases of the contact term (`fem.contact`) against closed forms (docs/DESIGN.md).

- contact-press: a quarter block (symmetry planes x = 0, y = 0) under a dead pressure p on its
  top, on a frictionless rigid plane. The exact state is homogeneous uniaxial compression, so the
  nominal contact pressure is p at every facet quadrature point. Error: the worst relative
  pressure error, and the penetration after the Uzawa loop relative to the pure penalty one
  (p / eps_N), whichever is larger.
- contact-drag: a block pressed by a follower pressure p on its top face and dragged by a
  prescribed tangential displacement of that face far past the stick limit. In full slip the
  friction force is mu N. Error: |F_T + mu N| / (mu N) (the force on the body opposes the drag),
  and 1 - (slipping area share).
- contact-viscous-drag: contact-drag with viscous slip (`fem.contact_law`, eta = 0.06 MPa s/mm)
  and the drag spread over a duration T (0.5 mm in 1 s, 16 sub-steps): the block slides at the
  steady speed v = 0.5 mm/s, where the closed form of backward-Euler viscous slip is exact at any
  sub-step: |F_T| = mu N + eta v A (tractions per reference area; A the base's reference area in
  contact). The friction's moment lifts the trailing quarter of the base off the plane (the
  pressure is not uniform), so A is the report's active area, 1.47 of 2 mm^2: the viscous part
  acts only where the base touches. Error: |F_T + mu N + eta v A| / (mu N + eta v A); Coulomb's
  mu N alone would be off by 27 %.
- contact-stick: a block with nu = 0 (no Poisson slip) under a proportional dead load
  (T, 0, -N) on its top, T = 0.5 mu N: no point slips and the friction force balances T. Error:
  |F_T + T| / T plus the slipping area share. (With nu = 0.35 the base slips at its edges as it
  expands under the normal load, 70 % of the area at T = 0.5 mu N; at T = 0.8 mu N with nu = 0
  17 % slips at the unloaded edge: both are the physics, not a defect.)
- contact-hertz: plane-strain line contact of an elastic cylinder (radius R, compressible
  Neo-Hookean at small load) on a frictionless rigid plane, pushed by a rigid displacement of a
  small inner hole. Hertz: for the force per length F' (from the solution), the half width
  a = sqrt(4 F' R / (pi E*)) and the peak pressure p0 = 2 F' / (pi a), E* = E / (1 - nu^2)
  (`hertz_line_contact`, `plane_strain_modulus`). Error: the FE peak pressure against p0 (cells
  of 0.08 mm near the contact, about a/7; `hertz_result` compares a solved state of
  `hertz_model`, so the comparison is tested without the 10-30 s solve).
- contact-area: the quarter block of contact-press (reference base A0 = 1.5 x 1 mm) stretched
  laterally by lam = 1.2 in x and y (prescribed normal displacements of its outer faces) and
  pressed by a dead force p A0 on a frictionless plane. The state is homogeneous, F = diag(lam,
  lam, lam_z), so by Nanson's formula (da = |cof(F) N| dA) the current contact area is A0 lam^2
  = 2.16 mm^2, the reference area A0, and the mean contact pressure N / a = p / lam^2 with
  N = p A0. Error: the worst relative error of the three. Before 2026-11-25 `ContactTerm.report`
  summed |cof(F) N| over the active quadrature points without their area weights dA: it gave
  an area of 103.68 mm^2 here (lam^2 times the 72 points of the 12 base facets; 48x the exact
  value, relative error 47.0) and a mean pressure of 0.00217 MPa against 0.1042 MPa (relative
  error 0.979); the forces, and the reference area, were right.
- contact-newton: the observed order of convergence of Newton's method in a sliding increment
  against a curved wall (a block pressed on the inside of a cylinder and dragged along the axis
  and around it): log(r_k+1 / r_k) / log(r_k / r_k-1) over the last three residuals above
  1e-11 (round-off sits near 1e-13).
"""

from __future__ import annotations

import numpy as np
import skfem

from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_law import steady_slip_traction
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions
from softcrawl.fem.rigid_surfaces import CylinderWall, Plane
from softcrawl.fem.structured import box, curved, tag_boundaries
from softcrawl.fem.verification import CaseResult

MATERIAL = NeoHookean(mu=1.0, bulk=3.0)  # nu ~ 0.35


def press_test(pressure=0.3, penalty=100.0, tolerance=5e-3, smoothing=0.0) -> CaseResult:
    a = 1.0
    mesh = box((a, a, 1.0), (3, 3, 2))
    spec = ContactSpec(("z0",), Plane(), penalty=penalty, smoothing=smoothing)
    bcs = [Dirichlet.symmetry("x0", 0), Dirichlet.symmetry("y0", 1)]
    model = SolidModel(
        mesh, MATERIAL, dirichlet=bcs, dead_loads={"z1": (0, 0, -pressure * a * a)}, contacts=[spec]
    )
    res = run_stages(model, [Stage("press", factor=1.0, steps=2)], penetration_tol=1e-12, max_augment=8)
    if not res.converged:
        return CaseResult("contact-press", np.inf, tolerance, {"message": res.message})
    term = model.contacts[0]
    st = term.state(res.x)
    p_err = float(np.abs(st.pressure / pressure - 1).max())
    pen_ratio = term.report(res.x).max_penetration / (pressure / penalty)
    return CaseResult(
        "contact-press",
        max(p_err, pen_ratio),
        tolerance,
        {
            "pressure_error": p_err,
            "penetration_over_penalty": pen_ratio,
            "uzawa_solves": res.steps[-1].iterations,
        },
    )


def area_test(pressure=0.15, stretch=1.2, penalty=100.0, tolerance=1e-8) -> CaseResult:
    """Current contact area and mean contact pressure of a laterally stretched, pressed block
    against Nanson's formula (module docstring)."""
    size = (1.5, 1.0, 1.0)
    area0 = size[0] * size[1]
    mesh = box(size, (3, 2, 2))
    spec = ContactSpec(("z0",), Plane(), penalty=penalty)
    bcs = [
        Dirichlet.symmetry("x0", 0),
        Dirichlet.symmetry("y0", 1),
        Dirichlet.prescribed("x1", 0, (stretch - 1.0) * size[0]),
        Dirichlet.prescribed("y1", 1, (stretch - 1.0) * size[1]),
    ]
    model = SolidModel(
        mesh, MATERIAL, dirichlet=bcs, dead_loads={"z1": (0, 0, -pressure * area0)}, contacts=[spec]
    )
    res = run_stages(model, [Stage("press", factor=1.0, steps=2)], penetration_tol=1e-12, max_augment=8)
    if not res.converged:
        return CaseResult("contact-area", np.inf, tolerance, {"message": res.message})
    rep = model.contacts[0].report(res.x)
    area, mean = area0 * stretch**2, pressure / stretch**2
    errors = {
        "area_current": abs(rep.area_current / area - 1.0),
        "mean_pressure": abs(rep.mean_pressure / mean - 1.0),
        "area_reference": abs(rep.area_reference / area0 - 1.0),
    }
    return CaseResult(
        "contact-area",
        max(errors.values()),
        tolerance,
        {
            "area_current": rep.area_current,
            "area_current_exact": area,
            "mean_pressure": rep.mean_pressure,
            "mean_pressure_exact": mean,
            "area_reference": rep.area_reference,
            "normal_force": rep.normal_force,
            "errors": errors,
        },
    )


def _drag_block(penalty, drag, smoothing, slip_band, viscosity=0.0):
    """The block 2 x 1 x 1 (half: y >= 0) on the plane z = 0, frictionless until a stage sets mu;
    its top z1 a chamber (the follower pressure) moved by (drag, 0) in x and y at load factor 1."""
    mesh = box((2.0, 1.0, 1.0), (4, 2, 2))
    spec = ContactSpec(
        ("z0",), Plane(), penalty=penalty, smoothing=smoothing, slip_band=slip_band, slip_viscosity=viscosity
    )
    bcs = [Dirichlet.symmetry("y0", 1), Dirichlet("z1", (0, 1), (drag, 0.0))]
    return SolidModel(mesh, MATERIAL, dirichlet=bcs, chambers=ChamberSpec(("z1",)), contacts=[spec])


def drag_test(
    mu=0.3, pressure=0.2, penalty=100.0, drag=0.5, tolerance=5e-3, smoothing=0.0, slip_band=0.0
) -> CaseResult:
    model = _drag_block(penalty, drag, smoothing, slip_band)
    stages = [
        Stage("press", pressure=pressure, steps=2),
        Stage("drag", factor=1.0, friction={0: mu}, steps=4),
    ]
    res = run_stages(model, stages, penetration_tol=1e-8)
    rep = model.contacts[0].report(res.x)
    err = abs(rep.friction_force[0] + mu * rep.normal_force) / (mu * rep.normal_force)
    return CaseResult(
        "contact-drag",
        max(err, 1.0 - rep.slip_fraction) if res.converged else np.inf,
        tolerance,
        {
            "normal_force": rep.normal_force,
            "friction_x": rep.friction_force[0],
            "slip_fraction": rep.slip_fraction,
        },
    )


def viscous_drag_test(
    mu=0.3, pressure=0.2, penalty=100.0, drag=0.5, duration=1.0, viscosity=0.06, tolerance=5e-3
) -> CaseResult:
    model = _drag_block(penalty, drag, 0.0, 0.0, viscosity)
    stages = [
        Stage("press", pressure=pressure, steps=2),
        Stage("drag", factor=1.0, friction={0: mu}, steps=16, duration=duration),
    ]
    res = run_stages(model, stages, penetration_tol=1e-8)
    rep = model.contacts[0].report(res.x)
    exact = steady_slip_traction(mu * rep.normal_force, viscosity * rep.area_reference, drag / duration)
    err = abs(rep.friction_force[0] + exact) / exact
    return CaseResult(
        "contact-viscous-drag",
        err if res.converged else np.inf,
        tolerance,
        {"normal_force": rep.normal_force, "friction_x": rep.friction_force[0], "exact": exact},
    )


def stick_test(
    mu=0.3, pressure=0.02, penalty=100.0, ratio=0.5, tolerance=5e-3, smoothing=0.0, slip_band=0.0
) -> CaseResult:
    """Proportional dead load (T, 0, -N) on the top of a 2 x 1 x 0.5 block with nu = 0 (K = 2/3 mu,
    no Poisson slip under the normal load), T = ratio mu N: every point sticks."""
    mesh = box((2.0, 1.0, 0.5), (4, 2, 2))
    normal = pressure * 2.0
    shear = ratio * mu * normal
    spec = ContactSpec(("z0",), Plane(), penalty=penalty, mu=mu, smoothing=smoothing, slip_band=slip_band)
    model = SolidModel(
        mesh,
        NeoHookean(mu=1.0, bulk=2.0 / 3.0),
        dirichlet=[Dirichlet.symmetry("y0", 1)],
        dead_loads={"z1": (shear, 0.0, -normal)},
        contacts=[spec],
    )
    res = run_stages(model, [Stage("load", factor=1.0, steps=2)], penetration_tol=1e-8)
    rep = model.contacts[0].report(res.x)
    err = abs(rep.friction_force[0] + shear) / shear + rep.slip_fraction
    return CaseResult(
        "contact-stick",
        err if res.converged else np.inf,
        tolerance,
        {"shear": shear, "friction_x": rep.friction_force[0], "slip_fraction": rep.slip_fraction},
    )


def _graded(fine: float, fine_length: float, total: float, growth: float = 1.3) -> np.ndarray:
    """0 .. total: uniform cells of `fine` up to `fine_length` (or `total`), then cells growing
    by `growth`, the last clipped at `total` and merged into the one before when under half its h."""
    pts = list(np.arange(0.0, min(fine_length, total) + 1e-12, fine))
    h = fine
    while pts[-1] < total - 1e-12:
        h *= growth
        pts.append(min(pts[-1] + h, total))
    if total - pts[-2] < 0.5 * h and len(pts) > 2:  # no sliver at the end
        pts.pop(-2)
    return np.array(pts)


def _hertz_mesh(radius, hole, thickness, fine):
    """A quarter ring hole < r < radius, -90 deg <= theta <= 0 (the contact at theta = -90 deg),
    one layer 0 <= z <= thickness, graded towards the contact point."""
    dtheta = _graded(fine / radius, 15 * fine / radius, np.pi / 2)
    depth = _graded(fine, 12 * fine, radius - hole)
    r_grid = np.sort(radius - depth)  # fine near the outer surface, increasing like tube_sector
    grid = skfem.MeshTet.init_tensor(r_grid, -np.pi / 2 + dtheta, np.array([0.0, thickness]))
    r, th, z = grid.p
    mesh = skfem.MeshTet(np.vstack([r * np.cos(th), r * np.sin(th), z]), grid.t)
    tol = 1e-8 * radius
    rad = lambda x: np.hypot(x[0], x[1])  # noqa: E731
    tags = {
        "outer": lambda x: np.abs(rad(x) - radius) < 1e-6 * radius,
        "inner": lambda x: np.abs(rad(x) - hole) < 1e-6 * radius,
        "sym": lambda x: np.abs(x[0]) < tol,
        "z0": lambda x: np.abs(x[2]) < tol,
        "z1": lambda x: np.abs(x[2] - thickness) < tol,
    }
    return curved(tag_boundaries(mesh, tags), "cylinder")


def plane_strain_modulus(material) -> float:
    """E* = E / (1 - nu^2), E = 2 mu (1 + nu): the plane-strain modulus of the material at small strain."""
    nu = material.poisson_ratio
    return float(2.0 * material.mu * (1 + nu) / (1 - nu**2))


def hertz_line_contact(force_per_length: float, radius: float, e_star: float) -> tuple[float, float]:
    """Hertz's cylinder of `radius` on a rigid flat under the force per length F': the half width
    a = sqrt(4 F' R / (pi E*)) and the peak pressure p0 = 2 F' / (pi a) of p0 sqrt(1 - x^2 / a^2)."""
    half_width = np.sqrt(4.0 * force_per_length * radius / (np.pi * e_star))
    return float(half_width), float(2.0 * force_per_length / (np.pi * half_width))


#: The Hertz slice: one layer of elements, 0 <= z <= HERTZ_THICKNESS (mm), w = 0 on both faces.
HERTZ_THICKNESS = 0.5


def hertz_model(radius, hole, approach, fine, penalty, smoothing) -> SolidModel:
    """The quarter ring of `_hertz_mesh` (P2) on the plane y = -radius, which it touches at
    x = 0; the hole moved rigidly by (0, -approach) at load factor 1; x = 0 a symmetry plane."""
    mesh = _hertz_mesh(radius, hole, HERTZ_THICKNESS, fine)
    spec = ContactSpec(
        ("outer",), Plane((0.0, -radius, 0.0), (0.0, 1.0, 0.0)), penalty=penalty, smoothing=smoothing
    )
    bcs = [
        Dirichlet("inner", (0, 1), (0.0, -approach)),
        Dirichlet.symmetry("sym", 0),
        Dirichlet.symmetry("z0", 2),
        Dirichlet.symmetry("z1", 2),
    ]
    return SolidModel(mesh, MATERIAL, dirichlet=bcs, contacts=[spec], formulation="p2")


def hertz_result(model: SolidModel, x: np.ndarray, radius: float, tolerance: float) -> CaseResult:
    """The Hertz case at the solved state x of `hertz_model`: the FE peak pressure against p0 of
    `hertz_line_contact` for the force per length of the solution (twice the half model's force,
    over the slice's thickness), and the FE half width (the farthest pressed contact point)."""
    term = model.contacts[0]
    rep = term.report(x)
    force_per_length = 2.0 * rep.normal_force / HERTZ_THICKNESS
    half_width, p0 = hertz_line_contact(force_per_length, radius, plane_strain_modulus(MATERIAL))
    xs = term.positions(x)[:, 0]
    width_fe = float(xs[term.state(x).pressure > 0].max())
    return CaseResult(
        "contact-hertz",
        abs(rep.max_pressure / p0 - 1.0),
        tolerance,
        {
            "force_per_length": force_per_length,
            "p0_hertz": p0,
            "p0_fe": rep.max_pressure,
            "half_width_hertz": half_width,
            "half_width_fe": width_fe,
            "a_over_R": half_width / radius,
            "dofs": model.n_dofs,
        },
    )


def hertz_test(
    radius=10.0, hole=2.0, approach=0.06, fine=0.08, penalty=100.0, tolerance=0.05, smoothing=0.0
) -> CaseResult:
    """Plane-strain cylinder on a rigid plane (module docstring); peak pressure against Hertz."""
    model = hertz_model(radius, hole, approach, fine, penalty, smoothing)
    res = run_stages(model, [Stage("press", factor=1.0, steps=2)], penetration_tol=1e-6)
    if not res.converged:
        return CaseResult("contact-hertz", np.inf, tolerance, {"message": res.message})
    return hertz_result(model, res.x, radius, tolerance)


def convergence_order(residuals, floor=1e-11) -> float:
    """Observed order from the last three residuals above `floor` in the asymptotic range
    (r_k <= 1e-2): log(r_k+1 / r_k) / log(r_k / r_k-1); nan without such a triple."""
    r = [v for v in residuals if v > floor]
    orders = [
        np.log(r[k + 1] / r[k]) / np.log(r[k] / r[k - 1])
        for k in range(1, len(r) - 1)
        if r[k] <= 1e-2 and r[k] < r[k - 1]
    ]
    return float(orders[-1]) if orders else float("nan")


def newton_test(
    radius=20.0, mu=0.3, pressure=0.2, penalty=100.0, steps=8, tolerance=1.8, smoothing=0.0, slip_band=0.0
) -> CaseResult:
    """Sliding on the inside of a cylinder (axis x, under the block), dragged along the axis and
    around it in `steps` increments: the order of convergence in the last increment, a steady
    slide in which no point changes its contact or slip status (the curvature and
    slip-coupling terms of the tangent act there). Earlier increments, where points change
    status, are semi-smooth: their tail orders are reported in the details (1.4-2.6 measured).
    The error is tolerance / order, so the case passes when the order >= tolerance."""
    mesh = box((2.0, 1.0, 1.0), (4, 2, 2))
    # the wall rises around the flat base: its long edges start 2 um into the wall (the block has
    # no other support in z), its centre line 4 um clear
    wall = CylinderWall(radius, (0.0, 0.5, float(np.sqrt((radius + 0.002) ** 2 - 0.25))), (1.0, 0.0, 0.0))
    spec = ContactSpec(
        ("z0",),
        wall,
        penalty=penalty,
        max_initial_penetration=0.003,
        smoothing=smoothing,
        slip_band=slip_band,
    )
    bcs = [Dirichlet("z1", (0, 1), (0.4, 0.3))]
    model = SolidModel(mesh, MATERIAL, dirichlet=bcs, chambers=ChamberSpec(("z1",)), contacts=[spec])
    stages = [
        Stage("press", pressure=pressure, steps=2),
        Stage("drag", factor=1.0, friction={0: mu}, steps=steps),
    ]
    res = run_stages(model, stages, penetration_tol=1e-8, options=NewtonOptions(tol=1e-11))
    drag = [s for s in res.steps if s.stage == "drag"]
    orders = [convergence_order(s.residuals) for s in drag]
    if not (res.converged and drag):
        return CaseResult("contact-newton", np.inf, 1.0, {"message": res.message})
    rep = model.contacts[0].report(res.x)
    last = orders[-1]
    return CaseResult(
        "contact-newton",
        tolerance / last if last > 0 else np.inf,
        1.0,
        {
            "order_last_increment": last,
            "orders": orders,
            "residuals_last": list(drag[-1].residuals),
            "slip_fraction": rep.slip_fraction,
            "friction_over_mu_n": float(np.linalg.norm(rep.friction_force) / (mu * rep.normal_force)),
        },
    )


CASES = {
    "contact-press": press_test,
    "contact-area": area_test,
    "contact-drag": drag_test,
    "contact-viscous-drag": viscous_drag_test,
    "contact-stick": stick_test,
    "contact-hertz": hertz_test,
    "contact-newton": newton_test,
}
