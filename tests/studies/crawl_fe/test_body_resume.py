"""The FE-body crawl's checkpoints (`studies.crawl_fe.resume`).

Fast: a state written and read back gives the same cursor, cycle log, setup states and model
history, bit for bit (on stand-ins for the model's contact terms and holds); the command refuses
another run's checkpoint and an unfinished run without --resume (exit 2, one line naming resume).
Slow: the small body of test_holding.py, killed within its cycle's second segment and resumed, writes
the states and strides of the uninterrupted run to the last bit, and its checkpoints go once the
run ends.
"""

import json
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem.axial_link import AxialLink, AxialLinkTerm
from softcrawl.fem.checkpoint import CheckpointError
from softcrawl.fem.contact_stages import Cursor
from softcrawl.fem.discretisation import Discretisation
from softcrawl.fem.inertia import Inertia
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.structured import box
from softcrawl.geometry.design import EPSADesign, RobotDesign
from softcrawl.studies.cli import main
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.resume import Totals
from softcrawl.studies.crawl.schedule import Schedule, preset
from softcrawl.studies.crawl_fe import files
from softcrawl.studies.crawl_fe.cycle import BodyState, CycleLog
from softcrawl.studies.crawl_fe.pipe import PipeRun, PipeState
from softcrawl.studies.crawl_fe.resume import FOLDER, BodyStore, body_options
from softcrawl.studies.sweeps.tables import read_csv
from tests.studies.crawl_fe.test_holding import SMALL
from tests.studies.sweeps.cli_runs import ROOT

RNG = np.random.default_rng(7)
GAIT = Schedule("test", np.array([0.0, 1.0, 2.0]), np.array([[0.0] * 3, [20.0] * 3, [0.0] * 3]), "test")


def _options(**changes):
    kw = {"pipe": "elbow", "bend_radius": 60.0, "mesh": "quick", "silicone": "s", "design": None} | changes
    return body_options(CrawlSetup(cycles=2), (GAIT,), **kw)


def _body():
    """Stand-ins for what the store reads of a `model.BodyModel`: contact terms and holds."""
    wall = ElbowPipe(35.0, 60.0, entry=120.0)
    contacts = [
        SimpleNamespace(
            multiplier=RNG.random(4), stick=RNG.random((3, 4)), mu=0.3, surface=wall.with_radius(r)
        )
        for r in (35.0, 35.0 + 1e-13)
    ]
    space = SimpleNamespace(boundary_nodes=lambda tag: np.arange(3))
    holds = {n: AxialLinkTerm(space, AxialLink(n, None, 0, 1e3, 0.0, name=n)) for n in ("a", "b")}
    for t in holds.values():
        t.set_load(1e-4, 0.0, float(RNG.random()))
    return SimpleNamespace(model=SimpleNamespace(contacts=contacts), holds=holds, inertia=None), wall


def _state(k):
    feet = ({"rear": 0.1, "front": 1 / 3}, {"rear": 2.0, "front": 9.0})
    forces = ({"rear": 50.0, "front": 51.0}, {"rear": -1.0, "front": 1.0})
    pressures = (20.0, 20.0, 0.1 * k)
    drift = (1e-9, -2e-9)
    return BodyState(
        1, 0.5 * k, pressures, (1.0, 2.0, 3.0), *feet, drift, 0.25, 0.125, *forces, 1e-3, 7, RNG.random(6)
    )


def test_a_state_reads_back_bit_for_bit(tmp_path):
    bm, wall = _body()
    normal = {"rear": 50.1, "front": 49.9}
    setup = tuple(
        PipeState(p, {"a": 1e-3}, normal, {"rear": RNG.random(3), "front": RNG.random(3)}, RNG.random(6))
        for p in ("insert", "friction")
    )
    run = PipeRun(True, "inserted", setup, 58, 1.5, 2.5, 100.0, 6)
    P = np.full(3, 0.1 / 3)
    cursor = Cursor(
        3, 0.375, 0.125, RNG.random(6), 0.25, RNG.random(6), np.zeros(3), 0.0, P, 1.0, 12, 0.5, 0.7
    )
    log = CycleLog(({"rear": 1 / 3, "front": 2 / 3}, 0.1), [_state(1), _state(2)], [26.3071978], [1e-7], 9,
                   [408.25], 12.5)  # fmt: skip
    store = BodyStore(tmp_path / FOLDER, _options())
    store.save_inserted(bm, run)
    store.save_cycle(bm, run, cursor, log, Totals(20, 1.0, 2.0, 30.0))
    got = BodyStore(tmp_path / FOLDER, _options()).load()
    assert got.crawl == Totals(20, 1.0, 2.0, 30.0) and got.log.segment == 9
    assert got.log.start == log.start and got.log.strides == log.strides and got.log.turns == log.turns
    assert (got.log.seconds, got.log.clock) == ([408.25], 12.5)
    for a, b in zip(got.log.states, log.states):
        assert np.array_equal(a.x, b.x) and {**vars(a), "x": 0} == {**vars(b), "x": 0}
    for name in ("stage", "t", "h", "prev_t", "f0", "f"):
        assert getattr(got.cursor, name) == getattr(cursor, name)
    for name in ("x", "prev_x", "P0", "P"):
        assert np.array_equal(getattr(got.cursor, name), getattr(cursor, name))
    assert (got.run.newton_iterations, got.run.wall_s, got.run.n_dofs) == (58, 100.0, 6)
    for a, b in zip(got.run.states, run.states):
        assert a.phase == b.phase and a.normal == b.normal and np.array_equal(a.x, b.x)
        assert all(np.array_equal(a.friction[f], b.friction[f]) for f in b.friction)
    fresh, _ = _body()
    store.restore(fresh, wall, got)
    for a, b in zip(fresh.model.contacts, bm.model.contacts):
        assert np.array_equal(a.multiplier, b.multiplier) and np.array_equal(a.stick, b.stick)
        assert a.surface.radius == b.surface.radius and type(a.surface) is ElbowPipe and a.mu == b.mu
    for name, t in bm.holds.items():
        assert (fresh.holds[name].stiffness, fresh.holds[name].rest) == (t.stiffness, t.rest)
    assert "1 cycle(s) done, stage 3 at s = 0.375" in got.describe()


