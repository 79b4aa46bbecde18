#!/usr/bin/env python3
"""Medians over runs of the harness's `--csv` rows, as a markdown table.

    for r in 1 2 3; do cargo run --release -- --csv runs.csv > /dev/null; done
    scripts/medians.py runs.csv

Per scene: the median over runs of each run's median frame times (ours, and each Embree
configuration that ran: point1, point8, user1, user8), and of each run's ratios (ours ÷ that
configuration's time). Embree best is the configuration with the lowest median wall time
over the runs; its ratios (wall, CPU, one thread) and the range of its wall ratio follow.
A second table gives the process-CPU-time ratios, ours ÷ each configuration (steadier than
wall time on a shared machine), and the configuration with the least CPU time.
Files from before the configurations (an `embree_ms` column: sphere points, single rays) read
as point1.
"""
import collections
import csv
import math
import statistics as st
import sys

CONFIGS = ["point1", "point8", "user1", "user8"]


def main():
    by_scene = collections.OrderedDict()
    for row in csv.DictReader(open(sys.argv[1])):
        if "point1_ms" not in row:
            # The harness's first columns: Embree was sphere points with single rays.
            for k in ["ms", "cpu_ms", "ms_1"]:
                row[f"point1_{k}"] = row.get(f"embree_{k}", "")
            row["point1_rays"] = row.get("embree_rays", "")
        by_scene.setdefault((row["scene"], row["width"], row["height"], row["threads"]), []).append(row)
    fmt = lambda v, spec: "–" if v is None or math.isnan(v) else format(v, spec)
    print(
        "| scene | spheres | W×H | rays | runs | ours ms | point1 ms | point8 ms | user1 ms | user8 ms | Embree best "
        "| ours ÷ best | CPU: ours ÷ best | ours ÷ point1 | CPU: ours ÷ point1 | ours ÷ point8 | ours ÷ user1 "
        "| ours ÷ user8 | ours Mrays/s/core | best Mrays/s/core | 1 thread: ours ÷ best | ours ÷ best, range |"
    )
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for (scene, w, h, _), rows in by_scene.items():
        f = lambda r, k: float(r[k]) if r.get(k) else float("nan")
        med = lambda k: st.median(f(r, k) for r in rows)
        ran = [c for c in CONFIGS if all(r.get(f"{c}_ms") for r in rows)]
        ratios = lambda k, c: [f(r, f"ours_{k}") / f(r, f"{c}_{k}") for r in rows]
        best = min(ran, key=lambda c: med(f"{c}_ms")) if ran else None
        cell = lambda c, k="ms": fmt(st.median(ratios(k, c)), ".2f") if c in ran else "–"
        ms = lambda c: fmt(med(f"{c}_ms"), ".0f") if c in ran else "–"
        rate = lambda who: st.median(f(r, f"{who}_rays") / f(r, f"{who}_cpu_ms") / 1e3 for r in rows)
        wall_best = ratios("ms", best) if best else [float("nan")]
        n = int(rows[0]["spheres"])
        rays = int(rows[0]["ours_rays"])
        print(
            f"| {scene} | {n:,} | {w}×{h} | {rays:,} | {len(rows)} | {fmt(med('ours_ms'), '.0f')} "
            f"| {ms('point1')} | {ms('point8')} | {ms('user1')} | {ms('user8')} | {best or '–'} "
            f"| {cell(best)} | {cell(best, 'cpu_ms')} | {cell('point1')} | {cell('point1', 'cpu_ms')} "
            f"| {cell('point8')} | {cell('user1')} | {cell('user8')} | {fmt(rate('ours'), '.1f')} "
            f"| {fmt(rate(best), '.1f') if best else '–'} | {cell(best, 'ms_1')} "
            f"| {fmt(min(wall_best), '.2f')}–{fmt(max(wall_best), '.2f')} |".replace(",", "\u202f")
        )
    print()
    print("| scene | runs | CPU: ours ÷ point1 | CPU: ours ÷ point8 | CPU: ours ÷ user1 | CPU: ours ÷ user8 | least CPU time |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for (scene, _, _, _), rows in by_scene.items():
        f = lambda r, k: float(r[k]) if r.get(k) else float("nan")
        ran = [c for c in CONFIGS if all(r.get(f"{c}_cpu_ms") for r in rows)]
        cpu = {c: st.median(f(r, "ours_cpu_ms") / f(r, f"{c}_cpu_ms") for r in rows) for c in ran}
        least = max(ran, key=lambda c: cpu[c]) if ran else "–"
        cells = " | ".join(fmt(cpu[c], ".2f") if c in ran else "–" for c in CONFIGS)
        print(f"| {scene} | {len(rows)} | {cells} | {least} |")


if __name__ == "__main__":
    main()
