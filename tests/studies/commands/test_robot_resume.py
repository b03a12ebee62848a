"""`softcrawl robot --resume` refusals, before any meshing: another option's checkpoint (one line
naming it, exit 2), an unfinished run without --resume, --resume without --out."""

import numpy as np
import pytest

from softcrawl.fem.checkpoint import Checkpoints
from softcrawl.studies.cli import main
from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL

ARGV = ["robot", "--pressures", "0,40,60", "--mesh", "quick"]
OPTIONS = {"pressures": "0,40,60", "first": None, "steps": 5, "mesh": "quick", "material": DEFAULT_MATERIAL,
           "rings": None, "d": None, "gravity": False}  # fmt: skip


def _written(out, **changed):
    Checkpoints(out / "checkpoints", OPTIONS | changed).save(1, {"x": np.zeros(3)}, {"index": 1})


@pytest.mark.parametrize(
    "extra, changed, line",
    [
        (["--resume"], {"steps": 3}, "was written with steps = 3, this run has 5"),
        (["--resume", "--gravity"], {}, "was written with gravity = False, this run has True"),
        ([], {}, "holds the checkpoint of an unfinished run; add --resume to continue it"),
    ],
)
def test_refused_in_one_line_before_any_work(tmp_path, capsys, monkeypatch, extra, changed, line):
    from softcrawl.studies.robot_fe import model

    monkeypatch.setattr(model, "build_robot_model", lambda *a, **k: pytest.fail("meshed"))
    _written(tmp_path, **changed)
    assert main([*ARGV, "--out", str(tmp_path), *extra]) == 2
    (err,) = capsys.readouterr().err.splitlines()
    assert err.startswith("softcrawl robot: error: resume: ") and line in err


def test_resume_needs_an_output_folder(capsys):
    assert main([*ARGV, "--resume"]) == 2
    assert (
        capsys.readouterr().err
        == "softcrawl robot: error: resume: needs --out (the checkpoints are in OUT/checkpoints)\n"
    )
