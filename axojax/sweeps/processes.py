"""Which chunks of a sweep this process computes, and the barriers between processes.

A sweep started in every process of a ``jax.distributed`` job (one process per host, or
one per GPU) splits its chunks round-robin: process ``i`` of ``n`` computes chunks
``i, i + n, i + 2n, ...`` on its own local devices and writes them into the shared
``FILE.npz.parts/`` directory (a file system that every process sees). No collective
operation runs between processes; they meet only at three barriers of the
``jax.distributed`` coordination service:

1. after process 0 has prepared ``FILE.npz.parts/`` (removed one left by a different
   sweep, written the manifest),
2. after every process has loaded the finished chunks and merged them (in grid order,
   the same arrays in every process),
3. so process 0 writes ``FILE.npz`` and removes the parts only when nobody reads them.

Between 1 and 2 each process waits on the file system for the other processes'
chunks (no barrier timeout can cut a long sweep short; a process that dies takes the
job down through the coordination service's heartbeat).
"""

from __future__ import annotations

import dataclasses
import itertools
import pathlib
import time

import jax

BARRIER_TIMEOUT_S = 3600
"""Barriers 1 and 3 wait for file-system work only (manifest, loading the chunks)."""

_barrier_ids = itertools.count()


@dataclasses.dataclass(frozen=True)
class Share:
    """This process's place in the job: ``index`` of ``count`` processes."""

    index: int = 0
    count: int = 1

    def __post_init__(self):
        if not 0 <= self.index < self.count:
            raise ValueError(f"process index {self.index} is not in 0..{self.count - 1}")

    @property
    def leader(self) -> bool:
        return self.index == 0

    def owns(self, chunk: int) -> bool:
        return chunk % self.count == self.index

    @classmethod
    def current(cls) -> "Share":
        """From ``jax.distributed`` (index 0 of 1 when it is not initialised)."""
        return cls(jax.process_index(), jax.process_count())


def _client():
    from jax._src import distributed  # the coordination service's client (as orbax uses it)

    return distributed.global_state.client


def barrier(share: Share, name: str, timeout_s: float = BARRIER_TIMEOUT_S) -> None:
    """Wait until every process of the job reaches this barrier (no-op for one process).
    Every process must call the same barriers in the same order."""
    if share.count == 1:
        return
    client = _client()
    if client is None:
        raise RuntimeError(
            "a sweep over several processes needs jax.distributed.initialize() in every process"
        )
    client.wait_at_barrier(f"axojax_sweep_{next(_barrier_ids)}_{name}", int(timeout_s * 1000))


def wait_for_files(paths: list[pathlib.Path], poll_s: float = 0.2) -> None:
    """Block until every path exists (the chunks other processes write)."""
    pending = [p for p in paths if not p.exists()]
    while pending:
        time.sleep(poll_s)
        pending = [p for p in pending if not p.exists()]
