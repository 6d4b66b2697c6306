"""A plan's tiles on a LocalCluster give the same bytes as spatch's own local run."""

import os
import shutil
import struct
import subprocess
import random

import pytest

from spatch_dask import run_plan, tile_file_name
from spatch_dask.staging import is_url


def spatch_binary():
    found = os.environ.get("SPATCH_BIN") or shutil.which("spatch")
    if not found:
        pytest.skip("no spatch binary: set SPATCH_BIN")
    return found


def write_scene(path, points=4000, seed=3):
    """Ground of 8 m x 8 m and one box building, as binary PLY with colours."""
    rng = random.Random(seed)
    rows = []
    for _ in range(points * 3 // 4):
        x, y = rng.uniform(0, 8), rng.uniform(0, 8)
        rows.append((x, y, 0.1 * x, 120, 120, 125))
    for _ in range(points - len(rows)):
        side, a, h = rng.randrange(4), rng.uniform(0, 2), rng.uniform(0, 2)
        x, y = [(3 + a, 3), (5, 3 + a), (5 - a, 5), (3, 5 - a)][side]
        rows.append((x, y, 0.1 * x + h, 200, 170, 150))
    header = (
        "ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n" % len(rows)
    )
    with open(path, "wb") as f:
        f.write(header.encode())
        for r in rows:
            f.write(struct.pack("<fffBBB", *r))


def test_four_tiles_on_two_workers_match_the_local_run(tmp_path):
    spatch = spatch_binary()
    cloud = str(tmp_path / "city.ply")
    plan = str(tmp_path / "plan.json")
    write_scene(cloud)
    run = lambda *a: subprocess.run([spatch, "-q", *a], check=True)
    run("plan", cloud, "--tile", "4.01", "--spacing", "0.07", "--buffer", "0.6", "-o", plan)
    local = tmp_path / "local"
    run("from-cloud", cloud, "--plan", plan, "-o", str(local))
    out = tmp_path / "dask"
    results = run_plan(cloud, plan, str(out), spatch=spatch, workers=2)
    assert len(results) == 4
    for r in results:
        name = tile_file_name(r.index)
        assert (out / name).read_bytes() == (local / name).read_bytes(), name
    assert (out / "index.json").read_bytes() == (local / "index.json").read_bytes()
    assert (out / "coarse.spatch").read_bytes() == (local / "coarse.spatch").read_bytes()
    assert not (local / ".spill").exists()


def test_file_urls_are_staged_through_fsspec_to_the_same_bytes(tmp_path):
    spatch = spatch_binary()
    remote = tmp_path / "remote"
    remote.mkdir()
    cloud, plan = remote / "city.ply", remote / "plan.json"
    write_scene(str(cloud), points=3000, seed=5)
    run = lambda *a: subprocess.run([spatch, "-q", *a], check=True)
    run("plan", str(cloud), "--tile", "4.01", "--spacing", "0.08", "--buffer", "0.6", "-o", str(plan))
    local = tmp_path / "local"
    run("from-cloud", str(cloud), "--plan", str(plan), "-o", str(local))
    url = lambda p: "file://" + str(p)
    out = remote / "out"
    results = run_plan(url(cloud), url(plan), url(out), spatch=spatch, workers=2)
    assert len(results) == 4
    assert all(r.path == url(out) + "/" + tile_file_name(r.index) for r in results)
    names = sorted(p.name for p in local.iterdir())
    assert sorted(p.name for p in out.iterdir()) == names
    for name in names:
        assert (out / name).read_bytes() == (local / name).read_bytes(), name
    assert is_url("s3://bucket/a.las") and is_url(url(cloud))
    assert not is_url(str(cloud)) and not is_url("C:/data/a.las")


def test_a_failing_tile_is_reported(tmp_path):
    spatch = spatch_binary()
    cloud = str(tmp_path / "city.ply")
    plan = str(tmp_path / "plan.json")
    write_scene(cloud, points=1000)
    subprocess.run([spatch, "-q", "plan", cloud, "--tile", "4.01", "--spacing", "0.1", "--buffer", "0.6", "-o", plan], check=True)
    os.remove(cloud)
    with pytest.raises(RuntimeError, match="city.ply"):
        run_plan(cloud, plan, str(tmp_path / "out"), spatch=spatch, workers=1, retries=1)
