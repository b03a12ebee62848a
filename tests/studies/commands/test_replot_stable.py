"""`softcrawl replot` is byte-stable: the same tables give the same PNG bytes (matplotlib's
metadata pinned, `studies.plots.style.METADATA`), and the committed figures are what replot draws,
so `softcrawl replot results` followed by `git status` shows no change."""

import hashlib
import shutil
from pathlib import Path

from softcrawl.studies.cli import main

RESULTS = Path(__file__).resolve().parents[3] / "results"
#: A 2D study figure (fiber-turns), a 3D one (the workspace) and the crawl study's.
FOLDERS = ("fiber-turns/ecoflex-00-50@mu=0.0638", "robot-workspace", "crawl/rubber-70a-quick")


def _digests(root: Path) -> dict[str, str]:
    return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest() for p in root.rglob("*.png")}


def test_replot_twice_gives_the_same_bytes_as_the_committed_figures(tmp_path, capsys):
    copy = tmp_path / "results"
    for folder in FOLDERS:
        shutil.copytree(RESULTS / folder, copy / folder)
    committed = _digests(copy)
    assert len(committed) >= 4
    assert main(["replot", str(copy)]) == 0
    first = _digests(copy)
    assert main(["replot", str(copy)]) == 0
    assert _digests(copy) == first  # the same data, the same bytes
    assert first == committed  # the committed figures are replot's (regenerate them if not)


def test_saved_pngs_carry_no_software_version(tmp_path):
    from softcrawl.studies.plots.style import pyplot, save

    plt = pyplot()
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    data = save(fig, tmp_path / "a.png").read_bytes()
    assert b"matplotlib version" not in data and b"Software" not in data


def test_replot_takes_a_study_folder_or_a_run_folder_under_results(tmp_path, capsys):
    """`softcrawl replot results/crawl` and `results/crawl/rubber-70a-quick` redraw the runs under
    them, and only those (they were "holds no study results", exit 2); the root still redraws all."""
    copy = tmp_path / "results"
    for folder in FOLDERS:
        shutil.copytree(RESULTS / folder, copy / folder)
    committed = _digests(copy)
    png = copy / "crawl" / "rubber-70a-quick" / "crawl-study.png"
    for sub in ("crawl", "crawl/rubber-70a-quick"):
        png.unlink()
        assert main(["replot", str(copy / sub)]) == 0
        assert "redrew 1 figures" in capsys.readouterr().out
        assert _digests(copy) == committed
    (copy / "fiber-turns" / "empty").mkdir()
    assert main(["replot", str(copy / "fiber-turns" / "empty")]) == 2
