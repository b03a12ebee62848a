"""Run inside a private mount namespace with a tiny tmpfs at DISK (see test_full_disk.py): fill
the disk, run a sweep that hits the full disk, free the space, resume; print what happened as
JSON. Usage: python -m tests.studies.sweeps.full_disk_driver DISK KEEP_BYTES"""

from __future__ import annotations

import dataclasses
import json
import os
import sys
import time
from pathlib import Path

from tests.studies.sweeps.cli_runs import completed_once, run, spec_of, study_argv


def main() -> None:
    disk, keep = Path(sys.argv[1]), int(sys.argv[2])
    # "output": the study database lives off the small disk, so that only an output can fill it
    # (the database grew with decision 063's flat metrics and would otherwise race the outputs)
    storage = (
        f"sqlite:///{disk.parent / 'study.db'}" if len(sys.argv) > 3 and sys.argv[3] == "output" else None
    )
    out, shapes, filler = disk / "out", disk / "out" / "shapes", disk / "filler"
    stat = os.statvfs(disk)
    with open(filler, "wb") as handle:
        handle.write(b"\0" * (stat.f_bavail * stat.f_frsize - keep))
    env = {"SOFTCRAWL_FAKE_OUTPUT": str(shapes), "SOFTCRAWL_FAKE_OUTPUT_BYTES": "150000"}
    first = run(study_argv(out, *(["--storage", storage] if storage else [])), env=env)
    partial = sorted(str(p) for p in disk.rglob(".partial-*"))
    running = [t.number for t in _trials(out, storage) if t.state.name == "RUNNING"]
    filler.unlink()  # space freed
    os.environ.update(env)
    from softcrawl.studies.epsa.evaluator import EPSA_TABLE
    from softcrawl.studies.sweeps.sweep import run_sweep

    t0 = time.monotonic()
    rows = run_sweep(
        dataclasses.replace(spec_of(out, storage=storage), grace_period=600),
        layout=EPSA_TABLE,
        progress=False,
    )
    report = {
        "first_code": first.returncode,
        "first_stderr": first.stderr,
        "partial_files": partial,
        "left_running": running,
        "resume_s": time.monotonic() - t0,
        "resumed_statuses": sorted({r["trial_status"] for r in rows}),
        "completed_once": completed_once(spec_of(out, storage=storage)),
        "shapes": sorted(p.name for p in shapes.iterdir()),
    }
    print(json.dumps(report))


def _trials(out, storage=None):
    from softcrawl.studies.sweeps.worker import open_sweep

    return open_sweep(spec_of(out, storage=storage))[0].get_trials(deepcopy=False)


if __name__ == "__main__":
    main()
