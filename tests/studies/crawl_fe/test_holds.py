"""The six holds of `studies.crawl_fe.model` fix the six rigid-body modes and nothing else.

For each rigid mode (translations along x, y, z; small rotations about x, y, z through the body's
mid-point) the six holds' extensions form a 6 x 6 matrix: it must be regular (every rigid mode is
held, so the tangent is regular with the wall clear), while a deformation that leaves the rear
hub's bottom face in place, the front hub's top face without lateral motion and no twist (the
actuators' axial extension, u_z = e (z + t_hub)) must stretch none of them: the holds resist
the rigid modes, not the body's own deformation.
"""

import numpy as np

from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.discretisation import Discretisation
from softcrawl.geometry.body_mesh import mesh_body
from softcrawl.geometry.design import RobotDesign
from softcrawl.studies.crawl_fe.model import HOLDS, with_hold_tags


def test_the_holds_fix_the_rigid_modes_and_nothing_else():
    design = RobotDesign()
    tagged = with_hold_tags(mesh_body(design, "quick"))
    space = Discretisation(tagged.to_skfem(order=2))
    terms = [AxialLink(b, a, c, 1.0, name=name).build(space) for name, b, a, c in HOLDS]
    X = space.nodes
    centre = 0.5 * (X.min(axis=1) + X.max(axis=1))[:, None]
    modes = []
    for axis in range(3):
        u = np.zeros_like(X)
        u[axis] = 1.0
        modes.append(u)
    for axis in range(3):
        w = np.zeros(3)
        w[axis] = 1e-3
        modes.append(np.cross(w, (X - centre).T).T)
    x = np.zeros(space.n_dofs)
    matrix = []
    for u in modes:
        x[: space.n_u] = u.T.reshape(-1)
        matrix.append([t.extension(x) for t in terms])
    s = np.linalg.svd(np.array(matrix), compute_uv=False)
    assert s.min() > 1e-6 * s.max()  # regular: observed 1.5e-2 (rotations of 1e-3 rad)
    x[: space.n_u] = np.stack([0 * X[0], 0 * X[1], 0.01 * (X[2] + design.foot.hub_thickness)]).T.reshape(-1)
    assert max(abs(t.extension(x)) for t in terms) < 1e-12
