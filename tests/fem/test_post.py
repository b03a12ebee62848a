"""Post-processing and VTU export on small solved states."""

import meshio
import numpy as np
import pytest

from softcrawl.fem import reference_models as RM
from softcrawl.fem.laws import NeoHookean
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.path import load_path
from softcrawl.fem.post import actuator_length, element_fields, max_principal_stretch, outer_radius_at
from softcrawl.fem.structured import box
from softcrawl.fem.vtu import write_path


@pytest.fixture(scope="module")
def stretched_box():
    """A 2 x 2 x 4 box stretched to lambda = 1.3 along z, lateral faces free."""
    mesh = box((2.0, 2.0, 4.0), (2, 2, 2))
    bcs = [
        Dirichlet.symmetry("x0", 0),
        Dirichlet.symmetry("y0", 1),
        Dirichlet.symmetry("z0", 2),
        Dirichlet.prescribed("z1", 2, 1.2),
    ]
    model = SolidModel(mesh, NeoHookean.nearly_incompressible(0.03, 1e4), dirichlet=bcs)
    res = load_path(model, [(0.0, 0.5), (0.0, 1.0)], control="displacement")
    assert res.converged
    return model, res


def test_length_radius_stretch_and_stress_of_a_homogeneous_state(stretched_box):
    model, res = stretched_box
    x = res.steps[-1].x
    lam = 1.3
    assert actuator_length(model, x, bottom="z0", top="z1") == pytest.approx(4.0 * lam, rel=1e-10)
    assert max_principal_stretch(model, x) == pytest.approx(lam, rel=1e-8)
    fields = element_fields(model, x)
    # uniaxial incompressible Cauchy stress mu (lam^2 - 1/lam), lateral stresses zero
    expected = 0.03 * (lam**2 - 1 / lam)
    assert np.allclose(fields.cauchy[2, 2], expected, rtol=2e-3)
    assert np.abs(fields.cauchy[0, 0]).max() < 1e-3 * expected
    assert np.allclose(fields.von_mises, expected, rtol=2e-3)
    # the lateral face x = 2 sits at 2 / sqrt(lam) (outer "radius" of the box's x-face layer)
    lateral = model.nodes[0] + model.displacement(x)[0]
    assert lateral.max() == pytest.approx(2.0 / np.sqrt(lam), rel=2e-4)


def test_outer_radius_of_the_tube_matches_the_analytic_one():
    model = RM.tube_model(3.0, 9.0, n_radial=4, n_angle=6)
    res = load_path(model, [(0.01, 0.0)])
    x = res.steps[-1].x
    from softcrawl.fem import analytic

    la = analytic.tube_inner_stretch(0.03, 0.01, 3.0, 9.0)
    expected = analytic.tube_outer_stretch(la, 3.0, 9.0) * 9.0
    assert outer_radius_at(model, x, 0.5, tag="outer") == pytest.approx(expected, rel=2e-3)


def test_vtu_series_has_displacement_and_stress(stretched_box, tmp_path):
    model, res = stretched_box
    files = write_path(tmp_path, model, res)
    assert len(files) == 3 and (tmp_path / "step.pvd").exists()
    m = meshio.read(files[-1])
    u = m.point_data["displacement_mm"]
    assert np.abs(u[:, 2]).max() == pytest.approx(1.2, rel=1e-10)
    assert m.cell_data["von_mises_MPa"][0].shape == (model.mesh.t.shape[1],)
    assert m.cell_data["cauchy_stress_MPa"][0].shape == (model.mesh.t.shape[1], 6)


def test_volumetric_error_is_zero_for_a_homogeneous_state_and_for_p2():
    """|J - 1 - p/K| (fem.post.volumetric_error): a homogeneous stretch is represented exactly by
    the P1 pressure, so the error is round-off; a bending-type state is not, so it is positive;
    the displacement-only formulation has p = K (J - 1) by construction."""

    from softcrawl.fem.laws import NeoHookean
    from softcrawl.fem.model import Dirichlet, SolidModel
    from softcrawl.fem.path import load_path
    from softcrawl.fem.post import volumetric_error
    from softcrawl.fem.structured import box

    def model(formulation, load):
        bcs = [Dirichlet.symmetry("x0", 0), Dirichlet.symmetry("y0", 1), Dirichlet.symmetry("z0", 2)]
        bcs += [load]
        return SolidModel(
            box((2.0, 2.0, 4.0), (2, 2, 3)),
            NeoHookean(mu=0.03, bulk=3.0),
            dirichlet=bcs,
            formulation=formulation,
        )

    m = model("p2p1", Dirichlet.prescribed("z1", 2, 2.0))
    x = load_path(m, [(0.0, 1.0)], control="displacement").steps[-1].x
    vmax, vmean = volumetric_error(m, x)
    assert vmax < 1e-8 and vmean < 1e-8  # the Newton tolerance, 4.5e-10 observed
    m = model("p2p1", Dirichlet("z1", (0, 2), (0.8, 0.5)))  # shear and stretch of the top: not homogeneous
    x = load_path(m, [(0.0, 1.0)], control="displacement").steps[-1].x
    vmax, vmean = volumetric_error(m, x)
    assert vmax > 1e-4 and 0 < vmean < vmax
    m = model("p2", Dirichlet("z1", (0, 2), (0.2, 0.2)))
    x = load_path(m, [(0.0, 0.5), (0.0, 1.0)], control="displacement").steps[-1].x
    assert volumetric_error(m, x)[0] < 1e-12
