"""Tests of `softcrawl material` (run in-process through studies.cli.main)."""

from __future__ import annotations

import json

import pytest

from studies.cli import main


def run(capsys, *argv):
    code = main(["material", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_fit_json_is_valid_and_complete(capsys):
    code, out, err = run(capsys, "fit", "--json")
    assert code == 0, err
    record = json.loads(out)
    assert record["data"] == "ecoflex-00-50" and record["model"] == "neo-hookean"
    assert 0.02 <= record["params_mpa"]["mu"] <= 0.05
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
        [sys.executable, "-m", "studies", "material", "show", "nope"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and result.stdout == ""
    assert len(result.stderr.strip().splitlines()) == 1 and "material:" in result.stderr
