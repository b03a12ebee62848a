"""The crawling cycle's geometry (analytic.cycle): the bend-plane form against the 3D one, the fit check."""

import numpy as np
import pytest

from softcrawl.analytic import cycle as cm
from softcrawl.analytic.errors import ModelInputError
from softcrawl.analytic.pipe import Pipe
from softcrawl.analytic.prototype import actuator_set


@pytest.mark.parametrize("kind", ["straight", "elbow"])
def test_plane_distance_is_locate_in_the_bend_plane(kind):
    pipe = Pipe(kind, 70.0, 40.0)
    rng = np.random.default_rng(3)
    x = rng.uniform(-60.0, 120.0, 2000)
    z = rng.uniform(-50.0, 400.0, 2000)  # behind the start, along the bend and past its end
    dist, _ = pipe.locate(np.stack([x, np.zeros_like(x), z], -1))
    np.testing.assert_allclose(pipe.plane_distance(x, z), dist, rtol=0, atol=1e-12)


def test_bend_plane_form_is_the_3d_cycle_with_p2_equal_p3():
    """planar_body_points / planar_slide of (l1, l23, l23) against body_points / rear_slide with
    the elbow roll: the same points in the x-z plane (y = 0), bending both ways."""
    pipe = Pipe("elbow", 70.0, 60.0)
    rot = cm.elbow_roll(pipe)
    d, f = 14.0, np.linspace(0.0, 1.0, 11)
    for l1, l23 in [(130.0, 110.0), (105.0, 140.0), (120.0, 120.0)]:
        pts = cm.body_points(np.zeros(3), rot, np.array([l1, l23, l23]), d, f.size)
        px, pz = cm.planar_body_points(0.0, 0.0, 0.0, np.array(l1), np.array(l23), d, f)
        np.testing.assert_allclose(pts[:, 1], 0.0, atol=1e-12)
        np.testing.assert_allclose(pts[:, 0], px, atol=1e-10)
        np.testing.assert_allclose(pts[:, 2], pz, atol=1e-10)
        # the slide of deflation: signed curvature k in the plane, kappa >= 0 at phi = +-90 deg in 3D
        k, lc = cm.planar_configuration(l1, l23, d)
        step = lc - 99.0
        x, z, heading = cm.planar_slide(0.0, 0.0, 0.0, k, step)
        phi = np.pi / 2 if k >= 0 else -np.pi / 2
        rear = cm.rear_slide(np.zeros(3), rot, abs(k), phi, step)
        np.testing.assert_allclose(rear, [x, 0.0, z], atol=1e-10)
        frame = cm.frame_slide(rot, abs(k), phi, step)
        np.testing.assert_allclose(frame[:, 2], [np.sin(heading), 0.0, np.cos(heading)], atol=1e-12)


def test_pipe_fit_bodies_and_allowance():
    pipe = Pipe("straight", 70.0)
    assert cm.PipeFit.of(pipe).allow == pytest.approx(12.0)
    epsa = cm.PipeFit.of(pipe, body="epsa")
    assert epsa.epsa and epsa.body_radius == 9.0 and epsa.allow == pytest.approx(26.0)
    assert epsa.fits(26.0 + 1e-10) and not epsa.fits(26.0 + 1e-8)
    with pytest.raises(ModelInputError) as e:
        cm.PipeFit.of(pipe, body="rings")
    assert e.value.parameter == "body"
    with pytest.raises(ModelInputError) as e:
        cm.PipeFit.of(Pipe("straight", 40.0))
    assert e.value.parameter == "diameter"


def test_deflated_pressures_vent_below_rest_and_invert_the_statics_above():
    acts = actuator_set("nominal")
    rest = float(acts[0].length(0.0, 0.0))
    target = float(acts[0].length(30.0, 0.0))
    p = cm.deflated_pressures(acts, np.array([rest - 2.0, target, rest]), 0.0)
    assert p[0] == 0.0 and p[2] == 0.0
    assert p[1] == pytest.approx(30.0, abs=1e-9)
