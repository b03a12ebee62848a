"""What stops a run without being a result: an interrupt, a full disk, an unwritable output.

A failed *evaluation* (a diverged design, an invalid point) is a result and is kept. A fault of
the machine is not a property of the point: a full disk (``ENOSPC``, ``EDQUOT``), a read-only or
unwritable output (``EROFS``, ``EACCES``, ``EPERM``), a file too large (``EFBIG``) or an I/O error.
Such a point is handed back (its trial is failed with ``user_attrs["handed_back"]``, and the
point is queued again at once), the worker stops, and the command prints one line.

Signals: `SignalGuard` turns SIGINT (Ctrl-C) and SIGTERM into a flag. Inside
`SignalGuard.evaluating` (the evaluator call) they raise `Interrupted` at once, so a long
finite-element solve is abandoned and its point handed back immediately; elsewhere (database
writes) the flag is read at the next safe step, so no write is cut in half. `Interrupted` derives
from BaseException, like KeyboardInterrupt, so that an evaluator's ``except Exception`` cannot
swallow it.
"""

from __future__ import annotations

import contextlib
import errno
import signal
import sqlite3
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass

#: errno values that are faults of the machine, not of the evaluated point.
MACHINE_ERRNOS = frozenset(
    {errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM, errno.EFBIG, errno.EIO}
)
#: SQLite messages of the same kind.
SQLITE_MACHINE_FAULTS = ("disk is full", "readonly database", "disk i/o error", "unable to open database")


class Interrupted(BaseException):
    """SIGINT or SIGTERM arrived while a point was being evaluated."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


class MachineFault(Exception):
    """An evaluation hit a fault of the machine (see `machine_fault`); ``line`` says which."""

    def __init__(self, line: str):
        super().__init__(line)
        self.line = line


def machine_fault(exc: BaseException) -> str | None:
    """One line if ``exc`` (or an exception it was raised from) is a fault of the machine."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, OSError) and exc.errno in MACHINE_ERRNOS:
            where = f": {exc.filename}" if exc.filename else ""
            kind = "disk full" if exc.errno in (errno.ENOSPC, errno.EDQUOT) else "cannot write"
            return f"{kind}: {exc.strerror or exc}{where}"
        if isinstance(exc, sqlite3.Error) and any(m in str(exc).lower() for m in SQLITE_MACHINE_FAULTS):
            kind = "disk full" if "full" in str(exc).lower() else "cannot write"
            return f"{kind}: SQLite: {exc}"
        exc = getattr(exc, "orig", None) or exc.__cause__ or exc.__context__
    return None


@dataclass
class WorkerReport:
    """What one worker did, and why it stopped (``stop`` is empty when the queue ran dry)."""

    completed: int = 0
    failed: int = 0
    handed_back: int = 0
    gave_way: int = 0
    stop: str = ""
    signum: int = 0

    def add(self, other: WorkerReport) -> None:
        self.completed += other.completed
        self.failed += other.failed
        self.handed_back += other.handed_back
        self.gave_way += other.gave_way
        self.stop = self.stop or other.stop
        self.signum = self.signum or other.signum


class SignalGuard:
    """SIGINT and SIGTERM as a flag (``signum``), raising `Interrupted` only inside
    `evaluating`. Installed in the main thread only (elsewhere Python forbids handlers)."""

    def __init__(self) -> None:
        self.signum = 0
        self._raise = False
        self._previous: dict[int, object] = {}

    def _handler(self, signum: int, frame: object) -> None:
        self.signum = self.signum or signum
        if self._raise:
            self._raise = False
            raise Interrupted(signum)

    def __enter__(self) -> SignalGuard:
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._previous[sig] = signal.signal(sig, self._handler)
            # a signal that lands in a finalizer (a weakref callback) cannot interrupt: Python
            # prints it as "Exception ignored"; the flag is set anyway, so keep the terminal quiet
            self._unraisable = sys.unraisablehook
            sys.unraisablehook = self._quiet_unraisable
        return self

    def _quiet_unraisable(self, args: object) -> None:
        if not isinstance(getattr(args, "exc_value", None), Interrupted):
            self._unraisable(args)

    def __exit__(self, *exc: object) -> None:
        for sig, previous in self._previous.items():
            signal.signal(sig, previous)
        if self._previous:
            sys.unraisablehook = self._unraisable
        self._previous.clear()

    @contextlib.contextmanager
    def evaluating(self) -> Iterator[None]:
        """The region in which a signal interrupts at once."""
        if self.signum:
            raise Interrupted(self.signum)
        self._raise = True
        try:
            yield
        finally:
            self._raise = False


def interrupted_line(report: WorkerReport) -> str:
    """The one line of an interrupted run."""
    n = report.handed_back
    return f"interrupted: {n} point{'s' if n != 1 else ''} handed back; run the same command to resume"


def exit_code(report: WorkerReport) -> int:
    """128 + signal for an interrupt (the shell's convention), 1 for a fault."""
    return 128 + report.signum if report.signum else 1


class SweepStopped(RuntimeError):
    """A run that stopped before the queue was empty; ``line`` is its one-line account."""

    def __init__(self, report: WorkerReport):
        self.report = report
        if report.signum:
            line = interrupted_line(report)
        else:
            n = report.handed_back
            back = f"; {n} point{'s' if n != 1 else ''} handed back" if n else ""
            line = f"error: {report.stop}{back}; run the same command to resume"
        super().__init__(line)
        self.line, self.exit_code = line, exit_code(report)
