"""Threads policy benchmark (issue 31): N concurrent solves, as N sweep workers, under two policies.

    python bench/workers_bench.py [--workers 2] [--repeats 2]

Each "worker" is one Table 1 ePSA ramp (`bench/epsa_bench.py --only default`, its own process),
and the N workers start together. Policies, run in alternation (A B A B ...) so that a changing
load from other jobs hits both alike:

  shared  `fem.parallel.worker_env(N, "shared")`: each worker max(1, cores // N) assembly and
          MKL threads;
  greedy  `fem.parallel.worker_env(N, "greedy")` (nothing set): each worker as a lone process,
          the assembly pool on every core (at most 4) and MKL's default of a thread per physical
          core (what the workers did before issue 31).

`fem.parallel.WORKER_POLICY` names the one `studies.sweeps.pool` applies to `--workers N`.

Printed per run: the wall time until the last worker finished, and the ratio greedy / shared of
the medians. The same number of Newton iterations must show in every run (the length at 100 kPa
too, to the solver tolerance): a policy changes the speed, not the result.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from softcrawl.fem.parallel import THREAD_VARIABLES, worker_env  # noqa: E402


def run(workers: int, env: dict[str, str]) -> tuple[float, list[str]]:
    cmd = [sys.executable, str(ROOT / "bench" / "epsa_bench.py"), "--only", "default"]
    t0 = time.perf_counter()
    procs = [subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True) for _ in range(workers)]
    outs = [p.communicate()[0].strip().splitlines()[-1] for p in procs]
    return time.perf_counter() - t0, outs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=2)
    args = ap.parse_args()
    base = {k: v for k, v in os.environ.items() if k not in THREAD_VARIABLES}
    policies = {name: base | worker_env(args.workers, name) for name in ("shared", "greedy")}
    print(f"$ python {' '.join(sys.argv)}")
    load = os.getloadavg()[0]
    threads = {n: {k: policies[n].get(k, "-") for k in THREAD_VARIABLES} for n in policies}
    print(f"load average {load:.1f} on {os.cpu_count()} cores; {threads}")
    walls: dict[str, list[float]] = {name: [] for name in policies}
    for k in range(args.repeats):
        for name, env in policies.items():
            wall, outs = run(args.workers, env)
            walls[name].append(wall)
            print(f"{name:<7} run {k + 1}: {wall:6.1f} s; " + " | ".join(o[10:] for o in outs))
    med = {name: statistics.median(w) for name, w in walls.items()}
    print(f"median wall: shared {med['shared']:.1f} s, greedy {med['greedy']:.1f} s; greedy / shared = "
          f"{med['greedy'] / med['shared']:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
