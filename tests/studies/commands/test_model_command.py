"""`softcrawl model ...` end to end (in-process)."""

import json

import pytest

from softcrawl.studies.cli import main


def run(capsys, *argv):
    code = main(["model", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_fk_json(capsys):
    code, out, _ = run(capsys, "fk", "--lengths", "110", "125", "140", "--d", "14", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["kappa_per_mm"] == pytest.approx(0.0098974, rel=1e-5)
    assert data["theta_rad"] == pytest.approx(1.23718, rel=1e-5)
    assert data["phi_rad"] == pytest.approx(2.09440, rel=1e-5)
    assert len(data["tip_mm"]) == 3


def test_ik_json_roundtrip(capsys):
    _, out, _ = run(capsys, "fk", "--lengths", "101", "133", "120", "--json")
    tip = json.loads(out)["tip_mm"]
    code, out, _ = run(capsys, "ik", "--tip", *map(repr, tip), "--json")
    assert code == 0
    assert json.loads(out)["lengths_mm"] == pytest.approx([101, 133, 120], rel=1e-9)


def test_statics_and_load(capsys):
    code, out, _ = run(capsys, "statics", "--pressure", "100", "--actuator", "1", "--g", "0", "--json")
    data = json.loads(out)
    assert code == 0 and data["length_mm"] == pytest.approx(152.763, abs=1e-3)
    assert data["blocked_force_n"] == pytest.approx(8.096)
    code, out, _ = run(capsys, "load")
    assert code == 0 and "2.456 kg" in out
    code, out, _ = run(capsys, "load", "--g", "9.81", "--json")
    assert json.loads(out)["load_kg"] == pytest.approx(2.505, abs=5e-4)


@pytest.mark.parametrize(
    "argv, parameter",
    [
        (["statics", "--pressure", "-1"], "pressure"),
        (["ik", "--tip", "0", "0", "-1"], "tip"),
        (["fk", "--lengths", "100", "0", "100"], "lengths"),
        (["plan", "--pipe", "elbow", "--out", "unused"], "bend-radius"),
        (["plan", "--pipe", "straight", "--diameter", "40", "--out", "unused"], "diameter"),
        (["plan", "--pipe", "straight", "--search", "continuous", "--out", "unused"], "search"),
        (
            [
                "plan",
                "--pipe",
                "elbow",
                "--bend-radius",
                "40",
                "--search",
                "continuous",
                "--cycles",
                "0",
                "--out",
                "unused",
            ],
            "cycles",
        ),
    ],
)
def test_user_errors_exit_2_naming_the_parameter(capsys, argv, parameter, tmp_path):
    argv = [a if a != "unused" else str(tmp_path) for a in argv]
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert err.count("\n") == 1 and parameter in err


def test_workspace_and_plan_write_files(capsys, tmp_path):
    code, out, _ = run(capsys, "workspace", "--out", str(tmp_path / "ws"), "--n", "5", "--json")
    assert code == 0 and json.loads(out)["points"] == 125
    assert (tmp_path / "ws" / "workspace.png").stat().st_size > 1000
    code, out, _ = run(
        capsys,
        "plan",
        "--pipe",
        "straight",
        "--length",
        "200",
        "--step",
        "20",
        "--out",
        str(tmp_path / "p"),
        "--json",
    )
    data = json.loads(out)
    assert code == 0 and data["success"]
    for g in data["gait"]:
        assert len(set(g["pressures_kpa"])) == 1
    for name in ("plan.png", "plan.json", "gait.csv"):
        assert (tmp_path / "p" / name).exists()


def test_identify_from_csv(capsys, tmp_path):
    import numpy as np

    from softcrawl.analytic.identification import synthetic_table
    from softcrawl.analytic.prototype import prototype_epsa

    a = prototype_epsa(1)
    P, W, y = synthetic_table(a, np.arange(10.0, 101.0, 10.0), [0.0, 1.0, 2.0])
    path = tmp_path / "t.csv"
    np.savetxt(
        path,
        np.column_stack([P, W, y]),
        delimiter=",",
        comments="",
        header="pressure_kpa,load_n,extension_mm",
    )
    code, out, _ = run(capsys, "identify", "--table", str(path), "--json")
    data = json.loads(out)
    assert code == 0
    assert data["k_p_n_per_m"]["low"] == pytest.approx([-2.579, 266.8], rel=1e-6)
    assert data["f_p_n"]["high"] == pytest.approx([0.1463, -6.534], rel=1e-6)
    code, out, err = run(capsys, "identify", "--table", str(tmp_path / "missing.csv"))
    assert code == 2 and "table" in err


def test_continuous_elbow_plan(capsys, tmp_path):
    code, out, _ = run(
        capsys,
        "plan",
        "--pipe",
        "elbow",
        "--bend-radius",
        "80",
        "--search",
        "continuous",
        "--cycles",
        "12",
        "--out",
        str(tmp_path),
        "--json",
    )
    data = json.loads(out)
    assert code == 0 and data["success"] and data["search"] == "continuous"
    assert all(
        g["pressures_kpa"][1] == g["pressures_kpa"][2] for g in data["gait"] if g["phase"] == "inflate"
    )
    assert (tmp_path / "gait.csv").exists()
