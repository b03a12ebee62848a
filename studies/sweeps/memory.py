"""Resident memory of a sweep worker: the peak of each point, and the `--max-memory` limit.

An address-space limit (``RLIMIT_AS``) counts reserved, never touched memory (PARDISO and the
BLAS threads reserve gigabytes they do not use), and cgroups are often not available in
containers; so the limit is a watchdog on the resident set. While a point is evaluated a thread
reads this process's ``VmRSS`` (``/proc/self/status``) every `SAMPLE_S` seconds and keeps its
peak; the peak is stored with the trial (``peak_rss_gb``) and shown in the study's tables, so a
user can choose ``--workers`` (workers x peak must fit in the machine's memory).

Above the limit the watchdog sends this process SIGUSR1; the handler raises `OutOfMemory` in the
main thread, inside the evaluation, and the worker records the point as a failed result, "out of
memory at N.N GB (limit M GB)", with the last converged state where the evaluator exposes one
(it catches `OutOfMemory`, fills ``last_state`` and re-raises); the sweep goes on with the other
points. Python runs the handler only between bytecodes: an evaluation stuck in one C call (a
factorisation) cannot be interrupted. If the resident set passes `HARD_FACTOR` x the limit, or
the main thread has not stopped `HARD_WAIT_S` s after the signal, the watchdog records the same
failure on the trial itself and ends the process (exit code `EXIT_OUT_OF_MEMORY`); the parent and
the other workers find its trial RUNNING with a dead worker and fail it, the recorded reason
kept (`studies.sweeps.queue`).

Where ``/proc`` is missing the peak is empty and no limit can be enforced (the command refuses
``--max-memory`` there).
"""

from __future__ import annotations

import os
import signal
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

#: Seconds between two samples of the resident set.
SAMPLE_S = 0.1
#: The watchdog ends the process when the resident set passes this multiple of the limit ...
HARD_FACTOR = 1.5
#: ... or when the evaluation has not stopped this long (s) after the signal.
HARD_WAIT_S = 60.0
#: Exit code of a worker ended by the watchdog (128 + SIGKILL, what an out-of-memory kill gives).
EXIT_OUT_OF_MEMORY = 137
GB = 1e9

_limit_gb: float | None = None


def rss_bytes(pid: int | str = "self") -> int | None:
    """The resident set (bytes) of process `pid`, or None where /proc cannot tell."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def available() -> bool:
    return rss_bytes() is not None


def limit_gb() -> float | None:
    """This process's limit per worker (GB), None for none."""
    return _limit_gb


def set_limit_gb(value: float | None) -> None:
    global _limit_gb
    _limit_gb = None if value is None else float(value)


class worker_memory_limit:
    """``with worker_memory_limit(gb):`` the sweeps run inside use that limit per worker (the
    pool hands it to its spawned workers)."""

    def __init__(self, value: float | None) -> None:
        self.value = value

    def __enter__(self) -> None:
        self._previous = limit_gb()
        set_limit_gb(self.value)

    def __exit__(self, *exc: object) -> None:
        set_limit_gb(self._previous)


def reason(peak_gb: float, limit: float) -> str:
    return f"out of memory at {peak_gb:.1f} GB (limit {limit:g} GB)"


class OutOfMemory(BaseException):
    """The resident set passed the limit during an evaluation. A BaseException, like
    `studies.sweeps.faults.Interrupted`, so that an evaluator's ``except Exception`` cannot swallow
    it; an evaluator may fill ``last_state`` (JSON-able attributes) and re-raise."""

    def __init__(self, peak_gb: float, limit: float) -> None:
        super().__init__(reason(peak_gb, limit))
        self.peak_gb, self.limit_gb = peak_gb, limit
        self.last_state: dict[str, Any] = {}

    @property
    def reason(self) -> str:
        return reason(self.peak_gb, self.limit_gb)


class MemoryWatch:
    """The watchdog around one evaluation (module docstring): ``peak_gb`` after it; with a limit,
    `OutOfMemory` inside it. ``on_hard_stop(reason)`` records the failure before the process ends."""

    def __init__(self, limit: float | None = None, on_hard_stop: Callable[[str], None] | None = None):
        self.limit, self.on_hard_stop = limit, on_hard_stop
        self.peak = rss_bytes() or 0
        self._stop = threading.Event()
        self._armed = False
        self._signalled_at: float | None = None
        self._previous: Any = None

    @property
    def peak_gb(self) -> float | None:
        return self.peak / GB if available() else None

    def _handler(self, signum: int, frame: object) -> None:
        if self._armed:
            self._armed = False
            raise OutOfMemory(self.peak / GB, self.limit)

    def __enter__(self) -> MemoryWatch:
        can_signal = threading.current_thread() is threading.main_thread()
        if self.limit is not None and can_signal:
            self._previous = signal.signal(signal.SIGUSR1, self._handler)
            self._armed = True
        self._thread = threading.Thread(target=self._watch, name="memory-watchdog", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()
        self._armed = False
        if self._previous is not None:
            signal.signal(signal.SIGUSR1, self._previous)
        rss = rss_bytes()
        self.peak = max(self.peak, rss or 0)

    def _watch(self) -> None:
        while not self._stop.wait(SAMPLE_S):
            rss = rss_bytes()
            if rss is None:
                return
            self.peak = max(self.peak, rss)
            if self.limit is None or rss <= self.limit * GB:
                continue
            now = time.monotonic()
            if self._signalled_at is None and self._armed:
                self._signalled_at = now
                os.kill(os.getpid(), signal.SIGUSR1)
            elif self._signalled_at is None or (
                rss > HARD_FACTOR * self.limit * GB or now - self._signalled_at > HARD_WAIT_S
            ):
                self._hard_stop()  # no handler (not the main thread), or it does not respond

    def _hard_stop(self) -> None:
        if self._stop.is_set():
            return
        try:
            if self.on_hard_stop is not None:
                self.on_hard_stop(reason(self.peak / GB, self.limit))
        finally:
            os._exit(EXIT_OUT_OF_MEMORY)
