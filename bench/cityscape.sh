#!/bin/sh
# Writes a synthetic cityscape of POINTS points as OUT.las and OUT.ply (see
# crates/tiling/examples/cityscape.rs). Usage: bench/cityscape.sh POINTS OUT [SEED]
set -eu
cd "$(dirname "$0")/.."
exec nice cargo run --quiet --release -p spatch-tiling --example cityscape -- "$@"
