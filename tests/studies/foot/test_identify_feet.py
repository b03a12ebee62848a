"""The feet's identification (studies/foot/identify.py, record 070): the friction fit finds the
analytic root of a known resistance law, reports a target outside the sourced range instead of
clipping it, and never reads the paper's held-out measurements (Table 2, Fig. 21)."""

from __future__ import annotations

import ast
import inspect
import math

import pytest

from softcrawl import paper
from softcrawl.studies.foot import identify, identify_run


def test_fit_finds_the_root_of_a_coulomb_like_law():
    # F(mu) = F0 + mu N with a mild curvature: the root of F = 15.3 N is known in closed form
    law = lambda mu: 2.0 + 30.0 * mu + 3.0 * mu**2  # noqa: E731
    root = (-30.0 + math.sqrt(30.0**2 - 4 * 3.0 * (2.0 - 15.3))) / (2 * 3.0)
    fit = identify.fit_mu(law, 15.3, "smooth", tol=1e-4)
    assert fit.in_range and fit.mu == pytest.approx(root, abs=1e-4)
    assert abs(fit.residual_n) <= 1e-4 and len(fit.solves) <= identify.MAX_SOLVES
    assert fit.solves[:2] == ((0.3, law(0.3)), (0.9, law(0.9)))  # both ends of the range first


def test_a_target_outside_the_range_is_reported_not_clipped():
    fit = identify.fit_mu(lambda mu: 40.0 * mu, 50.0, "grooved")  # F(0.9) = 36 N < 50 N
    assert fit.mu is None and not fit.in_range
    assert fit.resistance_n == pytest.approx(36.0) and fit.residual_n == pytest.approx(-14.0)
    assert "outside" in fit.note and "mu = 0.9" in fit.note
    low = identify.fit_mu(lambda mu: 40.0 * mu, 6.0, "smooth")  # F(0.3) = 12 N: needs mu = 0.15
    assert low.mu is None and "would need mu = 0.150" in low.note


def test_a_failed_drag_is_not_a_fit():
    fit = identify.fit_mu(lambda mu: math.nan, 15.3, "smooth")
    assert fit.mu is None and "converge" in fit.note


class _HeldOut(dict):
    """A paper constant that the identification must not read."""

    def _refuse(self, *args, **kwargs):
        raise AssertionError("the identification read a held-out measurement (Table 2 / Fig. 21)")

    __getitem__ = __iter__ = __len__ = get = items = keys = values = __contains__ = _refuse


def test_identification_reads_no_table_2_or_fig_21(monkeypatch, tmp_path):
    held_out = [n for n in vars(paper) if n.upper().startswith(("TABLE2", "FIG21")) or n == "table2"]
    assert "TABLE2_MM_S" in held_out and "table2" in held_out
    for name in held_out:
        value = _HeldOut() if isinstance(getattr(paper, name), dict) else _HeldOut()._refuse
        monkeypatch.setattr(paper, name, value)
    # eq. 26 / 3 per foot (record 062): 5.10 N and 5.63 N; F = 30 mu (+ 1 N) crosses them in range
    result = identify.identify(lambda mu: 15.0 * mu, lambda mu: 15.0 * mu + 1.0)
    assert result.mu("smooth") == pytest.approx(5.1 / 15.0, abs=0.1 / 15.0)
    assert result.mu("grooved") == pytest.approx((16.9 / 3 - 1.0) / 15.0, abs=0.1 / 15.0)
    assert result.youngs_mpa == pytest.approx(5.5205, abs=1e-3)  # Gent's relation at 70A, not fitted
    paths = identify_run.write(result, tmp_path)
    assert all(p.exists() for p in paths)
    # and no module of the identification names them
    for module in (identify, identify_run):
        nodes = list(ast.walk(ast.parse(inspect.getsource(module))))
        names = {n.id for n in nodes if isinstance(n, ast.Name)}
        names |= {n.attr for n in nodes if isinstance(n, ast.Attribute)}
        names |= {a.name for n in nodes if isinstance(n, ast.ImportFrom) for a in n.names}
        assert not names & set(held_out), module.__name__


def test_predictions_read_the_file_and_never_move_an_input_beyond_its_source(tmp_path):
    result = identify.identify(lambda mu: 40.0 * mu, lambda mu: 15.0 * mu + 1.0)
    identify_run.write(result, tmp_path)
    loaded = identify.load(tmp_path / "feet.json")
    assert loaded == result
    assert loaded.prediction_mu("smooth") == (0.3, loaded.prediction_mu("smooth")[1])  # 12 N > 5.1 N
    assert "outside the sourced range" in loaded.prediction_mu("smooth")[1]
    mu, what = loaded.prediction_mu("grooved")
    assert what == "identified" and mu == pytest.approx((16.9 / 3 - 1.0) / 15.0, abs=0.1 / 15.0)
    high = identify.identify(lambda mu: 2.0 * mu, None)  # F(0.9) = 1.8 N < 5.1 N: the upper end
    assert high.prediction_mu("smooth")[0] == 0.9
    with pytest.raises(ValueError, match="mu_grooved was not identified"):
        high.prediction_mu("grooved")
