"""--storage problems end in one line naming the option; the study lock; atomic outputs."""

from __future__ import annotations

import errno
import sqlite3

import pytest

pytest.importorskip("optuna")

from softcrawl.files import atomic_path, write_text_atomic
from softcrawl.studies.cli import main
from softcrawl.studies.sweeps.faults import machine_fault
from softcrawl.studies.sweeps.locks import FileLock
from softcrawl.studies.sweeps.spec import StudyError
from tests.studies.sweeps.cli_runs import study_argv


@pytest.mark.parametrize(
    "url, expected",
    [
        ("nosuchdb://user@host/db", "unknown database dialect"),
        ("postgresql://user@host:notaport/db", "not a database URL"),
        ("mysql://user:secret@127.0.0.1/db", "needs the Python package 'MySQLdb'"),
        ("sqlite:///{tmp}/a-file/study.db", "File exists: '{tmp}/a-file'"),
        ("postgresql://user:secret@host:port/db", "not a database URL: postgresql://user:***@host:port/db"),
    ],
)
def test_storage_problems_are_one_line(tmp_path, capsys, url, expected):
    (tmp_path / "a-file").write_text("not a folder")
    assert main(study_argv(tmp_path, "--storage", url.format(tmp=tmp_path))) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("softcrawl study: error: storage: "), err
    assert expected.format(tmp=tmp_path) in err and "secret" not in err


def test_file_lock_wait_is_bounded(tmp_path):
    holder, waiter = FileLock(tmp_path / "x.lock"), FileLock(tmp_path / "x.lock", timeout_s=0.3)
    with holder:
        with pytest.raises(StudyError) as err:
            waiter.acquire()
    assert err.value.parameter == "storage" and "busy" in str(err.value)
    with waiter, waiter:  # re-entrant once free
        pass


def test_machine_faults_are_told_from_failed_evaluations(tmp_path):
    full = OSError(errno.ENOSPC, "No space left on device", "/out/x.vtu")
    assert machine_fault(full) == "disk full: No space left on device: /out/x.vtu"
    try:
        raise RuntimeError("writing the shape failed") from full
    except RuntimeError as wrapped:
        assert machine_fault(wrapped).startswith("disk full")
    assert machine_fault(sqlite3.OperationalError("database or disk is full")).startswith("disk full")
    assert machine_fault(PermissionError(errno.EACCES, "Permission denied", "/ro")).startswith("cannot write")
    assert machine_fault(FileNotFoundError(errno.ENOENT, "No such file", "x")) is None
    assert machine_fault(ValueError("diverged")) is None


def test_atomic_writes_leave_the_old_file_or_the_new_one(tmp_path):
    target = tmp_path / "table.csv"
    write_text_atomic(target, "old\n")
    with pytest.raises(OSError), atomic_path(target) as temp:
        temp.write_text("half of the new")
        raise OSError(errno.ENOSPC, "No space left on device")
    assert target.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["table.csv"]
