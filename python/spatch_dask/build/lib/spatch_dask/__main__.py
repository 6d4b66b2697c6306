"""``python -m spatch_dask``: the ``spatch-dask`` command."""

import sys

from .cli import main

sys.exit(main())
