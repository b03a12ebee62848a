"""The kPa <-> MPa rule of `softcrawl.units`: floats and arrays, and the fixed arithmetic that keeps
the committed results' digits (a whole kPa survives the round trip)."""

import numpy as np

from softcrawl.units import kpa_to_mpa, mpa_to_kpa


def test_floats_and_arrays():
    assert kpa_to_mpa(100.0) == 0.1
    assert mpa_to_kpa(0.1) == 100.0
    np.testing.assert_array_equal(kpa_to_mpa(np.array([20.0, 40.0])), np.array([20.0, 40.0]) / 1e3)
    np.testing.assert_array_equal(mpa_to_kpa(np.array([0.02, 0.04])), np.array([0.02, 0.04]) * 1e3)


def test_the_arithmetic_is_the_one_the_results_were_made_with():
    for p in (0.0, 8.0, 36.0, 87.5, 100.0, 12.345):
        assert kpa_to_mpa(p) == p / 1e3
        assert mpa_to_kpa(p) == p * 1e3


def test_a_whole_kpa_survives_the_round_trip():
    assert all(mpa_to_kpa(kpa_to_mpa(float(p))) == p for p in range(1001))
