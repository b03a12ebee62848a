"""One benchmark case in its own spawned process, so that its peak resident memory is its own.

`in_child(target, *args)` runs `target(*args, queue)` in a spawned child and returns what the
child put on the queue. A child that dies first (out of memory, a missing optional package such as
FElupe) gives {"error": "the child exited with code N"} as soon as it is gone, instead of a wait
for a queue timeout of an hour or more.
"""

from __future__ import annotations

import multiprocessing as mp
from queue import Empty

POLL_S = 5.0  # how often a silent child is checked for life (s)


def in_child(target, *args) -> dict:
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=target, args=(*args, queue))
    proc.start()
    result = None
    while result is None:
        try:
            result = queue.get(timeout=POLL_S)
        except Empty:
            if not proc.is_alive():
                result = {"error": f"the child exited with code {proc.exitcode}"}
    proc.join()
    return result
