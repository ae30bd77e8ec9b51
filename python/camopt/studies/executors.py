"""Where a study's points run: in this process, on the local cores, or on a Dask cluster.

Every point is independent and deterministic, so the three give the same table point by point;
the points go out in batches (fewer round trips) and the results come back in point order.
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import os
from typing import Callable

from .pipeline import PointResult, evaluate_batch
from .spec import StudyInputError, StudySpec

Batch = list[tuple[int, tuple[float, ...]]]
Progress = Callable[[int, int], None]


def batches(points: list[tuple[float, ...]], first_index: int, count: int) -> list[Batch]:
    """`points` numbered from `first_index`, cut into about `count` batches of consecutive points."""
    numbered = [(first_index + i, tuple(float(v) for v in p)) for i, p in enumerate(points)]
    size = max(1, -(-len(numbered) // max(1, count)))
    return [numbered[i:i + size] for i in range(0, len(numbered), size)]


def _collect(futures, total: int, progress: Progress | None, next_result) -> list[PointResult]:
    results: list[PointResult] = []
    for batch_result in next_result(futures):
        results.extend(batch_result)
        if progress:
            progress(len(results), total)
    return sorted(results, key=lambda r: r.index)


def run_serial(spec: StudySpec, points: list[tuple[float, ...]], first_index: int = 0,
               progress: Progress | None = None) -> list[PointResult]:
    """Every point in this process, one after the other (each sweep on all cores)."""
    results = []
    for batch in batches(points, first_index, len(points)):
        results.extend(evaluate_batch(spec, batch, threads=0))
        if progress:
            progress(len(results), len(points))
    return results


def run_local(spec: StudySpec, points: list[tuple[float, ...]], workers: int, first_index: int = 0,
              progress: Progress | None = None) -> list[PointResult]:
    """The points on `workers` local processes (spawned: a fresh interpreter each, no fork of a
    threaded process), one sweep thread per point."""
    if workers < 1:
        raise StudyInputError(f"--workers: {workers}: must be >= 1")
    if workers == 1 or len(points) <= 1:
        return run_serial(spec, points, first_index, progress)
    context = multiprocessing.get_context("spawn")
    work = batches(points, first_index, 4 * workers)
    with concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(evaluate_batch, spec, b, 1) for b in work]
        return _collect(futures, len(points), progress,
                        lambda fs: (f.result() for f in concurrent.futures.as_completed(fs)))


def run_dask(spec: StudySpec, points: list[tuple[float, ...]], client=None, scheduler: str | None = None,
             first_index: int = 0, progress: Progress | None = None) -> list[PointResult]:
    """The points on a Dask distributed cluster: a `client` of the caller's, or a client of the
    scheduler at `scheduler` (tcp://HOST:PORT) closed on return. The workers must import the same
    camopt (docs/studies.md)."""
    from distributed import Client, as_completed

    own = client is None
    if own:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as e:
            raise StudyInputError(f"--scheduler: {scheduler}: no Dask scheduler answers there ({e})") from None
    try:
        workers = max(1, len(client.scheduler_info().get("workers", {})))
        work = batches(points, first_index, 4 * workers)
        futures = client.map(evaluate_batch, [spec] * len(work), work, [1] * len(work), pure=False)
        return _collect(futures, len(points), progress, lambda fs: (f.result() for f in as_completed(fs)))
    finally:
        if own:
            client.close()


def default_workers() -> int:
    """All the cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1
