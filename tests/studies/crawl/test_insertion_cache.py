"""The cache of inserted states (`studies.crawl.insertion`): its key changes with every input the
insertion depends on and with none it does not; a state written reads back into a fresh model bit
for bit; the key's lock makes a second process wait. The crawl from a cached insertion against a
computed one: test_insertion_cache_slow.py."""

from __future__ import annotations

import dataclasses
import json
import threading
import time
from types import SimpleNamespace

import numpy as np
import pytest

from softcrawl.fem.contact_stages import Cursor
from softcrawl.fem.laws.neo_hookean import NeoHookean
from softcrawl.geometry.design import RobotDesign
from softcrawl.studies.crawl import insertion as ins
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.resume import Totals
from softcrawl.studies.crawl.schedule import AxialLaw
from tests.studies.crawl.test_crawl_resume import _fakes


def _cm(**changes):
    setup = dataclasses.replace(CrawlSetup(insert_steps=4, sectors=24), **changes)
    return SimpleNamespace(setup=setup, law=AxialLaw())


def _mesh(shift=0.0):
    p = np.arange(12.0).reshape(3, 4) + shift
    return SimpleNamespace(p=p, t=np.array([[0], [1], [2], [3]]))


LAW = NeoHookean(mu=1.84, bulk=1840.0)
FOOT = RobotDesign().foot


def _key(cm=None, mesh=None, foot=FOOT, law=LAW, root="unused"):
    return ins.InsertionCache(cm or _cm(), mesh or _mesh(), foot, law, root).key


def test_the_key_changes_with_each_input_of_the_insertion():
    base = _key()
    assert _key() == base  # deterministic
    changed = {
        "pipe diameter": _key(_cm(pipe_diameter=65.0)),
        "insertion steps": _key(_cm(insert_steps=8)),
        "feet": _key(_cm(feet="backward")),
        "mesh": _key(mesh=_mesh(1e-12)),
        "foot design": _key(foot=FOOT.replace(hub_thickness=FOOT.hub_thickness + 1.0)),
        "material": _key(law=NeoHookean(mu=1.85, bulk=1840.0)),
    }
    for name, key in changed.items():
        assert key != base, name
    assert len(set(changed.values())) == len(changed)


def test_the_key_changes_with_the_solver_settings(monkeypatch):
    base = _key()
    monkeypatch.setattr(
        ins.crawl_model, "CRAWL_NEWTON", dataclasses.replace(ins.crawl_model.CRAWL_NEWTON, tol=1e-9)
    )
    assert _key() != base
    monkeypatch.undo()
    monkeypatch.setattr(ins.foot_model, "AUGMENT", {"penetration_tol": 0.005, "max_augment": 2})
    assert _key() != base
    monkeypatch.undo()
    monkeypatch.setattr(ins, "default_solver", lambda: "superlu")
    assert _key() != base


def test_the_flipped_feet_key_names_how_their_folds_are_held():
    """Record 078: the flipped feet's folds hold each foot's actuator face; an entry computed with
    both hub tops held must not be read for it, and the paper's feet's key keeps its value."""
    flipped = ins.insertion_options(_cm(feet="backward"), _mesh(), FOOT, LAW)
    assert flipped["fold_held"] == "actuator_face"
    assert "fold_held" not in ins.insertion_options(_cm(), _mesh(), FOOT, LAW)


def test_the_flipped_feet_key_names_how_their_plates_are_held(monkeypatch):
    """Record 079: the flipped feet's plates are held by ground springs of n k_p until friction;
    an entry inserted on GROUND_HOLD must not be read for it, nor one of another plate penalty,
    and the paper's feet's key keeps its value."""
    flipped = ins.insertion_options(_cm(feet="backward"), _mesh(), FOOT, LAW)
    assert flipped["plates_held"] == {"ground_hold": "n k_p", "plate_penalty": 1.0e3}
    paper = _key()
    assert "plates_held" not in ins.insertion_options(_cm(), _mesh(), FOOT, LAW)
    before = _key(_cm(feet="backward"))
    monkeypatch.setattr(ins.crawl_model, "PLATE_PENALTY", 1.0e2)
    assert _key(_cm(feet="backward")) != before and _key() == paper


