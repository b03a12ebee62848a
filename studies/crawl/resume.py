r"""The crawl's checkpoints: each converged state on disk (`fem.checkpoint`), to resume after a kill.

What a state holds (docs/decisions/061-long-runs.md), read from `studies.crawl.model`,
`fem.contact_stages` and `fem.contact`:

    arrays  x; the secant predictor's previous state prev_x; the stage's start load P0 and the
            current load P; per contact term its multipliers and stick points; the recorder's
            rows and cycles (JSON text: NaN survives, floats read back bit for bit)
    meta    the position: which call of `run_crawl` (phase: insert, friction, start ramp or cycle
            k, by index into the run's plan), the stage index in it, the pseudo-time t, the next
            sub-step h, the predictor's previous t, the factors f0 and f; per contact term its
            surface and friction coefficient; the actuator's and the two ground springs'
            stiffness, preload and base; the recorder's start positions and cycle start; the
            solver's effort and the wall time so far

The run's options (the `CrawlSetup`, the schedule and the material) key the folder: a changed
option or softcrawl version refuses to resume, in one line naming it (`fem.checkpoint`).

A folder with states is an unfinished run: `files.run_and_write` removes it once the run's files
are written (the run ended, converged or not); a run killed before that leaves it, and the same
command with ``--resume`` (`softcrawl crawl`) or the same point of a sweep (`crawl_study`)
continues from its newest state.
"""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from softcrawl.fem.checkpoint import CheckpointError, Checkpoints
from softcrawl.fem.contact_stages import Cursor
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.files import TEMP_PREFIX

LINKS = ("actuator", "ground_rear", "ground_front")
FOLDER = "checkpoints"


def crawl_options(setup, schedule, material: str) -> dict[str, Any]:
    """The options that define a crawl (its checkpoints' key): the setup, the schedule, the feet's
    rubber."""
    return dataclasses.asdict(setup) | {
        "schedule": schedule.name,
        "schedule_times_s": [float(t) for t in schedule.times],
        "schedule_pressures_kpa": [[float(p) for p in row] for row in schedule.pressures_kpa],
        "material": material,
    }


@dataclass(frozen=True)
class Totals:
    """The solver's effort and the wall time of the run so far (carried over a resume); a
    `StagedResult`-like item of `run_crawl`'s statistics (and of the FE-body crawl's,
    `studies.crawl_fe.resume`)."""

    newton_iterations: int = 0
    assembly_s: float = 0.0
    solve_s: float = 0.0
    wall_s: float = 0.0
    factorizations: int = 0

    def plus(self, other) -> Totals:
        """These and `other`'s (any object with the five fields: a `StagedResult`, a body crawl)."""
        return Totals(*(getattr(self, f.name) + getattr(other, f.name) for f in dataclasses.fields(self)))


@dataclass
class Resumed:
    """A state read back: where to continue, and what to restore."""

    phase: int
    phase_name: str
    cursor: Cursor
    totals: Totals
    meta: dict
    arrays: dict

    @property
    def rows(self) -> list[dict]:
        return json.loads(str(self.arrays["rows"]))

    @property
    def cycles(self) -> list[dict]:
        return json.loads(str(self.arrays["cycles"]))

    def describe(self) -> str:
        rows = self.rows
        last = rows[-1] if rows else None
        where = f"stage {last['stage']!r} at t = {last['time_s']:.4g} s" if last else "the start"
        return f"state {len(rows)} ({self.phase_name}, {where})"


