"""The public API (`import softcrawl as sc`, softcrawl/__init__.py): light to import, every public
name resolves, the table of the module docstring lists exactly the public names, and the simulation
functions take pressures in kPa."""

import importlib.util
import json
import subprocess
import sys

import pytest

import softcrawl as sc

#: Modules `import softcrawl` must not load: numpy and the solver stack, and every subpackage.
HEAVY = (
    "numpy",
    "scipy",
    "skfem",
    "pyvista",
    "optuna",
    "matplotlib",
    "softcrawl.fem",
    "softcrawl.geometry",
    "softcrawl.materials",
    "softcrawl.analytic",
    "softcrawl.studies",
)
#: Public names that another branch provides (the study registry); skipped while it is missing.
REGISTRY = {"run_study", "study_names"}


def _registry_missing() -> bool:
    return importlib.util.find_spec("softcrawl.studies.registry") is None


def test_import_softcrawl_loads_nothing_heavy():
    code = "import json, sys, softcrawl; print(json.dumps(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = set(json.loads(out.stdout))
    assert not [m for m in HEAVY if m in loaded]
    assert not [m for m in loaded if m.startswith("softcrawl.")]


@pytest.mark.parametrize("name", sc.__all__)
def test_every_public_name_resolves(name):
    if name in REGISTRY and _registry_missing():
        pytest.skip("softcrawl.studies.registry is not in this tree yet (written on another branch)")
    assert getattr(sc, name) is not None


def test_study_names_delegate_to_the_registry():
    if _registry_missing():
        pytest.skip("softcrawl.studies.registry is not in this tree yet (written on another branch)")
    from softcrawl.studies import registry

    assert sc.run_study is registry.run_study
    assert sc.study_names is registry.names


def test_dir_lists_the_public_names_and_unknown_names_are_attribute_errors():
    assert set(sc.__all__) <= set(dir(sc))
    with pytest.raises(AttributeError):
        sc.no_such_name  # noqa: B018
    from softcrawl import jsonio  # a core submodule is still imported as a submodule

    assert jsonio.__name__ == "softcrawl.jsonio"


def test_the_docstring_table_lists_every_public_name():
    lines = sc.__doc__.splitlines()
    rules = [i for i, line in enumerate(lines) if line.startswith("=====")]
    rows = [line.split()[0] for line in lines[rules[1] + 1 : rules[2]]]
    assert sorted(rows) == sorted(n for n in sc.__all__ if n != "__version__")


def test_results_are_the_feature_folders_frozen_classes():
    import dataclasses

    for name in ("ActuatorCurve", "RobotRun", "FootResult", "CrawlResult"):
        cls = getattr(sc, name)
        assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen, name


@pytest.mark.parametrize(
    ("function", "kwargs", "parameter"),
    [
        ("simulate_robot", {"pressures_kpa": (10.0, 20.0)}, "pressures_kpa"),
        ("simulate_robot", {"pressures_kpa": (10.0, 0.0, 0.0), "steps": 0}, "steps"),
        ("simulate_foot", {"pipe_diameter": 40.0}, "pipe_diameter"),
        ("simulate_foot", {"mu_smooth": -1.0}, "mu_smooth"),
        ("simulate_crawl", {"pipe_diameter": 90.0}, "pipe_diameter"),
        ("simulate_crawl", {"feet": "sideways"}, "feet"),
        ("simulate_crawl", {"gait": "hop"}, "gait"),
        ("simulate_epsa", {"design": sc.EPSADesign(), "pressures_kpa": (-5.0,)}, "pressures"),
    ],
)
def test_bad_input_is_an_input_error_before_any_mesh(function, kwargs, parameter):
    with pytest.raises(sc.InputError) as info:
        getattr(sc, function)(**kwargs)
    assert info.value.parameter == parameter


def test_the_robot_takes_kpa():
    """Quick mesh, 20 kPa in chamber 1 in two steps (~15 s): the states report the kPa given, and
    the robot bends away from the pressurised actuator."""
    run = sc.simulate_robot(sc.RobotDesign(), (20.0, 0.0, 0.0), steps=2, quick=True)
    assert run.converged, run.message
    assert [s.pressures_kpa for s in run.states] == [(10.0, 0.0, 0.0), (20.0, 0.0, 0.0)]
    assert 0.0 < run.states[0].theta_deg < run.states[1].theta_deg


@pytest.mark.slow
def test_the_quick_foot():
    """The quick foot in the 70 mm pipe (~65 s): inserted, dragged both ways, anchoring."""
    r = sc.simulate_foot(sc.FootDesign(), 70.0, quick=True)
    assert r.converged, r.message
    assert r.normal_force > 0 and r.ratio > 1.0