def test_a_state_from_before_the_cycles_times_were_kept_reads_back_with_them_unknown(tmp_path):
    """A checkpoint of a run that began before record 092 has no cycle times: its completed cycles'
    times read back as None and the current cycle's as NaN, so no time is reported for them."""
    bm, _ = _body()
    run = PipeRun(True, "inserted", (), 58, 1.5, 2.5, 100.0, 6)
    cursor = Cursor(3, 0.375, 0.125, RNG.random(6), None, None, np.zeros(3), 0.0, np.zeros(3), 1.0, 0, 0, 0)
    log = CycleLog(({"rear": 0.0, "front": 0.0}, 0.0), [], [26.3, 0.5], [0.0, 0.0], 0)
    store = BodyStore(tmp_path / FOLDER, _options())
    path = store.save_cycle(bm, run, cursor, log, Totals())
    with np.load(path) as f:
        arrays = dict(f)
    meta = json.loads(str(arrays["_meta"]))
    del meta["log"]["seconds"], meta["log"]["clock"]
    arrays["_meta"] = np.array(json.dumps(meta))
    np.savez(path, **arrays)
    got = BodyStore(tmp_path / FOLDER, _options()).load().log
    assert got.seconds == [None, None] and np.isnan(got.clock)
    got.seconds.append(got.clock)  # the cycle in progress completes with its time unknown
    BodyStore(tmp_path / FOLDER, _options()).save_cycle(bm, run, cursor, got, Totals())
    again = BodyStore(tmp_path / FOLDER, _options()).load().log.seconds
    assert again[:2] == [None, None] and np.isnan(again[2])  # NaN stored as "nan", read back a float


def test_the_cycle_count_is_not_in_the_key_and_everything_else_is():
    assert _options() == body_options(CrawlSetup(cycles=5), (GAIT,), pipe="elbow", bend_radius=60.0,
                                      mesh="quick", silicone="s", design=None)  # fmt: skip
    changes = ({"bend_radius": 80.0}, {"mesh": "default"}, {"design": RobotDesign(n_rings=0)})
    for change in (*changes, {"inertia": True}):
        assert _options(**change) != _options()
    assert body_options(CrawlSetup(steps=8), (GAIT,), pipe="elbow", bend_radius=60.0, mesh="quick",
                        silicone="s", design=None) != _options()  # fmt: skip


def test_the_inertia_velocities_read_back_and_a_state_without_them_is_refused(tmp_path):
    """A body with inertia (`fem.inertia`): the committed velocities go with the state and come back
    bit for bit, the committed displacements are the cursor's x; a state without them is refused."""
    space = Discretisation(box(), "p2")
    bm, wall = _body()
    bm.inertia = Inertia(1e-9).build(space)
    bm.inertia.set_history(RNG.random(bm.inertia.dofs.shape), RNG.random(bm.inertia.dofs.shape))
    x = RNG.random(space.n_dofs)
    cursor = Cursor(0, 0.5, 0.25, x, None, None, np.zeros(3), 0.0, np.zeros(3), 0.0, 1, 0.1, 0.1)
    log = CycleLog(({"rear": 0.0, "front": 0.0}, 0.0), [], [], [], 0)
    run = PipeRun(True, "inserted", (), 1, 0.0, 0.0, 1.0, 6)
    store = BodyStore(tmp_path / FOLDER, _options(inertia=True))
    store.save_cycle(bm, run, cursor, log, Totals())
    fresh, _ = _body()
    fresh.inertia = Inertia(1e-9).build(space)
    store.restore(fresh, wall, BodyStore(tmp_path / FOLDER, _options(inertia=True)).load())
    assert np.array_equal(fresh.inertia.v_n, bm.inertia.v_n)
    assert np.array_equal(fresh.inertia.u_n, x[bm.inertia.dofs])
    bm.inertia = None
    store.save_cycle(bm, run, cursor, log, Totals())
    with pytest.raises(CheckpointError, match="has no velocities"):
        store.restore(fresh, wall, BodyStore(tmp_path / FOLDER, _options(inertia=True)).load())