def test_the_key_ignores_what_comes_after_the_insertion():
    """Friction, the cycles, their sub-steps and the wall budget do not enter the insertion."""
    base = _key()
    for changes in ({"mu_smooth": 0.3, "mu_grooved": 0.3}, {"cycles": 3}, {"steps": 8}, {"max_wall_s": 10.0}):
        assert _key(_cm(**changes)) == base, changes


def test_a_cached_state_reads_back_bit_for_bit(tmp_path):
    cache = ins.InsertionCache(_cm(), _mesh(), FOOT, LAW, tmp_path)
    assert cache.load() is None
    cm, recorder = _fakes(3)
    x = np.random.default_rng(0).random(9)
    cursor = Cursor(0, 1.0, 0.25, x, 0.75, x - 1, np.zeros(1), 0.0, np.zeros(1), 0.0, 17, 1.0, 2.0)
    cache.save(cm, recorder, cursor, Totals(17, 1.0, 2.0, 30.0))
    again = ins.InsertionCache(_cm(mu_smooth=0.3), _mesh(), FOOT, LAW, tmp_path).load()
    assert again is not None
    assert again.phase == 0 and again.cursor.t == 1.0
    assert np.array_equal(again.cursor.x, x)
    assert again.totals == Totals(17)  # the iterations carried, not the times of another run
    fresh, fresh_recorder = _fakes(5)
    ins.InsertionCache(_cm(), _mesh(), FOOT, LAW, tmp_path).store.restore(fresh, fresh_recorder, again)
    for a, b in zip(cm.model.contacts, fresh.model.contacts):
        assert np.array_equal(a.multiplier, b.multiplier) and np.array_equal(a.stick, b.stick)
        assert a.surface.radius == b.surface.radius and a.mu == b.mu
    assert json.dumps(fresh_recorder.states) == json.dumps(recorder.states)  # NaN included
    assert ins.InsertionCache(_cm(pipe_diameter=65.0), _mesh(), FOOT, LAW, tmp_path).load() is None


def test_a_second_process_waits_for_the_first_ones_insertion(tmp_path):
    first = ins.InsertionCache(_cm(), _mesh(), FOOT, LAW, tmp_path)
    second = ins.InsertionCache(_cm(), _mesh(), FOOT, LAW, tmp_path)
    order = []

    def wait():
        with second.locked():
            order.append("second")

    with first.locked():
        thread = threading.Thread(target=wait)
        thread.start()
        time.sleep(0.3)
        order.append("first")
    thread.join(5)
    assert order == ["first", "second"]


@pytest.mark.parametrize("choice", [False, None])
def test_no_cache_is_asked_for(choice):
    assert ins.insertion_cache_for(choice, _cm(), _mesh(), FOOT, LAW) is None


def test_the_flipped_feet_key_names_their_insertions_stabilisation(monkeypatch):
    """Record 094: where the flipped feet's insertion is stabilised (c0 = STABILISE E / t^2 > 0,
    a fold outside the wall) the key names it, so an entry inserted without it, or with another
    coefficient, is not read; where it is off (c0 = 0) and for the paper's feet the key keeps its
    value from before."""

    def stabilised(c0):
        cm = _cm(feet="backward")
        cm.stabilise = c0
        return cm

    key = ins.insertion_options(stabilised(0.01), _mesh(), FOOT, LAW)
    assert key["stabilised"] == {"coefficient": "STABILISE E / t^2", "STABILISE": 1.0e-2}
    assert "stabilised" not in ins.insertion_options(stabilised(0.0), _mesh(), FOOT, LAW)
    assert _key(stabilised(0.0)) == _key(_cm(feet="backward"))
    assert "stabilised" not in ins.insertion_options(_cm(), _mesh(), FOOT, LAW)
    before = _key(stabilised(0.01))
    monkeypatch.setattr(ins.flipped_feet, "STABILISE", 1.0e-1)
    assert _key(stabilised(0.01)) != before
