#!/usr/bin/env python3
"""Where a `perf record` of the harness spent its samples, by tracer stage.

    perf record -F 499 -o ours.data -- "$CARGO_TARGET_DIR"/release/embree-anchor \
        --spheres 100k --frames 6 --no-single --only ours
    scripts/perf-stages.py ours.data "$CARGO_TARGET_DIR"/release/embree-anchor

The tracer's hot code is inlined into a few `fearless_simd` `vectorize` functions, so
`perf report`'s symbols say nothing. This resolves each sample's address to its chain of
inlined frames (`addr2line -i`, from the release profile's line tables) and files the sample
under the first stage whose function appears anywhere in that chain: the shadow-ray query,
the mirror-ray query, the primary hits, the shading stages. Then, within the two queries,
the innermost tracer function.
"""
import collections
import re
import subprocess
import sys

STAGES = [
    ("shadow rays (Aggregate::occluded_lanes: light cube maps)", r"^(occluded_lanes|occluded_in|occluded|towards_light) @"),
    ("mirror rays (Aggregate::intersect_lanes: BVH, cones)", r"^(intersect_lanes|intersect_in|intersect) @"),
    ("screen bins build", r"^build @accel/screen"),
    ("primary hits (screen bins, row loop)", r"accel/screen\.rs|render/row\.rs"),
    ("shading: per-lane gathers of sphere data", r"^(per_object|material) @"),
    ("shading: hit points, normals, lights, highlights", r"^shade @"),
    ("shading: mirror stage (reflect, spawn)", r"^mirrors @"),
    ("wavefront bookkeeping", r"wavefront"),
    ("Tracer::new (snapshot, BVH, bins)", r"build\.rs|snapshot\.rs|bvh/"),
]


def text_bias(binary):
    """vaddr − file offset of the executable segment: perf prints file offsets."""
    out = subprocess.run(["readelf", "-lW", binary], capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        f = line.split()
        if f and f[0] == "LOAD" and "E" in f[6:-1]:
            return int(f[2], 16) - int(f[1], 16)
    return 0


def leaf_addresses(data, binary):
    out = subprocess.run(["perf", "script", "-i", data, "-F", "ip,dso"], capture_output=True, text=True).stdout
    leaves, new = [], True
    for line in out.splitlines():
        if not line.strip():
            new = True
            continue
        if new:
            leaves.append(line.split())
            new = False
    return len(leaves), [f[0] for f in leaves if len(f) > 1 and binary in f[1]]


def frames(binary, addresses, bias):
    uniq = sorted(set(addresses))
    args = ["addr2line", "-a", "-i", "-f", "-C", "-e", binary] + [hex(int(a, 16) + bias) for a in uniq]
    lines = subprocess.run(args, capture_output=True, text=True, check=True).stdout.splitlines()
    chains, key, i = {}, None, 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("0x"):
            key = format(int(line, 16) - bias, "x")
            chains[key] = []
            i += 1
            continue
        name = line
        for _ in range(3):
            name = re.sub(r"<[^<>]*>", "", name)
        loc = re.search(r"/src/(.*?):\d+", lines[i + 1]) if i + 1 < len(lines) else None
        chains[key].append(f"{name.split('::')[-1].strip()} @{loc.group(1) if loc else '?'}")
        i += 2
    return chains


def main():
    data, binary = sys.argv[1], sys.argv[2]
    total, addresses = leaf_addresses(data, binary)
    chains = frames(binary, addresses, text_bias(binary))
    stages, inner = collections.Counter(), collections.Counter()
    for a in addresses:
        chain = chains.get(format(int(a, 16), "x"), [])
        stage = next((name for name, p in STAGES if any(re.search(p, f) for f in chain)), "other")
        stages[stage] += 1
        if stage.startswith(("shadow", "mirror rays")):
            f = next((f for f in chain if re.search(r"accel/|simd\.rs", f)), "?")
            inner[f"{stage.split(' (')[0]}: {f}"] += 1
    print(f"{total} samples, {len(addresses)} in {binary.split('/')[-1]}")
    for name, n in stages.most_common():
        print(f"{100 * n / total:5.1f} %  {name}")
    print("\nwithin the queries, the innermost tracer function:")
    for name, n in inner.most_common(12):
        print(f"{100 * n / total:5.1f} %  {name}")


if __name__ == "__main__":
    main()
