#!/usr/bin/env python3
"""Frame time of two spatch binaries on one scene, run in turn.

A change of a few percent in wall time is smaller than this host's drift
between runs, so the two binaries (say main's and a branch's) take turns:
each round runs `spatch render SCENE --bench N --json` with the first, then
with the second, and keeps each run's median frame. The medians over rounds
and their ratio are printed (second / first: below 1 means the second is
faster). With --one-frame each turn times the whole command
`spatch render SCENE -o PNG` instead (wall clock of the process: reading,
preparation, the first frame, the PNG). Binaries from before the shared
report schema (their `--json` has `ms` at the top) are read too, so a
binary as old as issue 21's can be compared. --second-args gives flags to
the second run only, so one binary can be timed with and without a knob
(pass it twice). Standard library only.

Usage:
  python3 bench/compare_binaries.py OLD_SPATCH NEW_SPATCH SCENE \\
      [--rounds 10] [--frames 30] [--one-frame] [--second-args "FLAGS"] \\
      [-- extra spatch render flags]
Example:
  python3 bench/compare_binaries.py /tmp/spatch_main target/release/spatch \\
      bunny.spatch --rounds 10 --frames 30 -- --threads 1
  python3 bench/compare_binaries.py /tmp/spatch_main target/release/spatch \\
      bunny.spatch --rounds 15 --one-frame -- --threads 2
  python3 bench/compare_binaries.py target/release/spatch target/release/spatch \\
      bunny.spatch --second-args "--level-one-limit 6" -- --threads 2 --width 1000 --height 1000
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def median_frame(binary, scene, frames, extra):
    """One `--bench` run's median frame in milliseconds."""
    command = [binary, "render", scene, "--bench", str(frames), "--json", *extra]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    report = json.loads(out)
    stages = report["details"]["bench"]["ms"] if "details" in report else report["ms"]
    return stages["frame"]["median_ms"]


def one_frame(binary, scene, png, extra):
    """Wall clock of one `spatch render SCENE -o PNG` process, in milliseconds."""
    command = [binary, "render", scene, "-o", png, *extra]
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return (time.perf_counter() - start) * 1e3


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("first", help="the reference spatch binary")
    parser.add_argument("second", help="the spatch binary compared with it")
    parser.add_argument("scene", help="a .spatch file")
    parser.add_argument("--rounds", type=int, default=10, help="turns of each binary")
    parser.add_argument("--frames", type=int, default=30, help="frames per --bench run")
    parser.add_argument(
        "--one-frame", action="store_true", help="time the whole one-image command instead"
    )
    parser.add_argument(
        "--second-args", default="", help="flags for the second run only (split at spaces)"
    )
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1 :] if "--" in argv else []
    args = parser.parse_args(argv[: argv.index("--")] if "--" in argv else argv)
    if args.rounds < 1 or args.frames < 1:
        sys.exit("compare_binaries: --rounds and --frames must be at least 1")
    turns = [(args.first, extra), (args.second, extra + args.second_args.split())]
    runs = [[], []]
    png = os.path.join(tempfile.mkdtemp(prefix="compare_binaries_"), "out.png")
    for k in range(args.rounds):
        for (binary, flags), times in zip(turns, runs):
            if args.one_frame:
                times.append(one_frame(binary, args.scene, png, flags))
            else:
                times.append(median_frame(binary, args.scene, args.frames, flags))
        print(f"round {k + 1}: {runs[0][-1]:.3f} ms, {runs[1][-1]:.3f} ms")
    first, second = (statistics.median(times) for times in runs)
    for (binary, flags), times, median in zip(turns, runs, (first, second)):
        name = " ".join([binary, *flags[len(extra) :]])
        print(f"{name}: median {median:.3f} ms, min {min(times):.3f} ms")
    unit = "one-image commands" if args.one_frame else f"{args.frames} frames"
    print(f"second / first: {second / first:.3f} over {args.rounds} rounds of {unit}")


if __name__ == "__main__":
    main()
