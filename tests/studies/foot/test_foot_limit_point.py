"""`studies.foot.model.limit_point`: a stopped drag whose resistance passed a maximum."""

import numpy as np
import pytest

from softcrawl.studies.foot.model import LIMIT_DROP, limit_point


def test_the_largest_computed_state_is_the_bound():
    d = np.array([0.25, 0.5, 0.75, 1.0, 1.25])
    f = 100.0 - 40.0 * (d - 0.8) ** 2  # true peak 100 N at 0.8 mm, between the samples 0.75 and 1.0
    top = limit_point(d, f)
    assert top == (0.75, pytest.approx(100.0 - 40.0 * 0.05**2))  # a computed state, below the peak
    assert top[1] < 100.0


def test_a_rising_or_flat_curve_has_no_limit_point():
    d = np.linspace(0.25, 2.0, 8)
    assert limit_point(d, 10 * d) is None  # still rising where it stopped
    f = np.full(8, 20.0)
    f[-1] = 20.0 * (1 - 0.5 * LIMIT_DROP)  # a plateau within the threshold: no peak was passed
    assert limit_point(d, f) is None


def test_a_fall_after_the_first_sample_reports_that_sample():
    assert limit_point(np.array([1.0, 2.0]), np.array([5.0, 3.0])) == (1.0, 5.0)
