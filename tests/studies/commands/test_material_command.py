"""Tests of `softcrawl material` (run in-process through studies.cli.main)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from softcrawl.studies.cli import main


def run(capsys, *argv):
    code = main(["material", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_fit_json_is_valid_and_complete(capsys):
    code, out, err = run(capsys, "fit", "--json")
    assert code == 0, err
    record = json.loads(out)
    assert record["data"] == "ecoflex-00-50" and record["model"] == "neo-hookean"
    assert record["params_mpa"]["mu"] == pytest.approx(0.022416, abs=2e-6)  # the tensile fit
    assert record["max_strain"] == 1.0 and record["strain_range"][1] <= 1.0
    assert record["rms_error_mpa"] > 0 and "Marechal" in record["attribution"]
    assert "ODbL" in record["license"]


def test_fit_out_writes_json_and_png(capsys, tmp_path):
    code, out, err = run(
        capsys,
        "fit",
        "--data",
        "dragon-skin-30",
        "--model",
        "yeoh",
        "--max-strain",
        "0.5",
        "--out",
        str(tmp_path),
    )
    assert code == 0, err
    record = json.loads((tmp_path / "fit.json").read_text())
    assert record["model"] == "yeoh" and set(record["params_mpa"]) == {"C10", "C20", "C30"}
    assert record["strain_range"][1] <= 0.5
    # Independent least squares of P = 2 (lam - lam^-2)(C10 + 2 C20 x + 3 C30 x^2), x = I1 - 3.
    # Unconstrained, C30 < 0 (unstable at large strain), so the fit holds C30 = 0 and is the
    # least squares over (C10, C20) alone.
    from softcrawl import materials

    data = materials.load_tensile("dragon-skin-30")
    lam, stress = materials.select_fit_points(data.stretch, data.nominal_stress, 0.5)
    x, g = lam**2 + 2 / lam - 3, 2 * (lam - lam**-2)
    free = np.linalg.lstsq(np.column_stack([g, 2 * g * x, 3 * g * x**2]), stress, rcond=None)[0]
    assert free[2] < 0 and any("unstable" in note for note in record["notes"])
    c10, c20 = np.linalg.lstsq(np.column_stack([g, 2 * g * x]), stress, rcond=None)[0]
    params = record["params_mpa"]
    assert (params["C10"], params["C20"], params["C30"]) == pytest.approx((c10, c20, 0.0), rel=1e-6)
    residual = stress - g * (c10 + 2 * c20 * x)
    assert record["rms_error_mpa"] == pytest.approx(np.sqrt(np.mean(residual**2)), rel=1e-6)
    assert (tmp_path / "fit.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "C10 =" in out and "strain range" in out


def test_list_shows_every_preset(capsys):
    code, out, _ = run(capsys, "list")
    assert code == 0
    for name in (
        "ecoflex-00-50",
        "ecoflex-00-50-fit",
        "ecoflex-00-30",
        "dragon-skin-30",
        "rubber-70a",
        "abs",
        "kevlar",
    ):
        assert f"\n{name} " in out


@pytest.mark.parametrize(
    "argv, parameter",
    [
        (("show", "no-such-material"), "material"),
        (("fit", "--data", "no-such-data"), "data"),
        (("fit", "--max-strain", "-1"), "max_strain"),
    ],
)
def test_user_errors_exit_2_with_one_line_naming_the_parameter(capsys, argv, parameter):
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and (
        f"error: {parameter}:" in lines[0] or f"--{parameter.replace('_', '-')}:" in lines[0]
    )


def test_console_entry_point_unknown_preset_exit_code_2():
    import subprocess
    import sys

    result = subprocess.run(
        [sys.executable, "-m", "softcrawl", "material", "show", "nope"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and result.stdout == ""
    assert len(result.stderr.strip().splitlines()) == 1 and "material:" in result.stderr
