"""The default crawl uses the identified feet (issue 29 step 9, record 070): `softcrawl crawl` and
`simulate_crawl` take mu_smooth and mu_grooved from the committed identification, the file's
verdict is carried into the source line, and a missing identification is a one-line exit 2."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

import pytest

from softcrawl.studies.commands.crawl import friction_settings
from softcrawl.studies.foot import identify


def _write(path, mu_smooth, residual=0.0):
    """An identification file: the smooth face identified at `mu_smooth` (None: outside the range,
    `residual` N above the target at its lower end); the grooved face outside, above."""
    data = json.loads(identify.COMMITTED.read_text())
    data["fits"][0] |= {"mu": mu_smooth, "residual_n": residual, "in_range": mu_smooth is not None}
    path.write_text(json.dumps(data))
    return path


def test_the_committed_identification_gives_the_range_end_flagged():
    ident = identify.load(identify.COMMITTED)  # the committed file: no mu fits in 0.3-0.9 (record 070)
    friction = identify.prediction_friction(identify.COMMITTED)
    assert (friction["mu_smooth"], friction["mu_grooved"]) == (0.3, 0.3) == (ident.mu_range[0],) * 2
    assert friction["source"].count("outside the sourced range") == 2


def test_an_identified_value_is_used_as_it_is(tmp_path, monkeypatch):
    monkeypatch.setenv(identify.ENV, str(_write(tmp_path / "feet.json", 0.42)))
    friction = identify.prediction_friction()
    assert friction["mu_smooth"] == 0.42 and "mu_smooth = 0.42: identified" in friction["source"]
    assert friction["mu_grooved"] == 0.3  # still the lower end: its residual in the file is > 0


def test_a_target_above_the_range_takes_its_upper_end(tmp_path, monkeypatch):
    monkeypatch.setenv(identify.ENV, str(_write(tmp_path / "feet.json", None, residual=-3.0)))
    assert identify.prediction_friction()["mu_smooth"] == 0.9


def test_the_command_line_takes_what_is_given_and_the_identification_for_the_rest(tmp_path, monkeypatch):
    monkeypatch.setenv(identify.ENV, str(_write(tmp_path / "feet.json", 0.42)))
    both = friction_settings(argparse.Namespace(mu_smooth=0.6, mu_grooved=0.7))
    assert (both["mu_smooth"], both["mu_grooved"]) == (0.6, 0.7) and "given by the caller" in both["source"]
    one = friction_settings(argparse.Namespace(mu_smooth=None, mu_grooved=0.7))
    assert (one["mu_smooth"], one["mu_grooved"]) == (0.42, 0.7)
    assert "mu_grooved given: 0.7" in one["source"] and "identified" in one["source"]


def test_a_missing_identification_is_one_line_and_exit_2(tmp_path):
    env = {"SOFTCRAWL_FEET": str(tmp_path / "none.json"), "PATH": ""}
    done = subprocess.run(
        [sys.executable, "-m", "softcrawl", "crawl", "--quick", "--out", str(tmp_path / "out")],
        capture_output=True, text=True, env=env, timeout=120,
    )  # fmt: skip
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "mu-smooth" in done.stderr and "identify-feet" in done.stderr
    assert not (tmp_path / "out").exists()  # refused before any work
    with pytest.raises(identify.IdentificationMissing, match="mu_smooth"):
        identify.prediction_friction(tmp_path / "none.json")


@pytest.mark.parametrize("study", ["feet", "optimise-feet", "predict-crawl"])
def test_a_study_without_its_identification_is_the_readers_error_naming_out(study, tmp_path, capfd):
    """The studies read OUT/identify/feet/feet.json through `identify.study_friction`: a feet.json
    that is no file (here a folder) is the reader's `IdentificationMissing`, named "out", with the
    command that writes it. (The studies' own exists() checks let the folder through to the reader,
    whose line named mu_smooth and told to set SOFTCRAWL_FEET, which they do not read.)"""
    from softcrawl.studies.cli import main

    (tmp_path / "identify" / "feet" / "feet.json").mkdir(parents=True)
    assert main(["study", study, "--out", str(tmp_path)]) == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error: out: " in err[0] and f"identify-feet --out {tmp_path}" in err[0], err
    assert "SOFTCRAWL_FEET" not in err[0]
    with pytest.raises(identify.IdentificationMissing) as info:
        identify.study_friction(tmp_path)
    assert info.value.parameter == "out"


def test_the_reduced_crawl_takes_the_slip_viscosity_given(tmp_path, monkeypatch):
    """--slip-viscosity reaches the reduced crawl's setup (0, Coulomb, unless given; record 088)."""
    from softcrawl.studies.cli import main
    from softcrawl.studies.crawl import files

    seen = []

    def recorded(setup, schedule, out, **kwargs):
        seen.append(setup)
        raise SystemExit(0)  # stop before any solve

    monkeypatch.setattr(files, "run_and_write", recorded)
    for extra, eta in (([], 0.0), (["--slip-viscosity", "2.5e-4"], 2.5e-4)):
        with pytest.raises(SystemExit):
            main(["crawl", "--quick", *extra, "--out", str(tmp_path / str(eta))])
        assert seen[-1].slip_viscosity == eta