@pytest.fixture
def never_run(monkeypatch):
    def run_and_write(*args, **kwargs):
        raise AssertionError("the refusal must come before any work")

    monkeypatch.setattr(files, "run_and_write", run_and_write)


def _stored(out, argv_options):
    bm, _ = _body()
    run = PipeRun(True, "inserted", (), 1, 0.0, 0.0, 1.0, 6)
    BodyStore(out / FOLDER, argv_options).save_inserted(bm, run)


def test_another_runs_checkpoint_is_refused_in_one_line(never_run, tmp_path, capsys):
    out = tmp_path / "run"
    setup = CrawlSetup(mu_smooth=0.3, mu_grooved=0.3, insert_steps=4)
    key = body_options(setup, (preset("inflate", 100.0, 2.0),), pipe="straight", bend_radius=None,
                       mesh="quick", silicone="x", design=None)  # fmt: skip
    _stored(out, key)
    argv = [
        "crawl",
        "--body",
        "fe",
        "--quick",
        "--mu-smooth",
        "0.3",
        "--mu-grooved",
        "0.3",
        "--out",
        str(out),
    ]
    assert main([*argv, "--resume"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "resume: " in err[0] and "was written with " in err[0]
    assert main(argv) == 2
    assert "holds the checkpoint of an unfinished run; add --resume" in capsys.readouterr().err


#: One thread for the assembly and MKL: threaded reductions add in another order from run to run
#: (tests/studies/crawl/test_crawl_resume_slow.py measured 8.8e-8 mm between two uninterrupted
#: threaded crawls; here a threaded resumed run differed by 2.2e-16 mm), so the runs are children
#: on one thread, where two uninterrupted runs are bit-identical.
DETERMINISTIC = {"SOFTCRAWL_THREADS": "1", "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def _child(out: str, how: str) -> None:
    """One run of the small body (in a child process): "whole", "killed" (exit 3 once a state in
    the cycle's second segment is on disk) or "resumed" (from the newest state)."""
    setup = CrawlSetup(pipe_diameter=77.0, insert_steps=1, steps=2, cycles=1, mu_smooth=0.3, mu_grooved=0.3)
    design = RobotDesign(n_rings=0, epsa=EPSADesign(length=30.0))
    where = {"pipe": "straight", "bend_radius": None, "mesh": SMALL, "silicone": None, "design": design}
    key = body_options(setup, (GAIT,), **where)
    store = BodyStore(Path(out) / FOLDER, key)
    if how == "killed":
        save_cycle = BodyStore.save_cycle

        def killing(self, bm, run, cursor, log, crawl):
            save_cycle(self, bm, run, cursor, log, crawl)
            if log.states and cursor.t < 1.0:
                os._exit(3)  # within the second segment, its first sub-step on disk

        BodyStore.save_cycle = killing
    resumed = store.load() if how == "resumed" else None
    if how == "resumed":
        assert resumed.cursor is not None and len(resumed.log.states) == 1, resumed.describe()
    files.run_and_write(setup, GAIT, Path(out), mesh=SMALL, design=design, progress=lambda _: None,
                        store=None if how == "whole" else store, resumed=resumed)  # fmt: skip


def _run(out: Path, how: str) -> int:
    env = os.environ | {"PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"} | DETERMINISTIC
    code = f"from tests.studies.crawl_fe.test_body_resume import _child; _child({str(out)!r}, {how!r})"
    return subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, timeout=3000).returncode


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_a_killed_run_resumed_equals_the_uninterrupted_one(tmp_path):
    assert _run(tmp_path / "whole", "whole") == 0
    out = tmp_path / "resumed"
    assert _run(out, "killed") == 3 and (out / FOLDER).exists() and not (out / "summary.json").exists()
    assert _run(out, "resumed") == 0
    whole = json.loads((tmp_path / "whole" / "summary.json").read_text())
    again = json.loads((out / "summary.json").read_text())
    assert again["strides_mm"] == whole["strides_mm"] and again["solver"]["resumed"]
    assert read_csv(out / "states.csv") == read_csv(tmp_path / "whole" / "states.csv")
    assert again["solver"]["newton_iterations"] == whole["solver"]["newton_iterations"]
    # each cycle's time is kept through the kill (docs/decisions/092-cycle-time.md)
    assert len(again["cycle_wall_s"]) == len(whole["strides_mm"]) and min(again["cycle_wall_s"]) > 0
    assert not (out / FOLDER).exists()
