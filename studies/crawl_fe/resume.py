r"""The FE-body crawl's checkpoints: the inserted state and each converged sub-step of the cycles on
disk (`fem.checkpoint`), to resume after a kill or a stop at the time limit.

What a state holds (read from `studies.crawl_fe.pipe`, `.cycle` and `fem.contact_stages`):

    arrays  the setup phases' states x (insert, friction, load); the recorded cycle states' x; for
            a state in the cycles, the cursor's x, the predictor's prev_x and the loads P0, P;
            per contact term its multipliers and stick points; with inertia (`fem.inertia`) the
            committed nodal velocities (the committed displacements are the cursor's x)
    meta    kind: "inserted" (after `into_pipe`, before the first cycle) or "cycles"; the cursor's
            position (stage index, pseudo-time t, next sub-step h, the predictor's t, the factors
            f0 and f); per contact term its friction coefficient and wall radius (the wall itself
            is rebuilt from the options: straight, vertical or elbow); the holds' (six; a
            wedge's two) stiffness, preload and base; the setup phases' wall and hold forces; the cycle log
            (`cycle.CycleLog`: the states' outputs, strides, turns, where the cycle began);
            the solver's effort and the wall time so far

Floats go through JSON as Python writes them (repr), so they read back bit for bit, and a resumed
run's states and strides equal an uninterrupted run's (tests/studies/crawl_fe/test_body_resume.py).

The key (`body_options`) is the run's options: the setup except its cycle count, the schedules,
the pipe, the mesh, the silicone, the design and whether the body has inertia. The cycle count is
left out on purpose: the first k cycles' stages are the same whatever the count, so a stopped run
may be continued with more cycles (an elbow that needs more than was planned). A gait plan's
cycles are its schedules, which are in the key. Another option or softcrawl version refuses to
resume in one line naming it.

A run whose files are written and that ended (all cycles, or a diverged stage) clears its
folder; a run stopped at its time limit keeps it, so that ``softcrawl crawl --body fe --resume``
with the same options (and a new `--time-limit`) continues it.
"""

from __future__ import annotations

import dataclasses
import math
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from softcrawl.fem.checkpoint import CheckpointError, Checkpoints
from softcrawl.fem.contact_stages import Cursor
from softcrawl.studies.crawl.resume import Totals
from softcrawl.studies.crawl_fe.cycle import BodyState, CycleLog
from softcrawl.studies.crawl_fe.pipe import PipeRun, PipeState

FOLDER = "checkpoints"
#: The solver's effort and wall time carried over a resume (`Totals`' fields).
TOTALS = tuple(f.name for f in dataclasses.fields(Totals))


def body_options(
    setup, schedules, *, pipe, bend_radius, mesh, silicone, design, inertia=False, corrugation=None
) -> dict[str, Any]:
    """The options that define an FE-body crawl (its checkpoints' key; module docstring)."""
    return {k: v for k, v in dataclasses.asdict(setup).items() if k != "cycles"} | {
        "schedules": [
            {
                "name": s.name,
                "times_s": [float(t) for t in s.times],
                "pressures_kpa": [[float(p) for p in row] for row in s.pressures_kpa],
            }
            for s in schedules
        ],
        "pipe": pipe,
        "bend_radius": bend_radius,
        "mesh": mesh if isinstance(mesh, str) else dataclasses.asdict(mesh),
        "silicone": silicone,
        "design": None if design is None else dataclasses.asdict(design),
        "inertia": bool(inertia),
        "corrugation": None if corrugation is None else [float(v) for v in corrugation],
    }


@dataclass(frozen=True)
class Resumed:
    """A state read back: the setup run (the insertion), and for a state in the cycles the cursor
    and the cycle log; `crawl`: the cycles' effort before the state (its process's included)."""

    run: PipeRun
    cursor: Cursor | None
    log: CycleLog | None
    crawl: Totals
    meta: dict
    arrays: dict

    def describe(self) -> str:
        if self.cursor is None:
            return "the inserted state"
        done = len(self.log.strides)
        return f"{done} cycle(s) done, stage {self.cursor.stage} at s = {self.cursor.t:.4g}"


