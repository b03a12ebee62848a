"""Study benchmark (issue 31): the wall time and peak memory of the ring study and the workspace.

    python bench/study_bench.py rings [--workers 2] [--quick]
    python bench/study_bench.py workspace [--quick] [--reference DIR]

Each study runs as `softcrawl study ...` would, in its own process, into a temporary folder:
  rings      `softcrawl study rings --workers N` (five ring counts, a mesh each, two load cases);
  workspace  `softcrawl study workspace` (every continuation path from zero load).
Printed: the command, the load average at the start, the wall time, the peak resident memory of
the largest process (a worker's, with --workers), and for the workspace with --reference (a
folder holding a workspace.csv, e.g. the committed results/robot-workspace/<material>/) the
largest difference of the FE end points from it, in mm (a rerun reproduces its states).
"""

from __future__ import annotations

import argparse
import csv
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _command(args, out: Path) -> list[str]:
    workers = ["--workers", str(args.workers)] if args.study == "rings" else []
    quick = ["--quick"] if args.quick else []
    return [sys.executable, "-m", "softcrawl", "study", args.study, *workers, "--out", str(out), *quick]


def _end_points(path: Path) -> dict:
    with open(path, newline="") as f:
        return {
            (r["P1_kpa"], r["P2_kpa"], r["P3_kpa"]): [float(r[f"fe_{c}"]) for c in "xyz"]
            for r in csv.DictReader(f)
        }


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study", choices=("rings", "workspace"))
    ap.add_argument("--workers", type=int, default=2, help="rings: sweep workers (default 2)")
    ap.add_argument("--quick", action="store_true", help="the quick mesh (and grid)")
    ap.add_argument("--reference", type=Path, help="workspace: a folder with the workspace.csv to compare")
    args = ap.parse_args(argv)
    if args.reference is not None and not (args.reference / "workspace.csv").is_file():
        ap.exit(2, f"study_bench: --reference: no workspace.csv in {args.reference}\n")
    print(f"$ python bench/study_bench.py {' '.join(sys.argv[1:] if argv is None else argv)}")
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores at the start")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        env = os.environ | {"MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}
        t0 = time.perf_counter()
        proc = subprocess.run(_command(args, out), env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024**2
        lines = [ln for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip() and "%|" not in ln]
        tail = lines[-4:]  # the study's own last lines, progress bars left out
        print(*(f"  {line}" for line in tail), sep="\n")
        print(f"{args.study}: exit {proc.returncode}, wall {wall / 60:.1f} min ({wall:.0f} s), "
              f"peak RSS {rss:.2f} GB (largest process)")  # fmt: skip
        if args.study == "workspace" and args.reference is not None:
            folder = next(out.glob("robot-workspace/*/workspace.csv"), None)
            if folder is None:
                print("no workspace.csv written")
                return
            new, ref = _end_points(folder), _end_points(args.reference / "workspace.csv")
            common = new.keys() & ref.keys()
            diff = max((abs(a - b) for k in common for a, b in zip(new[k], ref[k])), default=float("nan"))
            print(f"against {args.reference}: {len(common)} common points, largest end-point difference "
                  f"{diff:.2e} mm")  # fmt: skip


if __name__ == "__main__":
    main()
