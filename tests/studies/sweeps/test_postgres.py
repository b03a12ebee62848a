"""Distributed sweeps on a real PostgreSQL server (started here on 127.0.0.1, see pg_server.py):
three workers started at the same moment on an empty database, as three machines would run
the same command, against the same sweep on SQLite."""

from __future__ import annotations

import subprocess
from collections import Counter

import pytest

from softcrawl.studies.sweeps.tables import read_csv
from tests.studies.sweeps import pg_server
from tests.studies.sweeps.cli_runs import comparable, completed_once, run, spec_of, start, study_argv, trials

REASON = pg_server.why_unavailable()
pytestmark = pytest.mark.skipif(REASON is not None, reason=f"PostgreSQL test skipped: {REASON}")


@pytest.fixture(scope="module")
def pg_url(tmp_path_factory):
    with pg_server.temporary_server(tmp_path_factory.mktemp("postgres")) as url:
        yield url


def _three_at_once(outs, storage, env):
    procs = [start(study_argv(out, *storage), env=env) for out in outs]
    done = []
    for proc in procs:
        out, err = proc.communicate(timeout=300)
        done.append(subprocess.CompletedProcess(proc.args, proc.returncode, out, err))
    return done


def _curves(out):
    return read_csv(out / "chamber-radius" / "ecoflex-00-50-quick" / "curves.csv")


def test_three_workers_on_an_empty_database_share_one_sweep(pg_url, tmp_path):
    log = tmp_path / "log"
    env = {"SOFTCRAWL_FAKE_SLEEP": "1", "SOFTCRAWL_FAKE_LOG": str(log)}
    machines = [tmp_path / f"machine{i}" for i in range(3)]
    done = _three_at_once(machines, ["--storage", pg_url], env)
    assert [d.returncode for d in done] == [0, 0, 0], [d.stderr for d in done]
    assert all("Traceback" not in d.stderr for d in done)
    spec = spec_of(machines[0], storage=pg_url)
    assert completed_once(spec)
    assert len(trials(spec)) == len(spec.points())  # each point queued once: no extra trial
    evaluated = Counter(line.rsplit(",", 1)[0] for line in log.read_text().splitlines())
    assert sorted(evaluated.values()) == [1] * 5  # each point computed once
    # the same sweep on SQLite, three processes sharing one file, gives the same table
    local = tmp_path / "sqlite"
    sqlite_done = _three_at_once([local] * 3, [], {"SOFTCRAWL_FAKE_SLEEP": "0.3"})
    assert [d.returncode for d in sqlite_done] == [0, 0, 0], [d.stderr for d in sqlite_done]
    assert completed_once(spec_of(local))
    reference = comparable(_curves(local))
    for machine in machines:
        assert comparable(_curves(machine)) == reference


def test_bad_password_and_closed_port_are_one_line_naming_storage(pg_url, tmp_path):
    wrong = pg_url.replace(f":{pg_server.PASSWORD}@", ":not-the-password@")
    port = pg_url.rsplit(":", 1)[1].split("/")[0]
    closed = pg_url.replace(f":{port}/", ":1/")
    for url, expected in ((wrong, "password authentication failed"), (closed, "refused")):
        done = run(study_argv(tmp_path, "--storage", url))
        lines = done.stderr.splitlines()
        assert done.returncode == 2 and len(lines) == 1, done.stderr
        assert lines[0].startswith("softcrawl study: error: storage: cannot use postgresql://softcrawl:***@")
        assert expected in lines[0] and "not-the-password" not in lines[0]
