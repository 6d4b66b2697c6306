"""``spatch-dask CLOUD PLAN OUT``: a plan's tiles on a Dask cluster."""

from __future__ import annotations

import argparse
import sys
import time

from .runner import run_plan


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="spatch-dask",
        description="Convert every tile of a spatch plan as dask.distributed tasks, then "
        "write OUT/index.json (paths must be reachable by every worker, or fsspec URLs).",
    )
    parser.add_argument("cloud", help="the input point cloud (as given to spatch plan)")
    parser.add_argument("plan", help="the plan (spatch plan ... -o plan.json)")
    parser.add_argument("out", help="the output folder (tile_00000.spatch, ..., index.json)")
    parser.add_argument("--scheduler", help="a scheduler address (default: a LocalCluster)")
    parser.add_argument("--workers", type=int, default=2, help="LocalCluster workers (default 2)")
    parser.add_argument("--threads", type=int, default=1, help="spatch --threads per task")
    parser.add_argument("--retries", type=int, default=2, help="reruns of a failed tile")
    parser.add_argument("--spatch", default="spatch", help="the spatch binary")
    args, extra = parser.parse_known_args(argv)
    started = time.monotonic()
    try:
        results = run_plan(
            args.cloud, args.plan, args.out, spatch=args.spatch, scheduler=args.scheduler,
            workers=args.workers, threads=args.threads, retries=args.retries, extra_args=extra,
        )
    except (RuntimeError, OSError) as e:
        print(f"spatch-dask: error: {e}", file=sys.stderr)
        return 2
    total = sum(r.bytes for r in results)
    print(f"{args.out}: {len(results)} tiles, {total} bytes in {time.monotonic() - started:.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
