"""`--max-memory GB` per worker (`studies.sweeps.memory`): a point whose resident memory passes the
limit is a failed result naming the memory, the sweep finishes its other points, and every point's
peak is in the table (``peak_rss_gb``)."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap

import pytest

pytest.importorskip("optuna")

from softcrawl.studies.sweeps import memory
from softcrawl.studies.sweeps.tables import read_csv
from tests.studies.sweeps.cli_runs import ROOT, run, spec_of, study_argv

pytestmark = pytest.mark.skipif(not memory.available(), reason="needs /proc/self/status")

#: A worker with the fake evaluator holds ~0.09 GB (measured); 0.3 GB leaves room for it, and the
#: point of chamber radius 4 allocates 0.5 GB, 25 MB at a time.
LIMIT_GB, HOG_MB = 0.3, 500


@pytest.mark.parametrize("workers", ["1", "2"])
def test_a_point_above_the_limit_fails_naming_the_memory_and_the_sweep_goes_on(tmp_path, workers):
    done = run(study_argv(tmp_path, "--workers", workers, "--max-memory", str(LIMIT_GB)),
               env={"SOFTCRAWL_FAKE_HOG": f"4:{HOG_MB}"})  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    rows = {float(r["chamber_radius"]): r for r in read_csv(f"{spec_of(tmp_path).out_dir}/curves.csv")}
    assert rows[4.0]["trial_status"] == "failed"
    peak = float(rows[4.0]["peak_rss_gb"])
    assert LIMIT_GB < peak < HOG_MB / 1024 and rows[4.0]["reason"] == memory.reason(peak, LIMIT_GB)
    # the reading that stops the point lands between the limit and the allocation's next 25 MB step,
    # or later on a loaded machine (it once printed 0.4 GB): the reason names the reading it saw
    assert re.match(r"out of memory at 0\.[3-5] GB \(limit 0\.3 GB\)", rows[4.0]["reason"])
    assert rows[4.0]["reason"].split(" (")[0] in done.stdout
    for r in (2.0, 3.0, 5.0, 6.0):
        assert rows[r]["trial_status"] == "completed" and 0 < float(rows[r]["peak_rss_gb"]) < LIMIT_GB


def test_without_a_limit_the_peak_is_recorded_and_nothing_fails(tmp_path):
    done = run(study_argv(tmp_path), env={"SOFTCRAWL_FAKE_HOG": "4:100"})
    assert done.returncode == 0, done.stderr
    rows = {float(r["chamber_radius"]): r for r in read_csv(f"{spec_of(tmp_path).out_dir}/curves.csv")}
    assert {r["trial_status"] for r in rows.values()} == {"completed"}
    assert float(rows[4.0]["peak_rss_gb"]) > float(rows[2.0]["peak_rss_gb"]) + 0.05


def test_an_evaluation_that_cannot_be_interrupted_ends_its_process_after_recording_why():
    """Outside the main thread no handler can raise: the watchdog records the reason and ends the
    process with `EXIT_OUT_OF_MEMORY`, as the kernel's out-of-memory killer would, but with a
    reason the sweep keeps."""
    code = textwrap.dedent(
        """
        import threading, time
        import numpy as np
        from softcrawl.studies.sweeps.memory import MemoryWatch

        def evaluate():
            with MemoryWatch(0.05, on_hard_stop=lambda why: print(why, flush=True)):
                held = [np.ones(2**22) for _ in range(20)]  # 0.67 GB
                time.sleep(30)

        t = threading.Thread(target=evaluate)
        t.start()
        t.join()
        """
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert done.returncode == memory.EXIT_OUT_OF_MEMORY
    assert done.stdout.startswith("out of memory at ") and done.stdout.strip().endswith("(limit 0.05 GB)")


def test_a_hard_stop_of_a_single_worker_ends_its_child_process_not_the_command(tmp_path):
    """An evaluation stuck in one C call (1.5 GB allocated at once) cannot be interrupted: the
    watchdog ends its process with 137. With --workers 1 and --max-memory the point runs in a
    child worker (the pool's path), so the command itself lives on: one line naming the dead
    worker, exit 1 (it was 137 and no line when the point ran in the command's own process); the
    failure is recorded with its reason, and the same command finishes the other points."""
    argv = study_argv(tmp_path, "--workers", "1", "--max-memory", str(LIMIT_GB))
    done = run(argv, env={"SOFTCRAWL_FAKE_HOG": "4:1500:block"})
    assert done.returncode == 1, done.stderr
    assert done.stderr.splitlines() == [
        "softcrawl study chamber-radius: error: 1 of 1 workers died (exit codes [137]) (137: the memory "
        "watchdog's stop or the kernel's out-of-memory kill); run the same command to resume"
    ]
    again = run(argv)
    assert again.returncode == 0, again.stderr
    rows = {float(r["chamber_radius"]): r for r in read_csv(f"{spec_of(tmp_path).out_dir}/curves.csv")}
    assert rows[4.0]["trial_status"] == "failed"
    assert rows[4.0]["reason"].startswith("out of memory at ") and rows[4.0]["reason"].endswith(
        "(limit 0.3 GB)"
    )
    assert {rows[r]["trial_status"] for r in (2.0, 3.0, 5.0, 6.0)} == {"completed"}