class BodyStore:
    """The checkpoint folder of one FE-body crawl (`fem.checkpoint.Checkpoints` keyed by
    `body_options`)."""

    def __init__(self, folder: str | Path, options: dict[str, Any]) -> None:
        self.checkpoints = Checkpoints(folder, options)
        self.folder = self.checkpoints.folder
        self._index = 0

    def unfinished(self) -> bool:
        """A state on disk: a run stopped before it ended."""
        return bool(self.checkpoints.states())

    def save_inserted(self, bm, run: PipeRun) -> Path:
        """The state after the insertion (`into_pipe` converged), before the first cycle."""
        return self._save(bm, run, None, None, Totals(), "inserted")

    def save_cycle(self, bm, run: PipeRun, cursor: Cursor, log: CycleLog, crawl: Totals) -> Path:
        """The state after a converged sub-step of the cycles; `crawl`: their effort so far."""
        return self._save(bm, run, cursor, log, crawl, "cycles")

    def _save(self, bm, run, cursor, log, crawl, kind) -> Path:
        arrays: dict[str, np.ndarray] = {}
        for k, st in enumerate(run.states):
            arrays[f"setup_x_{k}"] = st.x
        meta: dict[str, Any] = {
            "kind": kind,
            "run": {k: getattr(run, k) for k in ("message", "n_dofs", *TOTALS)},
            "setup_states": [
                {
                    "phase": st.phase,
                    "holds": st.holds,
                    "normal": st.normal,
                    "friction": {f: [float(v) for v in st.friction[f]] for f in st.friction},
                }
                for st in run.states
            ],  # fmt: skip
            "contacts": [],
            "holds": {
                name: {"stiffness": t.stiffness, "preload": t.preload, "rest": t.rest}
                for name, t in bm.holds.items()
            },
            "crawl": dataclasses.asdict(crawl),
        }
        for i, c in enumerate(bm.model.contacts):
            arrays[f"multiplier_{i}"], arrays[f"stick_{i}"] = c.multiplier, c.stick
            meta["contacts"].append({"mu": float(c.mu), "radius": float(c.surface.radius)})
        if cursor is not None:
            arrays |= {"x": cursor.x, "P0": np.asarray(cursor.P0), "P": np.asarray(cursor.P)}
            if cursor.prev_x is not None:
                arrays["prev_x"] = cursor.prev_x
            meta |= {k: getattr(cursor, k) for k in ("stage", "t", "h", "prev_t", "f0", "f")}
            if bm.inertia is not None:  # its committed displacements are the cursor's x
                arrays["velocity"] = bm.inertia.velocity()
            meta["log"] = {
                "start": list(log.start),
                "strides": log.strides,
                "turns": log.turns,
                "segment": log.segment,
                "seconds": log.seconds,
                "clock": log.clock,
                "states": [{f.name: getattr(st, f.name) for f in dataclasses.fields(st) if f.name != "x"}
                           for st in log.states],
            }  # fmt: skip
            for k, st in enumerate(log.states):
                arrays[f"state_x_{k}"] = st.x
        self._index += 1
        return self.checkpoints.save(self._index, arrays, meta)

    def load(self) -> Resumed | None:
        """The newest state, or None (a fresh start); `CheckpointError` (one line) for a folder of
        other options or another softcrawl version, or one that cannot be read."""
        found = self.checkpoints.load_latest()
        if found is None:
            return None
        meta, arrays = found
        self._index = int(self.checkpoints.states()[-1].stem.split("-")[1])
        try:
            setup = tuple(
                PipeState(s["phase"], s["holds"], s["normal"],
                          {f: np.asarray(v) for f, v in s["friction"].items()}, arrays[f"setup_x_{k}"])
                for k, s in enumerate(meta["setup_states"])
            )  # fmt: skip
            r = meta["run"]
            run = PipeRun(True, r["message"], setup, n_dofs=r["n_dofs"], **{k: r[k] for k in TOTALS})
            crawl = Totals(**meta["crawl"])
            if meta["kind"] == "inserted":
                return Resumed(run, None, None, crawl, meta, arrays)
            cursor = Cursor(
                stage=int(meta["stage"]), t=float(meta["t"]), h=float(meta["h"]), x=arrays["x"],
                prev_t=None if meta["prev_t"] is None else float(meta["prev_t"]), prev_x=arrays.get("prev_x"),
                P0=arrays["P0"], f0=float(meta["f0"]), P=arrays["P"], f=float(meta["f"]),
                newton_iterations=0, assembly_s=0.0, solve_s=0.0,
            )  # fmt: skip
            saved = meta["log"]
            states = [_body_state(s, arrays[f"state_x_{k}"]) for k, s in enumerate(saved["states"])]
            # a state written before the cycles' times were kept: those cycles' times are unknown
            seconds = [None if v is None else float(v)  # NaN is stored as "nan" (`fem.checkpoint`)
                       for v in saved.get("seconds", [None] * len(saved["strides"]))]  # fmt: skip
            clock = float(saved.get("clock", math.nan))  # NaN: this cycle's time is unknown too
            log = CycleLog((saved["start"][0], float(saved["start"][1])), states, list(saved["strides"]),
                           list(saved["turns"]), int(saved["segment"]), seconds,
                           clock)  # fmt: skip
            return Resumed(run, cursor, log, crawl, meta, arrays)
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            raise CheckpointError(
                "resume", f"the checkpoint in {self.folder} cannot be read ({type(exc).__name__}: {exc})"
            ) from None

    def restore(self, bm, wall, resumed: Resumed) -> None:
        """Put the model's history (contact terms, holds) back to the state `resumed`; `wall`: the
        run's pipe (`pipe.pipe_wall`), placed at each term's stored radius."""
        meta = resumed.meta
        contacts = bm.model.contacts
        if len(meta["contacts"]) != len(contacts) or set(meta["holds"]) != set(bm.holds):
            raise CheckpointError("resume", f"the checkpoint in {self.folder} has another model")
        for i, (c, saved) in enumerate(zip(contacts, meta["contacts"])):
            c.multiplier = np.array(resumed.arrays[f"multiplier_{i}"])
            c.stick = np.array(resumed.arrays[f"stick_{i}"])
            c.surface = wall.with_radius(float(saved["radius"]))
            c.mu = float(saved["mu"])
            c._solved = None
        for name, load in meta["holds"].items():
            bm.holds[name].set_load(load["stiffness"], load["preload"], load["rest"])
        if bm.inertia is not None and resumed.cursor is not None:
            velocity = resumed.arrays.get("velocity")
            if velocity is None:
                raise CheckpointError("resume", f"the checkpoint in {self.folder} has no velocities")
            bm.inertia.set_history(resumed.cursor.x[bm.inertia.dofs], velocity)

    def clear(self) -> None:
        """The run ended and its files are written: its checkpoints go."""
        shutil.rmtree(self.folder, ignore_errors=True)


def _body_state(saved: dict, x: np.ndarray) -> BodyState:
    """A `cycle.BodyState` from its stored fields (JSON lists back to the tuples it holds)."""
    tuples = {k: tuple(saved[k]) for k in ("pressures_kpa", "volumes", "drift")}
    return BodyState(**(saved | tuples), x=x)
