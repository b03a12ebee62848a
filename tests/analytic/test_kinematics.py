"""Acceptance tests of the constant-curvature kinematics (eqs. 4-6, 9) and the exact IK."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from softcrawl.analytic import kinematics as kin
from softcrawl.analytic.errors import ModelInputError


def test_fk_acceptance_values():
    k, t, p, lc = kin.forward([110.0, 125.0, 140.0], d=14.0)
    # The values are rounded: they agree with ours to the printed digits ...
    assert round(k, 7) == 0.0098974
    assert round(t, 5) == 1.23718
    assert round(p, 5) == 2.09440
    # ... and ours agree with the closed forms (Q = 675 mm^2) far below 1e-6 relative.
    assert k == pytest.approx(2 * np.sqrt(675.0) / (14.0 * 375.0), rel=1e-12)
    assert t == pytest.approx(2 * np.sqrt(675.0) / 42.0, rel=1e-12)
    assert p == pytest.approx(2.0 * np.pi / 3.0, rel=1e-12)
    assert lc == 125.0
    assert t == pytest.approx(k * lc, rel=1e-14)


def test_printed_ik_does_not_invert_fk():
    c = kin.configuration([110.0, 125.0, 140.0])
    printed = kin.printed_ik_lengths(c.kappa, c.phi, c.length)
    np.testing.assert_allclose(printed, [103.1, 117.2, 109.1], atol=0.05)
    np.testing.assert_allclose(kin.inverse(kin.tip([110.0, 125.0, 140.0])), [110, 125, 140], rtol=1e-12)


def test_transform_matches_printed_matrix():
    T = kin.transform([110.0, 125.0, 140.0])
    c = kin.configuration([110.0, 125.0, 140.0])
    ct, st_, cp, sp = np.cos(c.theta), np.sin(c.theta), np.cos(c.phi), np.sin(c.phi)
    expected = np.array(
        [
            [cp**2 * ct + sp**2, cp * sp * (ct - 1), cp * st_, cp * (1 - ct) / c.kappa],
            [cp * sp * (ct - 1), sp**2 * ct + cp**2, sp * st_, sp * (1 - ct) / c.kappa],
            [-cp * st_, -sp * st_, ct, st_ / c.kappa],
            [0, 0, 0, 1],
        ]
    )
    np.testing.assert_allclose(T, expected, atol=1e-12)
    np.testing.assert_allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3), atol=1e-14)


def test_straight_configuration():
    k, t, p, lc = kin.forward([120.0, 120.0, 120.0])
    assert k == 0 and t == 0
    np.testing.assert_allclose(kin.tip([120.0, 120.0, 120.0]), [0, 0, 120], atol=0)
    np.testing.assert_allclose(kin.inverse([0.0, 0.0, 120.0]), [120, 120, 120], rtol=1e-15)


lengths = st.floats(min_value=95.0, max_value=160.0, allow_nan=False)


@settings(max_examples=150, deadline=None)
@given(lengths, lengths, lengths)
def test_ik_inverts_fk_hypothesis(l1, l2, l3):
    l = np.array([l1, l2, l3])
    np.testing.assert_allclose(kin.inverse(kin.tip(l)), l, rtol=1e-9, atol=0)


def test_ik_inverts_fk_seeded_including_near_straight():
    rng = np.random.default_rng(20261121)
    base = rng.uniform(95.0, 160.0, size=(2000, 3))
    centre = rng.uniform(95.0, 160.0, size=(3000, 1))
    scales = 10.0 ** rng.uniform(-12, -1, size=(3000, 1))
    near = centre + scales * rng.standard_normal((3000, 3))
    l = np.vstack([base, near])
    back = kin.inverse(kin.tip(l))
    rel = np.max(np.abs(back - l) / l)
    assert rel < 1e-9
    # Large bends (theta near 3 rad) are covered by the uniform sample.
    assert kin.forward(base)[1].max() > 2.5


def test_bad_input():
    with pytest.raises(ModelInputError) as e:
        kin.forward([100.0, -1.0, 100.0])
    assert e.value.parameter == "lengths"
    with pytest.raises(ModelInputError) as e:
        kin.inverse([0.0, 0.0, -5.0])
    assert e.value.parameter == "tip"
