"""The study registry: a study declared in one place runs, replots and reports through the
commands, which name no study; stored evaluator names resolve, old import paths migrate."""

import csv
import json
from pathlib import Path

import pytest

from softcrawl.studies import registry
from softcrawl.studies.cli import main
from softcrawl.studies.declaration import Study, StudyRequest
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.sweeps.spec import StudyError, load_callable

RESULTS = Path(__file__).resolve().parents[2] / "results"
HERE = "tests.studies.test_registry"


def toy_run(request: StudyRequest) -> StudyOutcome:
    """A study with no FE: y = x^2 at three points, its table, spec.json and figure."""
    folder = Path(request.out) / "toy" / request.material
    folder.mkdir(parents=True, exist_ok=True)
    rows = [{"x": x, "y": x * x} for x in (1.0, 2.0, 3.0)]
    with open(folder / "summary.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=["x", "y"])
        writer.writeheader()
        writer.writerows(rows)
    (folder / "spec.json").write_text(json.dumps({"name": "toy", "settings": {"material": request.material}}))
    return StudyOutcome(("toy: 3 points",), (folder / "summary.csv", *toy_replot(folder)))


def toy_replot(folder: Path) -> list[Path]:
    import matplotlib.pyplot as plt

    with open(folder / "summary.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    fig, ax = plt.subplots()
    ax.plot([float(r["x"]) for r in rows], [float(r["y"]) for r in rows])
    fig.savefig(folder / "toy.png")
    plt.close(fig)
    return [folder / "toy.png"]


TOY = Study(
    name="toy",
    summary="a toy study for the registry's test",
    run=f"{HERE}:toy_run",
    figure="toy.png",
    tables=("summary.csv",),
    replot=f"{HERE}:toy_replot",
)


@pytest.fixture
def toy():
    registry.register(TOY)
    yield TOY
    registry.unregister("toy")


@pytest.mark.timeout(300)
def test_a_toy_study_runs_replots_and_reports_with_no_other_file_touched(toy, tmp_path, capsys):
    assert main(["study", "toy", "--out", str(tmp_path)]) == 0
    png = tmp_path / "toy" / "ecoflex-00-50" / "toy.png"
    assert png.stat().st_size > 1000
    assert "toy: 3 points" in capsys.readouterr().out
    png.unlink()
    assert main(["replot", str(tmp_path)]) == 0
    assert png.exists() and "redrew 1 figures" in capsys.readouterr().out
    assert main(["report", "--results", str(tmp_path), "--out", str(tmp_path / "review")]) == 0
    html = (tmp_path / "review" / "index.html").read_text()
    assert "softcrawl study toy" in html  # the toy's block, with the command that made it
    assert "toy/ecoflex-00-50/toy.png" in html


def test_the_study_command_lists_every_registered_study(toy, capsys):
    assert main(["study", "--help"]) == 0
    text = capsys.readouterr().out
    for name in registry.names():
        assert name in text
    assert "a toy study for the registry's test" in text


def test_every_declaration_resolves_and_names_its_files():
    from softcrawl.studies.declaration import resolve

    for study in registry.studies():
        for ref in (study.run, study.replot, study.report, study.check, study.table1):
            if ref is not None:
                assert callable(resolve(ref)), f"{study.name}: {ref}"
        for name, ref in study.evaluators.items():
            assert callable(resolve(ref)), f"{study.name}: evaluator {name}"
        assert study.replot is None or study.figure, f"{study.name} redraws a figure it does not name"


def test_replot_covers_every_study_with_a_figure_in_the_committed_results():
    figures = {s.name for s in registry.studies() if s.replot is not None}
    missing = {s.name for s in registry.studies() if s.figure and s.replot is None}
    assert not missing
    with_runs = {s.name for s in registry.studies() if s.replot and s.results_folders(RESULTS)}
    assert with_runs == figures  # every study that draws a figure has committed runs to redraw


def test_every_committed_run_holds_the_tables_and_figure_its_study_declares():
    for study in registry.studies():
        for folder in study.results_folders(RESULTS):
            named = (*study.tables, *([study.figure] if study.figure else []))
            missing = [name for name in named if not (folder / name).exists()]
            assert not missing, f"{study.name}: {folder} lacks {missing}"


def test_a_declared_name_cannot_be_replaced_and_an_unknown_one_is_an_input_error():
    with pytest.raises(ValueError, match="already declared"):
        registry.register(Study(name="crawl", summary="x", run="m:f"))
    with pytest.raises(registry.RegistryError) as err:
        registry.get("nope")
    assert err.value.parameter == "name"


def test_committed_specs_store_registry_names():
    known = registry.evaluators()
    stored = {json.loads(p.read_text()).get("evaluator") for p in RESULTS.rglob("spec.json")}
    stored.discard(None)
    assert stored and stored <= set(known), stored - set(known)


@pytest.mark.parametrize("old", sorted(registry.LEGACY_EVALUATORS))
def test_an_old_import_path_resolves_to_its_evaluator(old):
    name = registry.LEGACY_EVALUATORS[old]
    assert load_callable(old) is load_callable(name)


def test_an_unknown_evaluator_name_is_one_line_naming_the_evaluator():
    with pytest.raises(StudyError) as err:
        load_callable("no-such-evaluator")
    assert err.value.parameter == "evaluator" and "\n" not in str(err.value)


@pytest.mark.parametrize(
    "module, runner",
    [
        ("softcrawl.studies.crawl.crawl_study", "run_crawl_study"),
        ("softcrawl.studies.crawl.feet_study", "run_feet_study"),
    ],
)
def test_the_crawl_and_feet_studies_pass_the_sweep_options_through(module, runner, monkeypatch):
    """Both take `StudyRequest.sweep_options()` (one home for the options a sweep passes on)."""
    import importlib

    from softcrawl.studies.declaration import StudyRequest

    calls = []
    monkeypatch.setattr(importlib.import_module(module), runner, lambda *a, **k: calls.append((a, k)))
    options = {"storage": "sqlite:///s.db", "workers": 3, "progress": False, "retry": True}
    request = StudyRequest(study="x", out="OUT", quick=True, **options)
    assert request.sweep_options() == options
    importlib.import_module(module).run_request(request)
    assert calls == [(("OUT",), {"quick": True, "wedge": 1, **request.sweep_options()})]
    importlib.import_module(module).run_request(StudyRequest(study="x", out="OUT", wedge=4, **options))
    assert calls[-1] == (("OUT",), {"quick": False, "wedge": 4, **request.sweep_options()})


def test_the_python_api_refuses_a_material_for_a_study_that_takes_none(tmp_path):
    """`run_study` refuses it as `softcrawl study` does (exit 2 there), before any work: the
    material would be silently ignored."""
    study = next(s for s in registry.studies() if s.default_material is None)
    with pytest.raises(StudyError) as err:
        registry.run_study(study.name, str(tmp_path), material="rubber-70a")
    assert err.value.parameter == "material"
    assert not any(tmp_path.iterdir())
