r"""The inserted state of a crawl, computed once: a content-addressed cache of the insertion.

Every crawl begins with the same frictionless insertion (`studies.crawl.model`, phase "insert":
the wall shrinks from clear of the skirt tips to the pipe radius, both plates held by the stiff
ground springs, the actuator at its zero-pressure stiffness). Nothing of it depends on the
friction coefficients, the schedule, the sub-steps of the cycles or their number, so the crawl
study's two friction values of one diameter, a bench's repeated runs and a foot optimiser's
confirmation crawls can all start from one computed insertion.

Key. The cached state is the insertion's last converged state, written through the checkpoint
mechanism (`fem.checkpoint` via `studies.crawl.resume.CrawlStore`: x, each contact term's
multipliers, stick points, surface and friction coefficient, the springs' loads, the recorder's
rows), in a folder named by the hash of `insertion_options`: the mesh itself (a hash of its node
coordinates and elements, so a changed foot design, mesher or refinement is another key), the
foot design's hash, the feet's orientation, the pipe diameter, the insertion steps, the feet's
material law (its parameters), the actuator's zero-pressure stiffness, the crawl's contact and
Newton settings (`CRAWL_NEWTON`, `AUGMENT`, `MAX_CUTBACKS`, `GROUND_HOLD`, the contact smoothing
and slip band), the linear solver, `FORMAT`, and the softcrawl version (`fem.checkpoint`).
Bump `FORMAT` when the insertion's code changes without a version bump (an editable install).
The flipped feet's key also names how their folds are held (`fold_held`, record 078: each foot's
actuator face) and how their plates are held until friction (`plates_held`, record 079: ground
springs of n k_p, `studies.crawl.flipped.plate_hold`) and their insertion's viscous stabilisation
(`stabilised`, record 094: c0 = STABILISE E / t^2, E and t in the key through the law and the
design; named only where it is on, a fold outside the wall), so that an entry folded with both hub tops
held, or inserted on GROUND_HOLD, is not taken for it, while the other feet's keys keep their
value.
The feet's design and rubber (`CrawlSetup.foot`, `CrawlSetup.material`) reach the key through the
mesh hash, the foot design's hash and the law's parameters, as they did when both were fixed: the
key of every existing entry (the paper's foot in rubber-70a) keeps its meaning and its value.

Use. ``run_crawl(..., insertion=InsertionCache(...))``: when the cache holds the state, the run
continues from it exactly as `--resume` continues from a checkpoint at the end of the insertion
stage (the friction phase and everything after it run as in a cold run; the recorder's insertion
rows are the cached ones, so states.csv is the cold run's); when it does not, the run computes the
insertion and writes its last state there. The key's lock file (``fcntl.flock``) is held from the
look-up to the write, so a second worker asking for the same insertion waits for the first one's
instead of computing it again. Newton iterations of the insertion are carried in the result (the
path's effort, so the counts stay comparable with a cold run); its times are not (this run did
not spend them). `hit` says which happened.

Size and pruning. One entry is one checkpoint state and its manifest: 2.06 MB for the quick feet.
Nothing prunes the cache (an entry of another softcrawl version is never read again): deleting
`insertion_dir()`, or an entry, while no crawl runs costs only the recomputation (the README).
"""

from __future__ import annotations

import contextlib
import dataclasses
import fcntl
import hashlib
from pathlib import Path
from typing import Any

import numpy as np

from softcrawl.fem.checkpoint import content_hash, softcrawl_version
from softcrawl.fem.linsolve import default_solver
from softcrawl.geometry.tetwild import default_cache_dir
from softcrawl.studies.crawl import flipped as flipped_feet
from softcrawl.studies.crawl import model as crawl_model
from softcrawl.studies.crawl.resume import CrawlStore, Resumed, Totals
from softcrawl.studies.foot import model as foot_model

#: Bumped when what the insertion computes changes without a softcrawl version bump.
FORMAT = 2  # 2: feet "backward" are the flipped feet (record 067), no longer mirrored ones


def insertion_dir() -> Path:
    """The cache's root: `insertions/` in the mesh cache's folder ($SOFTCRAWL_CACHE or
    ~/.cache/softcrawl/meshes)."""
    return default_cache_dir() / "insertions"


