"""CLI user errors: one line naming the parameter, exit code 2 (no meshing happens)."""

import pytest

from softcrawl.studies.cli import main


@pytest.mark.parametrize(
    "argv, parameter",
    [
        (["mesh", "epsa", "--chamber-radius", "10"], "chamber_radius"),
        (["mesh", "epsa", "--fiber-turns", "-3"], "fiber_turns"),
        (["mesh", "foot", "--groove-height", "5"], "groove_height"),
        (["mesh", "ring", "--outer-radius", "10"], "outer_radius"),
        (["mesh", "robot", "--d", "9"], "d"),
        (["mesh", "robot", "--epsa.chamber-radius", "9"], "epsa.chamber_radius"),
        (["mesh", "robot", "--foot.angle", "190"], "foot.angle"),
        (["mesh", "epsa", "--mesh-size", "-1"], "mesh-size"),
        (["mesh", "foot", "--mesher", "revolved", "--mesh-size", "3"], "mesh-size"),
    ],
)
def test_invalid_parameter(argv, parameter, tmp_path, capsys):
    assert main(argv + ["--out", str(tmp_path / "o"), "--no-cache"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and parameter in err


@pytest.mark.parametrize(
    "argv, word",
    [
        (["mesh", "epsa", "--radius", "3"], "--radius"),
        (["mesh", "epsa", "--length", "abc"], "--length"),
        (["mesh", "tube"], "tube"),
    ],
)
def test_unknown_or_malformed_parameter(argv, word, tmp_path, capsys):
    assert main(argv + ["--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err


def test_the_revolved_foot_mesh_from_the_cli(tmp_path):
    import json

    assert main(["mesh", "foot", "--mesher", "revolved", "--no-png", "--out", str(tmp_path / "o")]) == 0
    summary = json.loads((tmp_path / "o" / "mesh.json").read_text())
    assert summary["n_tets"] == 15552  # the foot study's mesh (48 sectors, 3 cells through the skirt)
    assert (tmp_path / "o" / "mesh.vtu").exists()
