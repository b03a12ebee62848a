"""Worker processes on this machine: start them, stop them on a signal, gather their reports.

Workers are spawned (a fresh interpreter each: safe with threads, and the same on every OS); the
target is a module-level function ``target(spec_dict, index, poll_s) -> WorkerReport`` that the
child imports by name. A child prints nothing: its report, or the one line of an exception it
did not expect, goes to the parent through a queue.

Ctrl-C reaches every process of the terminal's process group: the workers start with SIGINT
ignored (a disposition that survives ``exec``) until their own handler is installed, so none dies
with a KeyboardInterrupt traceback while it imports. After a signal the parent sends SIGTERM (the
workers hand their points back at once) and waits at most `STOP_WAIT_S`, then kills the rest
(their points are failed at once by the next run on this machine, which sees their processes
gone).

Workers die with their parent. A parent killed outright (kill -9 of its pid alone, as a job
scheduler or the kernel's out-of-memory killer does) cannot signal its workers, which would run on
as orphans of PID 1. Each worker therefore asks the kernel for SIGTERM when its parent dies
(Linux ``prctl(PR_SET_PDEATHSIG)``, `die_with_parent`), then checks that its parent is still the
pid that started it (the parent may have died before the request); elsewhere a watchdog thread
polls the parent's pid once a second. SIGTERM reaches the worker's `SignalGuard`: the point is
handed back as after Ctrl-C, and the next run computes it.

Threads: the workers start with `fem.parallel.worker_env(workers)` in their environment (the
threads policy's assembly and MKL threads; the user's settings kept).
"""

from __future__ import annotations

import ctypes
import dataclasses
import os
import signal
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

from softcrawl.fem.parallel import worker_env
from softcrawl.studies.sweeps import memory
from softcrawl.studies.sweeps.faults import SignalGuard, WorkerReport

#: Longest wait (s) for the workers to stop after a signal.
STOP_WAIT_S = 30
#: prctl option of <linux/prctl.h>: the signal sent to this process when its parent dies.
PR_SET_PDEATHSIG = 1
#: Period (s) of the parent watchdog where prctl is not available.
WATCHDOG_S = 1.0


def die_with_parent(parent_pid: int) -> str:
    """Make this process receive SIGTERM when `parent_pid` dies; returns how ("prctl" or
    "watchdog"). If the parent is already gone, SIGTERM is sent at once."""
    how = "watchdog"
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            if libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0) == 0:
                how = "prctl"
        except (OSError, AttributeError):
            pass
    if how == "watchdog":
        watchdog = threading.Thread(target=_watch_parent, args=(parent_pid,), name="parent-watchdog")
        watchdog.daemon = True
        watchdog.start()
    if os.getppid() != parent_pid:  # the parent died before the request: no signal would come
        os.kill(os.getpid(), signal.SIGTERM)
    return how


def _watch_parent(parent_pid: int) -> None:
    while os.getppid() == parent_pid:
        time.sleep(WATCHDOG_S)
    os.kill(os.getpid(), signal.SIGTERM)


def _child(
    target: Callable[..., WorkerReport],
    spec_dict: dict,
    index: int,
    poll_s: float,
    reports: Any,
    parent_pid: int | None = None,
    max_memory_gb: float | None = None,
) -> None:
    if parent_pid is not None:
        die_with_parent(parent_pid)
    memory.set_limit_gb(max_memory_gb)
    try:
        report = target(spec_dict, index, poll_s)
    except BaseException as exc:  # noqa: BLE001 - the parent prints the one line
        report = WorkerReport(stop=f"{type(exc).__name__}: {exc}")
    reports.put(dataclasses.asdict(report))


def run_pool(
    target: Callable[..., WorkerReport],
    spec_dict: dict[str, Any],
    workers: int,
    poll_s: float,
    on_tick: Callable[[], None] | None = None,
) -> tuple[WorkerReport, list[int]]:
    """Run ``workers`` processes of ``target``; returns their summed report and the exit codes of
    the workers that did not exit cleanly. ``on_tick`` runs every 0.2 s (a progress bar)."""
    import multiprocessing as mp

    ctx = mp.get_context("spawn")
    reports = ctx.Queue()
    extra = (os.getpid(), memory.limit_gb())  # the workers die with this process; their memory limit
    procs = [
        ctx.Process(target=_child, args=(target, spec_dict, i, poll_s, reports, *extra))
        for i in range(workers)
    ]
    total = WorkerReport()
    saved = dict(os.environ)
    with SignalGuard() as guard:
        handler = signal.signal(signal.SIGINT, signal.SIG_IGN)
        os.environ.update(worker_env(workers))  # the threads policy (fem.parallel), inherited at spawn
        try:
            for p in procs:
                p.start()
        finally:
            signal.signal(signal.SIGINT, handler)
            os.environ.clear()
            os.environ.update(saved)
        deadline = None
        while any(p.is_alive() for p in procs):
            if guard.signum and deadline is None:
                deadline = time.monotonic() + STOP_WAIT_S
                for p in procs:
                    if p.is_alive():
                        p.terminate()
            if deadline is not None and time.monotonic() > deadline:
                for p in procs:
                    if p.is_alive():
                        p.kill()
            time.sleep(0.2)
            if on_tick is not None:
                on_tick()
        for p in procs:
            p.join()
        total.signum = guard.signum
    for _ in procs:
        try:
            total.add(WorkerReport(**reports.get(timeout=5)))
        except Exception:  # noqa: BLE001 - a killed worker sends no report
            break
    return total, [p.exitcode for p in procs if p.exitcode]