def mesh_hash(mesh) -> str:
    """A content hash of an skfem mesh: its node coordinates and element connectivity, bit for bit."""
    h = hashlib.sha256()
    for a in (np.ascontiguousarray(mesh.p, dtype=float), np.ascontiguousarray(mesh.t, dtype=np.int64)):
        h.update(str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()[:16]


def insertion_options(cm, mesh, foot_design, law) -> dict[str, Any]:
    """What the inserted state of the crawl model `cm` depends on (module docstring, "Key")."""
    setup = cm.setup
    # the flipped feet's folds hold each foot's actuator face (record 078), and their plates are
    # held by ground springs of n k_p until friction (record 079; k_p = PLATE_PENALTY E h, n, E
    # and h from the mesh and the law, both in the key): an entry computed otherwise has another
    # key, and the other feet's keys keep their value
    flipped = (
        {
            "fold_held": "actuator_face",
            "plates_held": {"ground_hold": "n k_p", "plate_penalty": crawl_model.PLATE_PENALTY},
        }
        if setup.flipped
        else {}
    )
    if getattr(cm, "stabilise", 0.0) > 0:  # only where the fold is crushed (record 094)
        flipped["stabilised"] = {"coefficient": "STABILISE E / t^2", "STABILISE": flipped_feet.STABILISE}
    # a wedge of the feet (records 082, 083): its mesh is in the mesh hash, its tie here (exact
    # since 083: a penalty tie's cached states are not reused); the whole feet's keys keep their value
    wedge = {"wedge": {"copies": setup.copies, "tie": "exact"}} if setup.copies > 1 else {}
    return (
        flipped
        | wedge
        | {
            "format": FORMAT,
            "mesh": mesh_hash(mesh),
            "foot_design": foot_design.short_hash(),
            "feet": setup.feet,
            "pipe_diameter": float(setup.pipe_diameter),
            "insert_steps": int(setup.insert_steps),
            "law": type(law).__name__,
            "law_parameters": dataclasses.asdict(law) if dataclasses.is_dataclass(law) else repr(law),
            "actuator_k0": [float(v) for v in cm.law.stiffness_preload((0.0, 0.0, 0.0))],
            "newton": dataclasses.asdict(crawl_model.CRAWL_NEWTON),
            "augment": dict(foot_model.AUGMENT),
            "max_cutbacks": crawl_model.MAX_CUTBACKS,
            "ground_hold": crawl_model.GROUND_HOLD,
            "contact": {"smoothing": foot_model.SMOOTHING, "slip_band": foot_model.SLIP_BAND},
            "solver": default_solver(),
        }
    )


class InsertionCache:
    """The cached insertion of one crawl model (module docstring). `root`: the cache's folder
    (default `insertion_dir()`)."""

    def __init__(self, cm, mesh, foot_design, law, root: str | Path | None = None) -> None:
        self.options = insertion_options(cm, mesh, foot_design, law)
        self.key = content_hash(self.options, softcrawl_version())
        self.root = Path(root) if root is not None else insertion_dir()
        self.store = CrawlStore(self.root / f"insertion-{self.key}", self.options)
        self.hit: bool | None = None  # set by `run_crawl`: True when the state came from the cache

    @contextlib.contextmanager
    def locked(self):
        """Hold the key's lock (another process with the same key waits)."""
        self.root.mkdir(parents=True, exist_ok=True)
        with open(self.root / f"insertion-{self.key}.lock", "a") as handle:
            fcntl.flock(handle, fcntl.LOCK_EX)
            try:
                yield self
            finally:
                fcntl.flock(handle, fcntl.LOCK_UN)

    def load(self) -> Resumed | None:
        """The cached inserted state, or None. Its totals carry only the Newton iterations."""
        if not self.store.checkpoints.states():
            return None
        found = self.store.load()
        if found is None:
            return None
        found.totals = Totals(newton_iterations=found.totals.newton_iterations)
        return found

    def save(self, cm, recorder, cursor, totals: Totals) -> Path:
        """Write the inserted state (the cursor at the end of the insertion stage)."""
        return self.store.save(cm, recorder, 0, "insert", cursor, totals)


def insertion_cache_for(choice, cm, mesh, foot_design, law) -> InsertionCache | None:
    """The cache a caller's `insertion_cache` option names: True (the default folder), a folder,
    or False/None (no cache: the insertion is computed)."""
    if choice is False or choice is None:
        return None
    return InsertionCache(cm, mesh, foot_design, law, None if choice is True else choice)