class CrawlStore:
    """The checkpoint folder of one crawl (`fem.checkpoint.Checkpoints` keyed by `crawl_options`)."""

    def __init__(self, folder: str | Path, options: dict[str, Any]) -> None:
        self.checkpoints = Checkpoints(folder, options)
        self.folder = self.checkpoints.folder

    def unfinished(self) -> bool:
        """A state on disk: a run that was stopped before its files were written."""
        return bool(self.checkpoints.states())

    def load(self) -> Resumed | None:
        """The newest state, or None (no state: a fresh start); `CheckpointError` (one line) when
        the folder was written with other options or another softcrawl version."""
        found = self.checkpoints.load_latest()
        if found is None:
            return None
        meta, arrays = found
        try:
            cursor = Cursor(
                stage=int(meta["stage"]),
                t=float(meta["t"]),
                h=float(meta["h"]),
                x=arrays["x"],
                prev_t=None if meta["prev_t"] is None else float(meta["prev_t"]),
                prev_x=arrays.get("prev_x"),
                P0=arrays["P0"],
                f0=float(meta["f0"]),
                P=arrays["P"],
                f=float(meta["f"]),
                newton_iterations=0,
                assembly_s=0.0,
                solve_s=0.0,
            )
            totals = Totals(**meta["totals"])
            return Resumed(int(meta["phase"]), str(meta["phase_name"]), cursor, totals, meta, arrays)
        except (KeyError, TypeError, ValueError) as exc:
            raise CheckpointError(
                "resume", f"the checkpoint in {self.folder} cannot be read ({type(exc).__name__}: {exc})"
            ) from None

    def save(self, cm, recorder, phase: int, phase_name: str, cursor: Cursor, totals: Totals) -> Path:
        """Write the state after the converged sub-step `cursor` (module docstring)."""
        arrays = {"x": cursor.x, "P0": np.asarray(cursor.P0), "P": np.asarray(cursor.P)}
        if cursor.prev_x is not None:
            arrays["prev_x"] = cursor.prev_x
        contacts = []
        for i, c in enumerate(cm.model.contacts):
            arrays[f"multiplier_{i}"], arrays[f"stick_{i}"] = c.multiplier, c.stick
            contacts.append({"mu": float(c.mu), "surface": _surface(c.surface)})
        arrays["rows"] = np.array(json.dumps(recorder.states))
        arrays["cycles"] = np.array(json.dumps(recorder.cycles))
        meta = {
            "phase": phase,
            "phase_name": phase_name,
            "stage": cursor.stage,
            "t": cursor.t,
            "h": cursor.h,
            "prev_t": cursor.prev_t,
            "f0": cursor.f0,
            "f": cursor.f,
            "contacts": contacts,
            "links": {
                n: {"stiffness": t.stiffness, "preload": t.preload, "rest": t.rest}
                for n, t in cm.terms.items()
            },
            "recorder": {
                "start": recorder.start,
                "cycle_from": recorder._cycle_from,
                "cycle_start": getattr(recorder, "_cycle_start", None),
            },
            "totals": dataclasses.asdict(totals),
        }
        path = self.checkpoints.save(len(recorder.states), arrays, meta)
        for temp in self.folder.glob(f"{TEMP_PREFIX}*"):  # left by a kill -9 during a write
            if not temp.name.startswith(f"{TEMP_PREFIX}{os.getpid()}-"):
                temp.unlink(missing_ok=True)
        return path

    def restore(self, cm, recorder, resumed: Resumed) -> None:
        """Put the model's history and the recorder back to the state `resumed`."""
        meta, arrays = resumed.meta, resumed.arrays
        contacts = cm.model.contacts
        if len(meta["contacts"]) != len(contacts):
            raise CheckpointError("resume", f"the checkpoint in {self.folder} has another model")
        for i, (c, saved) in enumerate(zip(contacts, meta["contacts"])):
            c.multiplier = np.array(arrays[f"multiplier_{i}"])
            c.stick = np.array(arrays[f"stick_{i}"])
            c.surface = _cylinder(saved["surface"])
            c.mu = float(saved["mu"])
            c._solved = None
        for name, load in meta["links"].items():
            cm.terms[name].set_load(load["stiffness"], load["preload"], load["rest"])
        recorder.states = resumed.rows
        recorder.cycles = resumed.cycles
        saved = meta["recorder"]
        recorder.start = saved["start"]
        recorder._cycle_from = int(saved["cycle_from"])
        if saved["cycle_start"] is not None:
            recorder._cycle_start = saved["cycle_start"]

    def latest_summary(self) -> dict[str, Any]:
        """The newest state in a few JSON-able fields (`OutOfMemory.last_state`); {} without one."""
        try:
            resumed = self.load()
        except CheckpointError:
            return {}
        if resumed is None:
            return {}
        rows = resumed.rows
        out = {
            "checkpoint": str(self.checkpoints.states()[-1]),
            "states": len(rows),
            "phase": resumed.phase_name,
        }
        if rows:
            out |= {k: rows[-1][k] for k in ("stage", "time_s", "centre_u_mm")}
        return out

    def clear(self) -> None:
        """The run ended and its files are written: its checkpoints go."""
        shutil.rmtree(self.folder, ignore_errors=True)


def _surface(surface) -> dict:
    if not isinstance(surface, CylinderWall):
        raise CheckpointError(
            "resume", f"a crawl checkpoint stores cylinder walls, not {type(surface).__name__}"
        )
    return {"radius": surface.radius, "centre": list(surface.centre), "axis": list(surface.axis)}


def _cylinder(saved: dict) -> CylinderWall:
    return CylinderWall(float(saved["radius"]), tuple(saved["centre"]), tuple(saved["axis"]))
