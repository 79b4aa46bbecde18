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
    # Functions, matched against a sample's chain of frames (inlined ones included, full
    # paths without generics), innermost first; the first stage any frame matches wins.
    # `intersect_deep` is the BVH's out-of-line traversal of a deep tree (1M spheres).
    ("shadow rays (Aggregate::occluded_lanes: light cube maps)", r"(^|::)(occluded_lanes|occluded_in|occluded|towards_light)\b"),
    ("mirror rays (Aggregate::intersect_lanes: BVH, cones)", r"(^|::)(intersect_lanes|intersect_in|intersect_deep)\b"),
    ("screen bins build", r"ScreenBins::build|(^|::)build @accel/screen"),
    ("primary hits (screen bins)", r"@accel/screen\.rs"),
    ("shading: per-lane gathers of sphere data", r"(^|::)(per_object|material)\b"),
    ("shading: hit points, normals, lights, highlights", r"(^|::)shade @wavefront/lanes"),
    ("shading: mirror stage (reflect, spawn)", r"(^|::)mirrors @wavefront/lanes"),
    ("Tracer::new (snapshot, BVH, light maps, cones)", r"@accel/bvh/build\.rs|@snapshot\.rs|(^|::)(build|update) @"),
    ("generating the field", r"@field\.rs"),
]
# Matched only when no frame matches a stage above: whatever else the row loop and the
# wavefront do.
FALLBACK = [
    ("wavefront bookkeeping", r"@wavefront"),
    ("row loop", r"@render/"),
]


def sample_stacks(data, binary):
    """Each sample's stack in `binary`, leaf first, as virtual addresses (what addr2line
    wants), from symbol + offset: perf prints absolute or file-relative addresses depending
    on whether call chains were recorded, but symbol + offset means one thing. Return
    addresses (every frame but the leaf) are moved back a byte into their call."""
    symbols = {}
    nm = subprocess.run(["nm", "--defined-only", binary], capture_output=True, text=True, check=True).stdout
    for line in nm.splitlines():
        f = line.split()
        if len(f) == 3:
            symbols[f[2]] = int(f[0], 16)
    out = subprocess.run(
        ["perf", "script", "-i", data, "-F", "ip,sym,symoff,dso", "--no-demangle"], capture_output=True, text=True
    ).stdout
    # With call chains a sample is a block of lines ending in a blank one; without, a line.
    chained = "\n\n" in out
    blocks = out.split("\n\n") if chained else out.splitlines()
    total, stacks = 0, []
    for block in blocks:
        lines = [l for l in block.splitlines() if l.strip()]
        if not lines:
            continue
        total += 1
        stack = []
        for depth, line in enumerate(lines):
            m = re.match(r"\s*\S+ (\S+)\+0x([0-9a-f]+) \((.*)\)", line)
            if m and m.group(3) == binary and m.group(1) in symbols:
                stack.append(format(symbols[m.group(1)] + int(m.group(2), 16) - (depth > 0), "x"))
        if stack and lines[0].endswith(f"({binary})"):
            stacks.append(stack)
    return total, stacks


def frames(binary, addresses):
    uniq = sorted(set(addresses))
    args = ["addr2line", "-a", "-i", "-f", "-C", "-e", binary] + ["0x" + a for a in uniq]
    lines = subprocess.run(args, capture_output=True, text=True, check=True).stdout.splitlines()
    chains, key, i = {}, None, 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("0x"):
            key = format(int(line, 16), "x")
            chains[key] = []
            i += 1
            continue
        name = line
        for _ in range(3):
            name = re.sub(r"<[^<>]*>", "", name)
        loc = re.search(r"/src/(.*?):\d+", lines[i + 1]) if i + 1 < len(lines) else None
        chains[key].append(f"{name.strip()} @{loc.group(1) if loc else '?'}")
        i += 2
    return chains


def main():
    data, binary = sys.argv[1], sys.argv[2]
    total, stacks = sample_stacks(data, binary)
    chains = frames(binary, [a for stack in stacks for a in stack])
    stages, inner, unfiled = collections.Counter(), collections.Counter(), collections.Counter()
    for stack in stacks:
        chain = [f for a in stack for f in chains.get(a, [])]
        stage = next(
            (name for f in chain for name, p in STAGES if re.search(p, f)),
            next((name for name, p in FALLBACK if any(re.search(p, f) for f in chain)), "other"),
        )
        stages[stage] += 1
        if stage == "other":
            unfiled[" < ".join(re.sub(r"<.*", "", f)[-60:] for f in chain[:10])] += 1
        if stage.startswith(("shadow", "mirror rays")):
            f = next((f for f in chain if re.search(r"@(accel/|simd\.rs)", f)), "?")
            inner[f"{stage.split(' (')[0]}: {re.sub(r'^.*::(?=[^:]+::[^:]+ @)', '', f)}"] += 1
    print(f"{total} samples, {len(stacks)} in {binary.split('/')[-1]}")
    for name, n in stages.most_common():
        print(f"{100 * n / total:5.1f} %  {name}")
    print("\nwithin the queries, the innermost tracer function:")
    for name, n in inner.most_common(12):
        print(f"{100 * n / total:5.1f} %  {name}")
    print("\nthe commonest unfiled chains (innermost first):")
    for name, n in unfiled.most_common(5):
        print(f"{100 * n / total:5.1f} %  {name}")


if __name__ == "__main__":
    main()
