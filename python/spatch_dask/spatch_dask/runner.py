"""The tasks and the driver: one task per tile, then the index."""

from __future__ import annotations

import json
import os
import subprocess
import time
from dataclasses import dataclass
from typing import Optional, Sequence

from . import staging


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

    ``cloud``, ``plan`` and ``out_dir`` may be fsspec URLs: the input and the plan are
    then staged to a local folder (once per worker process) and the tile is uploaded
    after spatch wrote it (see :mod:`spatch_dask.staging`).
    Raises ``RuntimeError`` with spatch's message when it fails, so Dask can retry.
    spatch writes the tile atomically: a failed or killed attempt leaves no partial file.
    """
    name = tile_file_name(index)
    target = staging.join(out_dir, name)
    scratch = staging.scratch_folder() if staging.is_url(out_dir) else None
    path = os.path.join(scratch, name) if scratch else target
    started = time.monotonic()
    try:
        command = [
            spatch, "-q", "from-cloud", staging.local_copy(cloud),
            "--plan", staging.local_copy(plan), "--tile", str(index),
            "--threads", str(threads), "-o", path, *extra_args,
        ]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            message = done.stderr.strip()
            raise RuntimeError(f"tile {index}: spatch exited {done.returncode}: {message}")
        size = os.path.getsize(path)
        if scratch:
            staging.upload(path, target)
    finally:
        if scratch:
            staging.remove(scratch)
    return TileResult(index, target, size, time.monotonic() - started)


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

    ``cloud``, ``plan`` and ``out_dir`` are local paths every worker can reach, or fsspec
    URLs (``s3://bucket/city.las``, ``file:///data/out``): see :func:`convert_tile`.

    ``scheduler``: a scheduler address; ``None`` starts a LocalCluster of ``workers``
    processes. ``threads``: spatch's ``--threads`` in each task. ``retries``: how many
    times Dask reruns a failed tile. ``extra_args``: further ``from-cloud`` options (the
    same for every tile, e.g. ``--views 12``). Returns the tiles' results in plan order.
    """
    tiles = [t["index"] for t in json.loads(staging.read_text(plan))["tiles"]]
    staging.make_folder(out_dir)
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
    write_index(spatch, plan, out_dir, [r.path for r in results])
    return sorted(results, key=lambda r: r.index)


def write_index(spatch: str, plan: str, out_dir: str, tiles: Sequence[str]) -> None:
    """Runs ``spatch index PLAN OUT_DIR``; for a URL folder, on a local copy of its tiles,
    uploading ``index.json`` and ``coarse.spatch`` (the driver downloads every tile: the
    index needs their counts and the coarse level their patches)."""
    if not staging.is_url(out_dir):
        _index(spatch, plan, out_dir)
        return
    local = staging.scratch_folder()
    try:
        names = [t.rstrip("/").rsplit("/", 1)[-1] for t in tiles]
        staging.download_folder_files(out_dir, names, local)
        _index(spatch, staging.local_copy(plan), local)
        for name in ("index.json", "coarse.spatch"):
            if os.path.exists(os.path.join(local, name)):
                staging.upload(os.path.join(local, name), staging.join(out_dir, name))
    finally:
        staging.remove(local)


def _index(spatch: str, plan: str, folder: str) -> None:
    done = subprocess.run([spatch, "-q", "index", plan, folder], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"spatch index failed: {done.stderr.strip()}")
