"""Element work over chunks of elements, on a small thread pool.

numpy releases the GIL inside matmul and ufunc loops, so an element kernel written as batched
numpy operations over a chunk of elements runs concurrently with the same kernel on other chunks.
Chunks of ~100-200 elements also keep a kernel's temporaries in the core's cache (whole-mesh
temporaries of a 30 x 30 element matrix per element are tens of MB, and every numpy pass over
them goes to main memory). The pool has `SOFTCRAWL_THREADS` threads, else one per usable core
(at most 4); with one thread the chunks run in the calling thread. Measured on the 2-core
benchmark machine (3,840 P2 tets): the element tangent takes ~39 ms on one thread and ~24 ms on
two when the second core is free; when other jobs keep both cores busy, two threads are no faster
(nor slower) than one.

Only the assembly runs here: the linear solver (PARDISO) has its own threads.

Threads policy (docs/decisions/069-crawl-speed.md), stated here once. A process uses the usable
cores twice over, one after the other: its assembly pool (`threads()`, at most 4) while it
assembles, MKL's OpenMP threads (PARDISO, one per core) while it factorises; the two never run at
the same time. N worker processes (`--workers N`, `studies.sweeps.pool`) start with `worker_env(N)`:
under `WORKER_POLICY = "greedy"` each worker takes what a lone process takes (nothing is set;
on 2 cores: 2 assembly and 2 MKL threads per worker), so that a worker in a serial part of its work (Python,
GMRES's substitutions, the contact update) leaves its cores to the other one's parallel parts; MKL's
threads sleep at once after a parallel region (`fem.linsolve.KMP_BLOCKTIME_MS` = 0), so
over-subscribed factorisations do not spin against each other. "shared" gives each worker
max(1, cores // N) threads instead. Greedy was 9-14 % faster than shared in 3 of 4 alternated
pairs on the loaded 2-core machine (`bench/workers_bench.py`; the idle comparison is the lead's).
A variable the user set (SOFTCRAWL_THREADS, MKL_NUM_THREADS, OMP_NUM_THREADS) is always kept.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor, wait

_POOL: dict = {}  # pid -> (threads, executor); a forked child makes its own


#: The thread variables of `worker_env`: the assembly pool's, MKL's, OpenMP's (MKL's runtime).
THREAD_VARIABLES = ("SOFTCRAWL_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")


def cores() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def threads() -> int:
    forced = os.environ.get("SOFTCRAWL_THREADS")
    if forced:
        return max(1, int(forced))
    return max(1, min(cores(), 4))


#: The policy of `worker_env`: "greedy" or "shared" (module docstring, "Threads policy").
WORKER_POLICY = "greedy"


def worker_env(workers: int, policy: str | None = None) -> dict[str, str]:
    """The thread variables to set in each of `workers` processes on this machine (module
    docstring, "Threads policy") under `policy` (default `WORKER_POLICY`); a variable the user set
    is never among them. "greedy" sets none: each worker takes a lone process's defaults (the
    assembly pool's `threads()`, MKL's one thread per physical core)."""
    policy = policy or WORKER_POLICY
    if policy not in ("greedy", "shared"):
        raise ValueError(f"threads policy {policy!r} is not 'greedy' or 'shared'")
    if policy == "greedy":
        return {}
    share = str(max(1, cores() // max(1, int(workers))))
    return {name: share for name in THREAD_VARIABLES if not os.environ.get(name)}


def _executor(n: int):
    pid = os.getpid()
    entry = _POOL.get(pid)
    if entry is None or entry[0] != n:
        if entry is not None:
            entry[1].shutdown(wait=True)
        entry = (n, ThreadPoolExecutor(max_workers=n, thread_name_prefix="fem-assembly"))
        _POOL[pid] = entry
    return entry[1]


def for_chunks(fn, n_items: int, chunk: int) -> None:
    """Call fn(slice) for consecutive slices of at most `chunk` items covering range(n_items).

    The slices must write disjoint outputs. All calls finish before this returns; the first
    exception (in slice order) is then re-raised.
    """
    slices = [slice(i, min(i + chunk, n_items)) for i in range(0, n_items, chunk)]
    n = threads()
    if n == 1 or len(slices) == 1:
        for s in slices:
            fn(s)
        return
    futures = [_executor(n).submit(fn, s) for s in slices]
    wait(futures)
    for f in futures:
        f.result()
