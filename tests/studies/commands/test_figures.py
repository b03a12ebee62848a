"""Each command that draws writes its PNG, and the PNG is not blank (a figure with content: many
colours and a good share of non-background pixels)."""

import shutil
from pathlib import Path

import numpy as np
import pytest

from softcrawl.studies.cli import main

RESULTS = Path(__file__).resolve().parents[3] / "results"


def assert_not_blank(path: Path, min_fraction: float = 0.03) -> None:
    from PIL import Image

    assert path.exists(), path
    image = np.asarray(Image.open(path).convert("RGB")).astype(int)
    background = np.median(image.reshape(-1, 3), axis=0)
    drawn = np.abs(image - background).sum(axis=2) > 30
    assert drawn.mean() > min_fraction, f"{path.name}: only {drawn.mean():.1%} drawn"
    assert len(np.unique(image.reshape(-1, 3), axis=0)) > 20, f"{path.name}: too few colours"


def test_epsa_writes_its_figure_and_renders(tmp_path):
    out = tmp_path / "epsa"
    argv = ["epsa", "--length", "40", "--fiber-turns", "8", "--quick", "--pressures", "0:10:5"]
    assert main([*argv, "--side-load", "1e-3", "--render", "--no-vtu", "--out", str(out)]) == 0
    names = (
        "epsa.png",
        "render-0kPa.png",
        "render-0kPa-side-load.png",
        "render-5kPa.png",
        "render-10kPa.png",
    )
    for name in names:
        assert_not_blank(out / name)


def test_model_workspace_and_plan_write_their_figures(tmp_path):
    assert main(["model", "workspace", "--out", str(tmp_path / "ws")]) == 0
    assert_not_blank(tmp_path / "ws" / "workspace.png")
    # exit code 1: this elbow is not passed (a result, not an error); the figure shows why
    code = main(["model", "plan", "--pipe", "elbow", "--bend-radius", "60", "--out", str(tmp_path / "p")])
    assert code in (0, 1)
    assert_not_blank(tmp_path / "p" / "plan.png")


def test_material_fit_writes_its_figure(tmp_path):
    assert main(["material", "fit", "--out", str(tmp_path / "fit")]) == 0
    assert_not_blank(tmp_path / "fit" / "fit.png")


def test_replot_redraws_the_committed_study_figures(tmp_path, capsys):
    copy = tmp_path / "results"
    for study in ("chamber-radius", "fiber-turns", "identify", "optimise-actuator"):
        shutil.copytree(RESULTS / study, copy / study)
    committed = sorted(copy.rglob("*.png"))
    for png in committed:
        png.unlink()
    assert main(["replot", str(copy)]) == 0
    assert f"redrew {len(committed)} figures" in capsys.readouterr().out
    for png in committed:  # every committed figure comes back from its tables alone
        assert_not_blank(png)


def test_mesh_render_of_a_part_is_a_cut_away_with_a_legend(tmp_path):
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.geometry.swept import mesh_epsa_swept
    from softcrawl.studies.plots.mesh_render import render_png

    mesh = mesh_epsa_swept(EPSADesign(fiber_turns=4, length=40.0), n_around=12, n_radial=1, axial_size=10.0)
    assert render_png(mesh, tmp_path / "mesh.png", title="test") == "pyvista"
    assert_not_blank(tmp_path / "mesh.png")


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["epsa", "foot", "ring", "robot"])
def test_mesh_command_writes_its_render(kind, tmp_path):
    out = tmp_path / kind
    assert main(["mesh", kind, "--cache-dir", str(tmp_path / "cache"), "--out", str(out)]) == 0
    assert_not_blank(out / "mesh.png")
