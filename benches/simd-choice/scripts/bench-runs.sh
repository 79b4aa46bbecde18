#!/usr/bin/env bash
# Runs the shade bench RUNS times (alternating thread-CPU-time and wall-clock runs), keeps
# each run's median per kernel, and prints the median over runs with its min–max spread,
# in ns per hit. Usage: scripts/bench-runs.sh [RUNS] [criterion filter]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5}
filter=${2:-}
target=${CARGO_TARGET_DIR:-target}
out=$target/bench-runs
rm -rf "$out" "$target/criterion/shade_4096" "$target/criterion/shade_4096_cpu"
mkdir -p "$out"
cargo bench --bench shade --no-run >/dev/null 2>&1
collect() { # group, run
    for est in "$target/criterion/$1"/*/new/estimates.json "$target/criterion/$1"/*/*/*/new/estimates.json; do
        [ -f "$est" ] || continue
        name=${est#"$target/criterion/$1/"}
        name=${name%/new/estimates.json}
        python3 -c 'import json,sys; print(sys.argv[1], json.load(open(sys.argv[2]))["median"]["point_estimate"] / 4096)' "$name" "$est"
    done >"$out/$1.$2.tsv"
}
for r in $(seq 1 "$runs"); do
    echo "run $r/$runs: $(uptime | sed 's/.*load/load/')" >&2
    SIMD_EVAL_CPU_TIME=1 cargo bench --bench shade -- ${filter:+"$filter"} >"$out/cpu.$r.log" 2>&1
    collect shade_4096_cpu "$r"
    cargo bench --bench shade -- ${filter:+"$filter"} >"$out/wall.$r.log" 2>&1
    collect shade_4096 "$r"
done
python3 - "$out" <<'PY'
import collections, glob, statistics, sys
out = sys.argv[1]
for group, label in (("shade_4096_cpu", "thread CPU time"), ("shade_4096", "wall time")):
    runs = collections.defaultdict(list)
    for f in sorted(glob.glob(f"{out}/{group}.*.tsv")):
        for line in open(f):
            name, ns = line.split()
            runs[name].append(float(ns))
    if not runs:
        continue
    base = statistics.median(runs.get("scalar_exact", [float("nan")]))
    print(f"\n{label}, ns per hit: median of {max(len(v) for v in runs.values())} runs [min–max], speed-up over scalar/exact")
    for name in sorted(runs, key=lambda n: statistics.median(runs[n])):
        v = runs[name]
        m = statistics.median(v)
        print(f"  {name:28} {m:7.2f}  [{min(v):6.2f}–{max(v):6.2f}]  {base / m:5.2f}x")
PY
