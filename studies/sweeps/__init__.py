"""Sweeps and optimisations on optuna, with no knowledge of what they evaluate.

`spec` (what a study is), `storage` and `locks` (where it lives), `queue` (which points are done,
pending or missing), `worker` and `pool` (who evaluates them), `sweep` and `search` (run or
resume), `tables` (the CSV table), `faults` (interrupts and faults of the machine).
docs/decisions/021-sweeps.md lists each guarantee and the mechanism that carries it.
"""
