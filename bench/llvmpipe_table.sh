#!/bin/sh
# The llvmpipe comparison (bench/llvmpipe_compare.py) over several meshes
# and image sizes: each mesh (PLY or OBJ; a raw range-grid scan is first
# triangulated by bench/range_grid_mesh.py) is converted with `spatch convert`'s
# defaults into a temporary folder, then timed against llvmpipe drawing it,
# one line per mesh and size (the script's summary line).
#
# Usage: bench/llvmpipe_table.sh SPATCH "SIZES" MESH [MESH ...]
# Example (the bunny at the four resolutions of the Stanford archive):
#   R=../shared/data/bunny/reconstruction
#   bench/llvmpipe_table.sh target/release/spatch "500 1000" \
#       $R/bun_zipper.ply $R/bun_zipper_res2.ply $R/bun_zipper_res3.ply $R/bun_zipper_res4.ply
# Needs the Python of bench/llvmpipe_compare.py's setup (PYTHON, default
# /tmp/venv/bin/python, with moderngl, numpy and pillow) and Mesa's llvmpipe;
# ROUNDS and FRAMES (default 5 and 30) set each comparison's length;
# TEXTURED=1 has llvmpipe draw textured OBJ files with their texture;
# SPATCH_ARGS adds options to `spatch render` (e.g. SPATCH_ARGS=--gap-fill).
set -eu
if [ $# -lt 3 ]; then
    sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
fi
spatch=$1
sizes=$2
shift 2
python=${PYTHON:-/tmp/venv/bin/python}
here=$(dirname "$0")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for mesh in "$@"; do
    name=$(basename "$mesh")
    # A raw range scan (a PLY with a range grid and no faces, as the
    # Stanford scans) is triangulated first, as a scanner's software would
    # (bench/range_grid_mesh.py), so both sides draw the same triangles.
    if head -c 4096 "$mesh" | grep -aq '^element range_grid'; then
        "$python" "$here/range_grid_mesh.py" "$mesh" "$work/$name" >/dev/null
        mesh="$work/$name"
    fi
    scene="$work/${name%.*}.spatch"
    # A mesh spatch refuses is reported and skipped; the other meshes are
    # still timed.
    if ! "$spatch" convert "$mesh" -o "$scene" --no-error -q; then
        echo "$name: not converted, skipped"
        continue
    fi
    for size in $sizes; do
        LP_NUM_THREADS=2 "$python" "$here/llvmpipe_compare.py" --spatch "$spatch" \
            --mesh "$mesh" --scene "$scene" --size "$size" \
            --rounds "${ROUNDS:-5}" --frames "${FRAMES:-30}" ${TEXTURED:+--textured} \
            ${SPATCH_ARGS:+-- $SPATCH_ARGS} | tail -n 1
    done
done
