"""The tasks and the driver: one task per tile, then the index."""

from __future__ import annotations

import json
import os
import subprocess
import time
from dataclasses import dataclass
from typing import Optional, Sequence


def tile_file_name(index: int) -> str:
    """The file name spatch gives tile ``index`` in a run's folder."""
    return f"tile_{index:05d}.spatch"


@dataclass(frozen=True)
class TileResult:
    """What one tile's task reports."""

    index: int
    path: str
    bytes: int
    seconds: float


def convert_tile(
    spatch: str,
    cloud: str,
    plan: str,
    index: int,
    out_dir: str,
    threads: int = 1,
    extra_args: Sequence[str] = (),
) -> TileResult:
    """Converts tile ``index`` of ``plan`` with the ``spatch`` binary (a Dask task).

    Raises ``RuntimeError`` with spatch's message when it fails, so Dask can retry.
    spatch writes the tile atomically: a failed or killed attempt leaves no partial file.
    """
    path = os.path.join(out_dir, tile_file_name(index))
    command = [
        spatch, "-q", "from-cloud", cloud, "--plan", plan, "--tile", str(index),
        "--threads", str(threads), "-o", path, *extra_args,
    ]
    started = time.monotonic()
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"tile {index}: spatch exited {done.returncode}: {done.stderr.strip()}")
    return TileResult(index, path, os.path.getsize(path), time.monotonic() - started)


def _client(scheduler: Optional[str], workers: int):
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True)
    return Client(cluster), cluster


def run_plan(
    cloud: str,
    plan: str,
    out_dir: str,
    *,
    spatch: str = "spatch",
    scheduler: Optional[str] = None,
    workers: int = 2,
    threads: int = 1,
    retries: int = 2,
    extra_args: Sequence[str] = (),
) -> list[TileResult]:
    """Runs every tile of ``plan`` as a Dask task, then writes ``out_dir/index.json``.

    ``scheduler``: a scheduler address; ``None`` starts a LocalCluster of ``workers``
    processes. ``threads``: spatch's ``--threads`` in each task. ``retries``: how many
    times Dask reruns a failed tile. ``extra_args``: further ``from-cloud`` options (the
    same for every tile, e.g. ``--views 12``). Returns the tiles' results in plan order.
    """
    with open(plan, encoding="utf-8") as f:
        tiles = [t["index"] for t in json.load(f)["tiles"]]
    os.makedirs(out_dir, exist_ok=True)
    client, cluster = _client(scheduler, workers)
    try:
        futures = [
            client.submit(
                convert_tile, spatch, cloud, plan, k, out_dir, threads, tuple(extra_args),
                key=f"spatch-tile-{k}", retries=retries, pure=False,
            )
            for k in tiles
        ]
        results = client.gather(futures)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    done = subprocess.run([spatch, "-q", "index", plan, out_dir], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"spatch index failed: {done.stderr.strip()}")
    return sorted(results, key=lambda r: r.index)
