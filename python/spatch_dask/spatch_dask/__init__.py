"""Run a spatch tile plan on a dask.distributed cluster.

Each tile of a plan (``spatch plan``) becomes one task that calls
``spatch from-cloud INPUT --plan PLAN --tile K -o OUT/tile_K.spatch``; when every
tile is done, ``spatch index PLAN OUT`` writes the tiled scene index. See
``docs/scale.md`` in the spatch repository.
"""

from .runner import TileResult, convert_tile, run_plan, tile_file_name

__all__ = ["TileResult", "convert_tile", "run_plan", "tile_file_name"]
