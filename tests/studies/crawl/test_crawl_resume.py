"""The crawl's checkpoints without a solve (`studies.crawl.resume`, `softcrawl crawl --resume`, the
crawl study's points): a state reads back bit for bit into a fresh model and recorder; a changed
option or version is refused in one line naming it (exit 2) before any meshing; an unfinished run
is not overwritten without --resume; --resume without a checkpoint starts from the beginning and
says so; a point of the study resumes from its checkpoint and, stopped by the memory watchdog,
names its last state."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem.checkpoint import CheckpointError
from softcrawl.fem.contact_stages import Cursor
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.studies.cli import main
from softcrawl.studies.crawl import files
from softcrawl.studies.crawl.mesh import QUICK_SECTORS
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.resume import CrawlStore, crawl_options
from softcrawl.studies.crawl.schedule import preset
from softcrawl.studies.foot.identify import prediction_friction

#: The setup of `softcrawl crawl --quick --cycles 1` (studies/commands/crawl.py).
_MU = {k: prediction_friction()[k] for k in ("mu_smooth", "mu_grooved")}  # the command's default friction
QUICK = CrawlSetup(insert_steps=4, steps=4, cycles=1, sectors=QUICK_SECTORS, thickness_layers=None, **_MU)


class _Link:
    def __init__(self, k=1.0, f=0.0, rest=0.0):
        self.stiffness, self.preload, self.rest = k, f, rest

    def set_load(self, k, f, rest=None):
        self.stiffness, self.preload = k, f
        self.rest = self.rest if rest is None else rest


def _fakes(seed: int):
    """A model of two contact terms and three links, and a recorder, in a state of `seed`."""
    rng = np.random.default_rng(seed)
    contacts = [
        SimpleNamespace(multiplier=rng.random(5), stick=rng.random((5, 3)), mu=0.1 * seed,
                        surface=CylinderWall(30.0 + seed), _solved=("x", "stick"))
        for _ in range(2)
    ]  # fmt: skip
    terms = {n: _Link(*rng.random(3)) for n in ("actuator", "ground_rear", "ground_front")}
    cm = SimpleNamespace(model=SimpleNamespace(contacts=contacts), terms=terms)
    rows = [{"index": i, "stage": "insert", "cycle": 0, "time_s": 0.0, "centre_u_mm": float(rng.random())}
            for i in range(seed)]  # fmt: skip
    rows += [{"index": seed, "stage": "cycle0-seg0", "cycle": 1, "time_s": 0.5, "centre_u_mm": float("nan")}]
    recorder = SimpleNamespace(states=rows, cycles=[], start={"rear": 0.1, "front": -0.2}, _cycle_from=seed)
    recorder._cycle_start = {"rear": 0.3, "front": 0.4}
    return cm, recorder


def _cursor(seed: int) -> Cursor:
    rng = np.random.default_rng(seed)
    return Cursor(
        2, 0.375, 0.125, rng.random(7), 0.25, rng.random(7), np.zeros(1), 0.0, np.zeros(1), 0.0, 9, 1.5, 2.5
    )


def _store(folder, setup=QUICK, **extra):
    return CrawlStore(folder, crawl_options(setup, preset("inflate"), "rubber-70a") | extra)


def test_a_state_reads_back_bit_for_bit_into_a_fresh_model_and_recorder(tmp_path):
    from softcrawl.studies.crawl.resume import Totals

    cm, recorder = _fakes(3)
    store = _store(tmp_path)
    store.save(cm, recorder, 3, "cycle0", _cursor(3), Totals(12, 1.0, 2.0, 30.0))
    fresh_cm, fresh_recorder = _fakes(4)
    resumed = _store(tmp_path).load()
    assert (resumed.phase, resumed.phase_name, resumed.totals) == (3, "cycle0", Totals(12, 1.0, 2.0, 30.0))
    for name in ("x", "prev_x"):
        assert np.array_equal(getattr(resumed.cursor, name), getattr(_cursor(3), name))
    assert (resumed.cursor.stage, resumed.cursor.t, resumed.cursor.h, resumed.cursor.prev_t) == (
        2,
        0.375,
        0.125,
        0.25,
    )
    store.restore(fresh_cm, fresh_recorder, resumed)
    for a, b in zip(fresh_cm.model.contacts, cm.model.contacts):
        assert np.array_equal(a.multiplier, b.multiplier) and np.array_equal(a.stick, b.stick)
        assert a.mu == b.mu and a.surface == b.surface and a._solved is None
    for name, link in cm.terms.items():
        assert vars(fresh_cm.terms[name]) == vars(link)
    assert fresh_recorder.states[:-1] == recorder.states[:-1]  # and the NaN of the last row survives:
    assert np.isnan(fresh_recorder.states[-1]["centre_u_mm"])
    assert (fresh_recorder.start, fresh_recorder._cycle_from, fresh_recorder._cycle_start) == (
        recorder.start, 3, recorder._cycle_start)  # fmt: skip
    assert resumed.describe() == "state 4 (cycle0, stage 'cycle0-seg0' at t = 0.5 s)"
    summary = store.latest_summary()
    assert (
        summary["stage"] == "cycle0-seg0"
        and summary["states"] == 4
        and summary["checkpoint"].endswith(".npz")
    )
    store.clear()
    assert not tmp_path.exists() and store.latest_summary() == {}


def test_another_option_is_refused_naming_it(tmp_path):
    cm, recorder = _fakes(1)
    _store(tmp_path).save(cm, recorder, 0, "insert", _cursor(1), _totals())
    with pytest.raises(CheckpointError, match="written with cycles = 1, this run has 2"):
        _store(tmp_path, dataclasses.replace(QUICK, cycles=2)).load()


def _totals():
    from softcrawl.studies.crawl.resume import Totals

    return Totals()


def _crawl(out, *extra) -> list[str]:
    return ["crawl", "--quick", "--cycles", "1", "--out", str(out), *extra]


def _written_by(out, version=None, **options):
    """A checkpoint in OUT/checkpoints as `softcrawl crawl --quick --cycles 1` writes it, but with
    `options` changed (or another softcrawl `version`)."""
    cm, recorder = _fakes(1)
    store = _store(out / "checkpoints", dataclasses.replace(QUICK, **options))
    if version is not None:
        from softcrawl.fem.checkpoint import Checkpoints

        store.checkpoints = Checkpoints(store.folder, store.checkpoints.options, version=version)
    store.save(cm, recorder, 0, "insert", _cursor(1), _totals())


@pytest.mark.parametrize(
    "changed, line",
    [
        ({"cycles": 3}, "written with cycles = 3, this run has 1"),
        ({"mu_smooth": 0.5}, "written with mu_smooth = 0.5, this run has 0.3"),
        ({"version": "0.0.1"}, "written by softcrawl 0.0.1, this is"),
    ],
)
def test_the_command_refuses_a_checkpoint_of_other_options_in_one_line(
    tmp_path, capsys, monkeypatch, changed, line
):
    monkeypatch.setattr(files, "run_and_write", _no_solve)  # refused before: never reached
    _written_by(tmp_path / "out", **changed)
    assert main(_crawl(tmp_path / "out", "--resume")) == 2
    err = capsys.readouterr().err.splitlines()
    assert (
        len(err) == 1
        and err[0].startswith("softcrawl crawl: error: resume: the checkpoint in ")
        and line in err[0]
    )


def test_an_unfinished_run_is_not_overwritten_without_resume(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(files, "run_and_write", _no_solve)
    _written_by(tmp_path / "out")
    assert main(_crawl(tmp_path / "out")) == 2
    (err,) = capsys.readouterr().err.splitlines()
    assert "holds the checkpoint of an unfinished run; add --resume to continue it" in err
    assert len(list((tmp_path / "out" / "checkpoints").glob("state-*.npz"))) == 1  # kept


def _no_solve(*args, **kwargs):
    raise AssertionError("the crawl was run")


def test_resume_without_a_checkpoint_starts_from_the_beginning_and_says_so(tmp_path, capsys, monkeypatch):
    seen = {}

    def fake_run(
        setup,
        schedule,
        folder,
        *,
        quick,
        progress,
        store,
        resumed,
        precision=32,
        insertion_cache,
        friction_source="",
    ):
        seen.update(setup=setup, store=store, resumed=resumed, insertion_cache=insertion_cache)
        return SimpleNamespace(converged=True), {"text": "done"}

    monkeypatch.setattr(files, "run_and_write", fake_run)
    assert main(_crawl(tmp_path / "out", "--resume")) == 0
    out = capsys.readouterr().out
    assert f"crawl: no checkpoint in {tmp_path / 'out' / 'checkpoints'}; starting from the beginning" in out
    assert seen["resumed"] is None and seen["setup"] == QUICK
    assert seen["insertion_cache"] is False  # softcrawl crawl computes its insertion unless asked
    assert seen["store"].checkpoints.options == _store(tmp_path).checkpoints.options  # the key of the run


def test_a_study_point_resumes_from_its_checkpoint_and_a_memory_stop_names_its_last_state(
    tmp_path, monkeypatch
):
    from softcrawl.studies.crawl import crawl_study
    from softcrawl.studies.sweeps.memory import OutOfMemory

    calls = []

    def stopped(setup, schedule, folder, *, quick, vtu, store, resumed, insertion_cache):
        assert insertion_cache is True  # a study point starts from its diameter's cached insertion
        calls.append(resumed)
        cm, recorder = _fakes(2)
        store.save(cm, recorder, 3, "cycle0", _cursor(2), _totals())
        raise OutOfMemory(1.2, 1.0)

    monkeypatch.setattr(crawl_study, "run_and_write", stopped)  # the study's own reference
    settings = {"quick": True, "out_dir": str(tmp_path), "cycles": 1}
    params = {"pipe_diameter": 70.0, "mu": 0.5}
    for _ in range(2):
        with pytest.raises(OutOfMemory) as stop:
            crawl_study.evaluate_crawl(params, {}, settings)
    assert calls[0] is None and calls[1].describe() == "state 3 (cycle0, stage 'cycle0-seg0' at t = 0.5 s)"
    last = stop.value.last_state
    assert (last["stage"], last["time_s"], last["states"]) == ("cycle0-seg0", 0.5, 3)
    assert last["checkpoint"].startswith(str(tmp_path / "points" / "D70-mu0.5" / "checkpoints"))
