"""`softcrawl study identify`: the paper's identification procedure on (fake and FE) sweep results."""

import json

import pytest

from softcrawl.studies.cli import main
from softcrawl.studies.sweeps import tables as runner
from tests.studies.fakes import fake_f_p, fake_k_p

FAKE = "tests.studies.fakes:loaded_simulate"


def _folder(tmp_path):
    return tmp_path / "identify" / "ecoflex-00-50-quick"


def test_identify_recovers_the_law_behind_the_data(tmp_path):
    assert (
        main(["study", "identify", "--quick", "--simulator", FAKE, "--no-progress", "--out", str(tmp_path)])
        == 0
    )
    folder = _folder(tmp_path)
    table = runner.read_csv(folder / "identification.csv")
    assert [float(r["pressure_kpa"]) for r in table] == [10.0 * k for k in range(1, 11)]
    for r in table:
        p = float(r["pressure_kpa"])
        assert float(r["k_p_fe_n_per_m"]) == pytest.approx(1e3 * fake_k_p(p), rel=1e-9)
        assert float(r["f_p_fe_n"]) == pytest.approx(fake_f_p(p), rel=1e-9, abs=1e-12)
        assert float(r["fit_rms_mm"]) < 1e-9
        # eqs. 19-24 sit beside it, in the paper's units
        assert float(r["k_p_epsa1_n_per_m"]) == pytest.approx(
            -2.579 * p + 266.8 if p <= 60 else 0.9125 * p + 62.19
        )
    laws = json.loads((folder / "identification.json").read_text())
    assert len(laws["k_p_n_per_m"]) == 2 and laws["k_p_n_per_m"][0]["p_max_kpa"] == 60.0
    assert laws["k_p_n_per_m"][1]["slope"] == pytest.approx(0.2, rel=1e-9)  # 2e-4 N/mm/kPa
    assert laws["f_p_n"][0]["slope"] == pytest.approx(0.04, rel=1e-9)
    for png in ("identify.png", "identification.png"):
        assert (folder / png).stat().st_size > 10_000


def test_identify_leaves_out_pressures_a_weight_did_not_reach(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("SOFTCRAWL_FAKE_FAIL_HEAVY", "1")
    main(["study", "identify", "--quick", "--simulator", FAKE, "--no-progress", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert "P = 70 kPa not used" in out and "W = 1 N (failed)" in out
    laws = json.loads((_folder(tmp_path) / "identification.json").read_text())
    assert laws["pressures_kpa"] == [10.0, 20.0, 30.0, 40.0, 50.0, 60.0]
    assert "one line per parameter" in laws["message"]  # nothing left above 60 kPa
    curves = runner.read_csv(_folder(tmp_path) / "curves.csv")
    heavy = [r for r in curves if float(r["end_load_n"]) == 1.0]
    assert heavy[0]["trial_status"] == "failed" and "70 kPa" in heavy[0]["reason"]


@pytest.mark.slow
def test_fe_weight_shortens_the_actuator_linearly():
    """Real FE (quick mesh): a heavier weight shortens the ePSA, and about linearly in W (eq. 3)."""
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.response import simulate_epsa

    y = {}
    for w in (0.0, 0.25, 0.5):
        c = simulate_epsa(EPSADesign(), quick=True, pressures_kpa=(30.0,), end_load_n=w)
        assert c.converged, c.message
        y[w] = c.rows[-1].length_mm - c.rows[0].length_mm
    assert y[0.0] > y[0.25] > y[0.5]
    assert abs((y[0.0] - y[0.25]) - (y[0.25] - y[0.5])) < 0.1 * (y[0.0] - y[0.5])


def test_landed_targets_are_grouped_with_their_pressure():
    """Volume control lands on a target to 1e-5: 79.9995 kPa is the 80 kPa state of that weight."""
    from softcrawl.studies.epsa.identification import identify_from_rows

    rows = []
    for w, p80 in ((0.0, 79.9995), (1.0, 80.0)):
        rows.append({"end_load_n": w, "pressure_kpa": 0.0, "length_mm": 100.0, "row_status": "reference"})
        for p in (20.0, 40.0, p80):
            y = (fake_f_p(p) - w) / fake_k_p(p)
            rows.append(
                {"end_load_n": w, "pressure_kpa": p, "length_mm": 100.0 + y, "row_status": "converged"}
            )
    ident = identify_from_rows(rows)
    assert ident.pressures_kpa == (20.0, 40.0, 80.0) and not ident.skipped
    assert ident.result.per_pressure.k_p[-1] == pytest.approx(fake_k_p(80.0), rel=1e-4)


def test_rules_read_a_landed_100_kpa_state_as_100_kpa():
    from softcrawl.studies.epsa.rules import design_curves

    rows = [
        {
            "fiber_turns": 10,
            "pressure_kpa": p,
            "length_mm": 100 + p / 2,
            "outer_radius_mm": 9.0,
            "row_status": s,
            "trial_status": "completed",
            "limit_pressure_kpa": "",
        }
        for p, s in ((0.0, "reference"), (50.0, "converged"), (99.99995, "converged"))
    ]
    curve = design_curves(rows, "fiber_turns")[10.0]
    assert curve.withstands and curve.at(100.0) is not None


def test_pressures_past_the_longest_state_of_a_weight_are_left_out():
    from softcrawl.studies.epsa.identification import identify_from_rows

    rows = []
    for w in (0.0, 1.0):
        rows.append({"end_load_n": w, "pressure_kpa": 0.0, "length_mm": 100.0, "row_status": "reference"})
        for p in (10.0, 20.0, 30.0, 40.0):
            y = (fake_f_p(p) - w) / fake_k_p(p)
            if w == 1.0 and p == 40.0:
                y = 0.0  # the loaded actuator collapses
            rows.append(
                {"end_load_n": w, "pressure_kpa": p, "length_mm": 100.0 + y, "row_status": "converged"}
            )
    ident = identify_from_rows(rows)
    assert ident.pressures_kpa == (10.0, 20.0, 30.0)
    assert ident.skipped[0][0] == 40.0 and "longest at 30 kPa" in ident.skipped[0][1]
