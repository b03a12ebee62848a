"""Measure the races that decide where the sweep engine needs its study lock
(docs/decisions/022-study-lock.md).

For SQLite (a file in WAL mode, opened as the engine opens it) and PostgreSQL (a throwaway server
on 127.0.0.1, see tests/studies/sweeps/pg_server.py), N processes released together by a barrier:

1. schema: each creates optuna's RDBStorage on an empty database -> processes that fail;
2. pop: each calls plain `study.ask()` on a queue of enqueued trials until the queue is empty
   -> trials popped by two processes, and fresh (unqueued) trials created by an ask that found
   the queue emptied between its look and its pop ("strays");
3. enqueue: each enqueues the grid points it sees missing (optuna's enqueue_trial, no lock)
   -> points queued twice;

each without the lock, then with the engine's lock (`studies.sweeps.locks`).

    python bench/storage_races.py [--processes 4] [--repeats 10]
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import tempfile
import warnings
from collections import Counter
from pathlib import Path

N_POINTS = 12


def _quiet():
    import optuna

    warnings.filterwarnings("ignore")
    optuna.logging.set_verbosity(optuna.logging.ERROR)


def _storage(url):
    import optuna

    from softcrawl.studies.sweeps.storage import _SqliteConnect, sqlite_path

    db = sqlite_path(url)
    kwargs = {"creator": _SqliteConnect(str(db))} if db else None
    return optuna.storages.RDBStorage(url, engine_kwargs=kwargs)


def _lock(url):
    from softcrawl.studies.sweeps.storage import _make_locks

    return _make_locks(url, "race")[1]


def _schema(url, barrier, out, locked=False):
    _quiet()
    if locked:
        from softcrawl.studies.sweeps.storage import _make_locks

        schema_lock = _make_locks(url, "race")[0]
    barrier.wait()
    try:
        if locked:
            with schema_lock:
                _storage(url)
        else:
            _storage(url)
        out.put("ok")
    except Exception as exc:  # noqa: BLE001 - the failure is what is measured
        out.put(type(exc).__name__)


def _pop(url, barrier, out, locked):
    """Pop like a worker: look for a WAITING trial, and ask only if there is one."""
    import contextlib

    import optuna

    _quiet()
    study = optuna.load_study(study_name="race", storage=_storage(url))
    lock = _lock(url) if locked else contextlib.nullcontext()
    barrier.wait()
    popped = []
    while True:
        with lock:
            waiting = study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.WAITING,))
            trial = study.ask() if waiting else None
        if trial is None:
            break
        popped.append(trial.user_attrs.get("i", -1))
        try:
            study.tell(trial, 0.0)
        except (ValueError, RuntimeError):  # another process popped and finished it too
            pass
    out.put(popped)


def _enqueue(url, barrier, out, locked):
    import contextlib

    import optuna

    _quiet()
    study = optuna.load_study(study_name="race", storage=_storage(url))
    lock = _lock(url) if locked else contextlib.nullcontext()
    barrier.wait()
    with lock:
        seen = {t.user_attrs.get("i") for t in study.get_trials(deepcopy=False)}
        for i in range(N_POINTS):
            if i not in seen:
                study.enqueue_trial({"x": float(i)}, user_attrs={"i": i})
    out.put(0)


def _spawn(target, url, n, *extra):
    ctx = mp.get_context("spawn")
    barrier, out = ctx.Barrier(n), ctx.Queue()
    procs = [ctx.Process(target=target, args=(url, barrier, out, *extra)) for _ in range(n)]
    for p in procs:
        p.start()
    results = [out.get(timeout=120) for _ in procs]
    for p in procs:
        p.join()
    return results


def _fresh_study(url, enqueue=True):
    import optuna

    _quiet()
    study = optuna.create_study(study_name="race", storage=_storage(url))
    if enqueue:
        for i in range(N_POINTS):
            study.enqueue_trial({"x": float(i)}, user_attrs={"i": i})
    return study


def measure(make_url, n, repeats, label):
    for locked in (False, True):
        fails = Counter()
        for _ in range(repeats):
            fails.update(r for r in _spawn(_schema, make_url(), n, locked) if r != "ok")
        how = "with" if locked else "without"
        print(f"{label} schema {how} lock, {n} processes x {repeats}: failed processes {dict(fails) or 0}")
    for locked in (False, True):
        dup = stray = 0
        for _ in range(repeats):
            url = make_url()
            _fresh_study(url)
            counts = Counter(i for popped in _spawn(_pop, url, n, locked) for i in popped)
            stray += counts.pop(-1, 0)
            dup += sum(c - 1 for c in counts.values())
        how = "with" if locked else "without"
        print(f"{label} pop {how} lock: {dup} trials popped twice, {stray} strays")
    for locked in (False, True):
        twice = 0
        for _ in range(repeats):
            url = make_url()
            study = _fresh_study(url, enqueue=False)
            _spawn(_enqueue, url, n, locked)
            twice += sum(c - 1 for c in Counter(t.user_attrs["i"] for t in study.get_trials()).values())
        print(f"{label} enqueue {'with' if locked else 'without'} lock: {twice} points queued twice")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--processes", type=int, default=4)
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        counter = iter(range(10**6))
        measure(lambda: f"sqlite:///{tmp}/race{next(counter)}.db", args.processes, args.repeats, "SQLite")
        sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
        from tests.studies.sweeps.pg_server import temporary_server, why_unavailable

        if why_unavailable():
            print(f"PostgreSQL: skipped ({why_unavailable()})")
            return
        with temporary_server(Path(tmp)) as url:
            import psycopg

            base, _, _ = url.rpartition("/")

            def make_url():
                name = f"race{next(counter)}"
                with psycopg.connect(base + "/postgres", autocommit=True) as c:
                    c.execute(f"CREATE DATABASE {name}")
                return f"{base}/{name}"

            measure(make_url, args.processes, args.repeats, "PostgreSQL")


if __name__ == "__main__":
    main()
