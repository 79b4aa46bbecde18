#!/usr/bin/env python3
"""Medians over runs of the harness's `--csv` rows, as a markdown table.

    for r in 1 2 3; do cargo run --release -- --csv runs.csv > /dev/null; done
    scripts/medians.py runs.csv

Per scene: the median over runs of each run's median frame times, and of each run's ratios
(ours ÷ Embree's time, wall and CPU; one thread), with the range of the wall ratio.
"""
import collections
import csv
import statistics as st
import sys


def main():
    by_scene = collections.OrderedDict()
    for row in csv.DictReader(open(sys.argv[1])):
        by_scene.setdefault((row["scene"], row["width"], row["height"], row["threads"]), []).append(row)
    print(
        "| scene | spheres | W×H | rays | runs | ours ms | Embree ms | ours ÷ Embree | CPU: ours ÷ Embree | "
        "our speed | ours Mrays/s/core | Embree Mrays/s/core | 1 thread: ours ÷ Embree | ours ÷ Embree, range |"
    )
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for (scene, w, h, _), rows in by_scene.items():
        f = lambda r, k: float(r[k]) if r[k] else float("nan")
        med = lambda k: st.median(f(r, k) for r in rows)
        wall = [f(r, "ours_ms") / f(r, "embree_ms") for r in rows]
        cpu = [f(r, "ours_cpu_ms") / f(r, "embree_cpu_ms") for r in rows]
        one = [f(r, "ours_ms_1") / f(r, "embree_ms_1") for r in rows]
        ours_rate = st.median(f(r, "ours_rays") / f(r, "ours_cpu_ms") / 1e3 for r in rows)
        embree_rate = st.median(f(r, "embree_rays") / f(r, "embree_cpu_ms") / 1e3 for r in rows)
        n = int(rows[0]["spheres"])
        rays = int(rows[0]["ours_rays"])
        print(
            f"| {scene} | {n:,} | {w}×{h} | {rays:,} | {len(rows)} | {med('ours_ms'):.0f} | {med('embree_ms'):.0f} "
            f"| {st.median(wall):.2f} | {st.median(cpu):.2f} | {1 / st.median(wall):.1f}× | {ours_rate:.1f} "
            f"| {embree_rate:.1f} | {st.median(one):.2f} | {min(wall):.2f}–{max(wall):.2f} |".replace(",", "\u202f")
        )


if __name__ == "__main__":
    main()
