#!/usr/bin/env python3
"""Side-by-side speed of two stereotrace binaries, every mode, alternating runs.

    scripts/ab-speed.py BEFORE AFTER [--rounds 5] [--frames 10] [--case seed:1280x720 ...]

Each round runs `bench --json --animate 0` of BEFORE then AFTER (then AFTER then BEFORE on
the next round, so neither always goes first) on each case, and takes each mode's median
stereo time (left + right). It prints, per case and mode, the median over the rounds of
each binary's time and their ratio (AFTER / BEFORE), then the geometric mean of the ratios.
A developer's tool for a shared, noisy machine: the two builds meet the same load.
"""

import argparse
import json
import math
import statistics
import subprocess
import sys


def bench(binary, scene, width, height, frames):
    out = subprocess.run(
        [binary, "bench", "--scene", f"assets/scenes/{scene}.toml", "--width", str(width), "--height",
         str(height), "--frames", str(frames), "--animate", "0", "--json"],
        check=True, capture_output=True, text=True).stdout
    report = json.loads(out)
    return {mode: m["stereo_ms"] for mode, m in report["modes"].items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("before")
    parser.add_argument("after")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--case", action="append", help="scene:WxH (default seed:1280x720 and many:640x360)")
    args = parser.parse_args()
    cases = args.case or ["seed:1280x720", "many:640x360"]
    times = {}
    for r in range(args.rounds):
        order = [("before", args.before), ("after", args.after)]
        if r % 2:
            order.reverse()
        for case in cases:
            scene, size = case.split(":")
            w, h = map(int, size.split("x"))
            for name, binary in order:
                for mode, ms in bench(binary, scene, w, h, args.frames).items():
                    times.setdefault((case, mode), {}).setdefault(name, []).append(ms)
        print(f"round {r + 1}/{args.rounds} done", file=sys.stderr)
    ratios = []
    print(f"| case | mode | before ms | after ms | after / before |")
    print(f"|---|---|---:|---:|---:|")
    for (case, mode), t in times.items():
        b, a = statistics.median(t["before"]), statistics.median(t["after"])
        ratios.append(a / b)
        print(f"| {case} | {mode} | {b:.2f} | {a:.2f} | {a / b:.3f} |")
    geo = math.exp(sum(map(math.log, ratios)) / len(ratios))
    print(f"\ngeometric mean of the ratios: {geo:.3f}; worst: {max(ratios):.3f} ({args.rounds} rounds)")


if __name__ == "__main__":
    main()
