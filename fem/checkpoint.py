"""Checkpoints of a long solve: each converged state on disk, atomically, to resume after a kill.

Why here, in the solver layer: what a state holds is the solver's (the state vector, the contact
history, the position on the load path, the step size, the predictor's history), and every long
run of the project needs the same: `softcrawl crawl`, `softcrawl robot`, the crawl study's points,
the insertion cache and the whole-robot crawl. This module knows no model: a state is a dict of
numpy arrays and a JSON-able dict of metadata; the callers (`studies.crawl.resume`, ...) say what
goes in.

On disk, in one folder per run:

    manifest.json        the run's options and the softcrawl version, and their content hash
    state-000042.npz     one converged state: its arrays, and its metadata as JSON in "_meta"

Each file is written to a temporary name and renamed (`softcrawl.files.atomic_path`), so a kill
-9, a SIGTERM or a full disk leaves the previous state whole: a half-written state never has its
final name. After each write the oldest states beyond `KEEP` are removed. `load_latest` returns
the newest state that reads back (a damaged file, which the rename should make impossible, is
skipped, not trusted).

A run resumes only with the options and the softcrawl version that wrote the folder: anything
else would continue a different problem from a state that is not its own. `Checkpoints.check`
raises `CheckpointError` (an `InputError` of parameter ``resume``) with one line naming the first
option that differs, or the version.
"""

from __future__ import annotations

import hashlib
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from softcrawl.errors import InputError
from softcrawl.files import atomic_path

#: States kept on disk (the newest); the older ones are removed after each write.
KEEP = 3
MANIFEST = "manifest.json"


class CheckpointError(InputError):
    """A checkpoint folder that cannot be resumed (other options, another version, unreadable)."""


def softcrawl_version() -> str:
    """The installed softcrawl version (read from the package metadata; this layer imports no
    project module above the core)."""
    from importlib import metadata

    try:
        return metadata.version("softcrawl")
    except metadata.PackageNotFoundError:
        return "0+unknown"


def _canonical(options: dict[str, Any]) -> dict[str, Any]:
    """The options as JSON stores them (tuples as lists, floats as floats), to compare equal."""
    return json.loads(json.dumps(options, sort_keys=True, default=str))


def content_hash(options: dict[str, Any], version: str) -> str:
    text = json.dumps({"options": _canonical(options), "version": version}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class Checkpoints:
    """The checkpoint folder of one run, identified by its `options` (JSON-able) and `version`."""

    def __init__(
        self, folder: str | Path, options: dict[str, Any], version: str | None = None, keep: int = KEEP
    ):
        if keep < 1:
            raise CheckpointError("keep", f"must keep at least one state, got {keep}")
        self.folder = Path(folder)
        self.options = _canonical(options)
        self.version = softcrawl_version() if version is None else version
        self.key = content_hash(self.options, self.version)
        self.keep = keep

    def states(self) -> list[Path]:
        """The state files on disk, oldest first."""
        return sorted(self.folder.glob("state-*.npz"))

    def manifest(self) -> dict[str, Any] | None:
        try:
            return json.loads((self.folder / MANIFEST).read_text())
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            raise CheckpointError("resume", f"cannot read {self.folder / MANIFEST}: {exc}") from None

    def check(self) -> None:
        """Raise `CheckpointError` (one line) if the folder was written by other options or another
        softcrawl version; a folder without a manifest is a fresh start."""
        found = self.manifest()
        if found is None or found.get("key") == self.key:
            return
        if found.get("version") != self.version:
            raise CheckpointError(
                "resume",
                f"the checkpoint in {self.folder} was written by softcrawl {found.get('version')}, this is "
                f"{self.version}; it cannot be resumed (remove the folder to start again)",
            )
        old = found.get("options", {})
        for name in sorted(set(old) | set(self.options)):
            then, now = old.get(name, "(not set)"), self.options.get(name, "(not set)")
            if then != now:
                raise CheckpointError(
                    "resume",
                    f"the checkpoint in {self.folder} was written with {name} = {then!r}, this run has "
                    f"{now!r}; run with the same options or remove the folder to start again",
                )
        raise CheckpointError("resume", f"the checkpoint in {self.folder} belongs to another run")

    def save(self, index: int, arrays: dict[str, np.ndarray], meta: dict[str, Any]) -> Path:
        """Write state `index` (increasing over the run) atomically, then prune to `keep`."""
        self.folder.mkdir(parents=True, exist_ok=True)
        if self.manifest() is None:
            manifest = {"key": self.key, "version": self.version, "options": self.options}
            with atomic_path(self.folder / MANIFEST) as temp:
                Path(temp).write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
        path = self.folder / f"state-{int(index):06d}.npz"
        payload = {k: np.asarray(v) for k, v in arrays.items()}
        payload["_meta"] = np.array(json.dumps(_finite(meta)))
        with atomic_path(path) as temp:
            with open(temp, "wb") as handle:
                np.savez(handle, **payload)
        for old in self.states()[: -self.keep]:
            old.unlink(missing_ok=True)
        return path

    def load_latest(self) -> tuple[dict[str, Any], dict[str, np.ndarray]] | None:
        """(meta, arrays) of the newest readable state, or None; checks the folder first."""
        self.check()
        for path in reversed(self.states()):
            try:
                with np.load(path, allow_pickle=False) as data:
                    arrays = {k: data[k] for k in data.files if k != "_meta"}
                    meta = json.loads(str(data["_meta"]))
            except (OSError, ValueError, KeyError):
                continue
            return meta, arrays
        return None


def _finite(value: Any) -> Any:
    """JSON cannot hold NaN or infinity in strict form: they are stored as strings and read back by
    the caller where it needs them (none of a converged state is)."""
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    if isinstance(value, dict):
        return {str(k): _finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value
