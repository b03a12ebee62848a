"""`softcrawl crawl --body fe` hands the runner what the command line says.

The runner (`studies.crawl_fe.files.run_and_write`, exercised end to end by
test_body_run_slow.py) is replaced by a recorder, so that this checks the wiring only: the pipe,
bend radius, mesh, cycles, steps, friction (given, or the committed identification's) and the
schedule (a preset, or a gait plan's cycles), and the exit code from the run's convergence.
"""

import pytest

from softcrawl.studies.cli import main
from softcrawl.studies.crawl_fe import files


@pytest.fixture
def recorded(monkeypatch):
    calls = []

    def run_and_write(setup, schedule, out, **kwargs):
        calls.append((setup, schedule, out, kwargs))
        return calls[-1][3].get("pipe") != "vertical-down", {"text": "recorded"}

    monkeypatch.setattr(files, "run_and_write", run_and_write)
    return calls


def test_the_options_reach_the_runner(recorded, tmp_path):
    argv = ["crawl", "--body", "fe", "--quick", "--pipe", "elbow", "--bend-radius", "60", "--cycles", "3"]
    argv += ["--mu-smooth", "0.4", "--mu-grooved", "0.2", "--steps", "6", "--out", str(tmp_path / "a")]
    assert main(argv) == 0
    setup, schedule, out, kw = recorded[-1]
    assert (setup.cycles, setup.steps, setup.mu_smooth, setup.mu_grooved) == (3, 6, 0.4, 0.2)
    assert (setup.pipe_diameter, setup.insert_steps) == (70.0, 4)
    assert (kw["pipe"], kw["bend_radius"], kw["mesh"]) == ("elbow", 60.0, "quick")
    assert schedule.name == "inflate" and out == tmp_path / "a"
    assert "--mu-smooth and --mu-grooved" in kw["friction_source"] and kw["max_wall_s"] is None
    assert setup.slip_viscosity == 0.0  # Coulomb unless asked (docs/decisions/088-viscous-slip.md)
    assert main(argv[:-1] + [str(tmp_path / "d"), "--time-limit", "1.5", "--slip-viscosity", "7.5e-4"]) == 0
    assert recorded[-1][3]["max_wall_s"] == 90.0 and recorded[-1][0].slip_viscosity == 7.5e-4
    assert kw["inertia"] is False  # quasi-static unless asked (docs/decisions/089-inertia.md)
    assert main(argv[:-1] + [str(tmp_path / "e"), "--inertia"]) == 0 and recorded[-1][3]["inertia"] is True
    assert recorded[-1][3]["store"].checkpoints.options["inertia"] is True  # in the checkpoints' key


def test_a_bellows_gets_its_corrugations_and_they_are_refused_for_other_pipes(recorded, tmp_path, capsys):
    argv = ["crawl", "--body", "fe", "--quick", "--pipe", "bellows", "--pipe-diameter", "75"]
    assert main(argv + ["--out", str(tmp_path / "a")]) == 0
    kw = recorded[-1][3]
    assert kw["pipe"] == "bellows" and kw["corrugation"] == (2.0, 10.0)  # the example default
    assert main(argv + ["--bellows-depth", "3", "--out", str(tmp_path / "b")]) == 0
    kw = recorded[-1][3]
    assert kw["corrugation"] == (3.0, 10.0) and kw["store"].checkpoints.options["corrugation"] == [3.0, 10.0]
    calls = len(recorded)
    refused = [
        (["crawl", "--body", "fe", "--bellows-pitch", "12"], "bellows-pitch"),  # a straight pipe
        (["crawl", "--bellows-depth", "3"], "bellows-depth"),  # the reduced crawl
        (argv + ["--bellows-depth", "0"], "bellows-depth"),  # out of range
    ]
    for bad, option in refused:
        try:
            code = main(bad + ["--out", str(tmp_path / "c")])
        except SystemExit as exit:  # argparse's range check
            code = exit.code
        assert code == 2 and option in capsys.readouterr().err
    assert len(recorded) == calls and not (tmp_path / "c").exists()


def test_the_default_mesh_without_quick_and_a_failed_run_exits_1(recorded, tmp_path):
    assert main(["crawl", "--body", "fe", "--pipe", "vertical-down", "--out", str(tmp_path / "b")]) == 1
    setup, _, _, kw = recorded[-1]
    assert kw["mesh"] == "default" and setup.insert_steps == 8
    assert "identification" in kw["friction_source"] or "feet.json" in kw["friction_source"]


def test_a_gait_plan_replaces_the_preset(recorded, tmp_path):
    plan = tmp_path / "gait.csv"
    plan.write_text("cycle,phase,P1_kpa,P2_kpa,P3_kpa\n1,inflate,100,0,0\n1,deflate,0,0,0\n")
    argv = [
        "crawl",
        "--body",
        "fe",
        "--quick",
        "--gait-plan",
        str(plan),
        "--cycle-time",
        "3",
        "--out",
        str(tmp_path / "c"),
    ]
    assert main(argv) == 0
    _, schedule, _, _ = recorded[-1]
    assert len(schedule) == 1 and schedule[0].cycle_s == 3.0
    assert schedule[0].pressures_kpa.tolist() == [[0, 0, 0], [100, 0, 0], [0, 0, 0]]


def test_a_wedge_of_the_body_reaches_the_setup_and_the_checkpoints_key(recorded, tmp_path):
    argv = ["crawl", "--body", "fe", "--quick", "--out", str(tmp_path / "w")]
    assert main(argv) == 0 and recorded[-1][0].copies == 1  # the whole body unless asked
    assert main(argv[:-1] + [str(tmp_path / "v"), "--pipe", "vertical-up", "--wedge", "3"]) == 0
    setup, _, _, kw = recorded[-1]
    assert setup.copies == 3 and kw["store"].checkpoints.options["copies"] == 3
