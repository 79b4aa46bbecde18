#!/usr/bin/env bash
# Writes docs/performance.md: `stereotrace bench --json` on each run's scene, as Markdown
# tables stamped with the date, the commit, the CPU model, the thread count and the exact
# command lines. docs/performance-notes.md says how the numbers are measured and what each
# column means; this script only produces the day's numbers.
#
#   scripts/perf-report.sh [--frames N] [--out PATH] [--bin PATH] [--note TEXT] [RUN ...]
#
#   RUN       one bench run: a scene file, then any extra `stereotrace bench` flags, as one
#             word, e.g. "assets/scenes/seed.toml --depth 0". Each run is 1280×720 per eye
#             unless it gives --width/--height. Default: seed.toml (the reference),
#             seed.toml --depth 0, many.toml, thousand.toml.
#   --frames  frames per mode (medians over them; default 7)
#   --out     the page to write (default docs/performance.md)
#   --bin     time this stereotrace binary instead of building the checkout's release binary
#             (the page then says so: its commit stamp is the checkout's, not the binary's)
#   --note    a line for the page's header, e.g. "other builds were running"
#
# Needs: the Rust toolchain, git, python3. Builds with `cargo build --release --locked -p
# viewer` (the package of the `stereotrace` binary). The page is written to a temporary file
# beside the output and renamed, so a failed run leaves the previous page as it was.
set -euo pipefail

frames=7
out=docs/performance.md
bin=
note=
runs=()
# The usage text is this file's opening comment.
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; }
while (($#)); do
  case $1 in
    --frames) frames=${2:?--frames needs a number}; shift 2 ;;
    --out) out=${2:?--out needs a path}; shift 2 ;;
    --bin) bin=${2:?--bin needs a path}; shift 2 ;;
    --note) note=${2:?--note needs a text}; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "perf-report: unknown option $1" >&2; usage >&2; exit 2 ;;
    *) runs+=("$1"); shift ;;
  esac
done
[[ $frames =~ ^[1-9][0-9]*$ ]] || { echo "perf-report: --frames must be a positive integer, not '$frames'" >&2; exit 2; }

# Paths given on the command line are relative to where the script was started.
abspath() { case $1 in /*) printf '%s\n' "$1" ;; *) printf '%s\n' "$PWD/$1" ;; esac; }
out=$(abspath "$out")
[[ -z $bin ]] || bin=$(abspath "$bin")
cd "$(dirname "$0")/.."
root=$PWD
if ((${#runs[@]} == 0)); then
  runs=(
    "assets/scenes/seed.toml"
    "assets/scenes/seed.toml --depth 0"
    "assets/scenes/many.toml"
    "assets/scenes/thousand.toml"
  )
fi
outdir=$(dirname "$out")
[[ -d $outdir ]] || { echo "perf-report: no folder $outdir for the page" >&2; exit 2; }

# The stamp: the commit, with -dirty when anything but the page itself differs from it.
commit=$(git rev-parse --short HEAD)
pathspec=(.)
case $out in "$root"/*) pathspec+=(":(exclude)${out#"$root"/}") ;; esac
changes=$(git status --porcelain --untracked-files=normal -- "${pathspec[@]}")
if [[ -n $changes ]]; then
  commit+=-dirty
fi

if [[ -z $bin ]]; then
  echo "== cargo build --release --locked -p viewer" >&2
  cargo build --release --locked -p viewer
  target_dir=$(cargo metadata --format-version 1 --no-deps --locked |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')
  bin=$target_dir/release/stereotrace
  built=yes
else
  built=no
fi
[[ -x $bin ]] || { echo "perf-report: $bin is not an executable" >&2; exit 2; }

work=$(mktemp -d)
tmp_page=
cleanup() { rm -rf "$work"; [[ -z $tmp_page ]] || rm -f "$tmp_page"; }
trap cleanup EXIT

cpu=$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//' || true)
[[ -n $cpu ]] || cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1 || true)
[[ -n $cpu ]] || cpu=unknown

export PR_DATE PR_COMMIT PR_CPU PR_NPROC PR_RAYON PR_RUSTC PR_BIN PR_BUILT PR_NOTE PR_FRAMES
PR_DATE=$(date -u '+%Y-%m-%d %H:%M UTC')
PR_COMMIT=$commit
PR_CPU=$cpu
PR_NPROC=$(nproc)
PR_RAYON=${RAYON_NUM_THREADS:-}
PR_RUSTC=$(rustc -V 2>/dev/null || echo unknown)
PR_BIN=${bin#"$root"/}
PR_BUILT=$built
PR_NOTE=$note
PR_FRAMES=$frames
read -r load_before _ < /proc/loadavg

i=0
for run in "${runs[@]}"; do
  read -ra words <<< "$run"
  ((${#words[@]})) || { echo "perf-report: an empty run" >&2; exit 2; }
  scene=${words[0]}
  extra=("${words[@]:1}")
  [[ -f $scene ]] || { echo "perf-report: no scene file $scene (paths are relative to $root)" >&2; exit 2; }
  size=(--width 1280 --height 720)
  for w in "${extra[@]}"; do
    if [[ $w == --width* || $w == --height* ]]; then size=(); fi
  done
  args=(bench --scene "$scene" "${size[@]}" "${extra[@]}" --frames "$frames" --json)
  echo "== $PR_BIN ${args[*]}" >&2
  "$bin" "${args[@]}" > "$work/run$i.json"
  printf '%s\n' "$PR_BIN ${args[*]}" > "$work/run$i.cmd"
  printf '%s\n' "${extra[*]}" > "$work/run$i.extra"
  i=$((i + 1))
done
read -r load_after _ < /proc/loadavg
export PR_LOAD="$load_before before the first bench, $load_after after the last" PR_LOAD_AFTER=$load_after

tmp_page=$(mktemp "$outdir/.perf-report.XXXXXX")
python3 - "$work" "$i" > "$tmp_page" <<'PY'
"""Markdown tables from the bench JSON reports (keys as in docs/cli.md, "JSON report keys")."""
import json
import math
import os
import sys

work, n = sys.argv[1], int(sys.argv[2])
env = os.environ
runs = []
extras = []
for k in range(n):
    with open(f"{work}/run{k}.json") as f:
        report = json.load(f)
    with open(f"{work}/run{k}.cmd") as f:
        cmd = f.read().strip()
    with open(f"{work}/run{k}.extra") as f:
        extras.append(f.read().split())
    runs.append((cmd, report))

ORDER = ["full", "copy", "copy+edges", "reshade", "reshade+edges", "exact"]
LABEL = {"copy": "copy (the paper)", "copy+edges": "copy + edges", "reshade+edges": "reshade + edges"}


def modes(report):
    m = report["modes"]
    names = [x for x in ORDER if x in m] + sorted(x for x in m if x not in ORDER)
    return [(LABEL.get(x, x), m[x]) for x in names]


def pct(x, digits=1):
    return f"{100 * x:.{digits}f} %"


def identical(q):
    """The share of identical pixels, rounded down: 100 % only when every pixel is."""
    share = 1 - q["share_not_identical"]
    return "100 %" if share == 1 else f"{math.floor(1000 * share) / 10:.1f} %"


def over(q):
    """The share of pixels off by more than 2/255, never shown as 0 when one is."""
    share = q["share_over_2_255"]
    if share == 0:
        return "0 %"
    return "< 0.01 %" if share < 1e-4 else pct(share, 2)


def psnr(q):
    return "∞" if q["psnr_db"] is None else f"{q['psnr_db']:.1f} dB"


def title(k, report):
    """The scene's file name, the size per eye and the run's other flags."""
    words = extras[k]
    flags = []
    j = 0
    while j < len(words):
        if words[j] in ("--width", "--height"):
            j += 2
            continue
        if not words[j].startswith(("--width=", "--height=")):
            flags.append(words[j])
        j += 1
    head = f"{os.path.basename(report['scene'])}, {report['width']}×{report['height']} per eye"
    return f"{head}, {' '.join(flags)}" if flags else head


threads = {r["threads"] for _, r in runs}
rayon = ", ".join(str(t) for t in sorted(threads))
rayon_env = f" (RAYON_NUM_THREADS={env['PR_RAYON']})" if env["PR_RAYON"] else ""
binary = f"`{env['PR_BIN']}`" + ("" if env["PR_BUILT"] == "yes" else " (given with --bin, not built from this checkout: the commit is the checkout's)")

print("# Performance: one run")
print()
print("Written by `scripts/perf-report.sh` (all but [Scale](#scale), kept from the last page); do not")
print("edit by hand, run the script again. How the")
print("numbers are measured and what each column means:")
print("[performance-notes.md](performance-notes.md).")
print()
print(f"- date: {env['PR_DATE']}")
print(f"- commit: `{env['PR_COMMIT']}`")
print(f"- CPU: {env['PR_CPU']}; {env['PR_NPROC']} logical CPUs (nproc); {rayon} rayon threads{rayon_env}")
print(f"- rustc: {env['PR_RUSTC']}; binary {binary}")
busy = float(env["PR_LOAD_AFTER"]) > 1.5 * int(env["PR_NPROC"])
warn = "; above 1.5 × the CPU count at the end: other work shared the CPUs, expect noise" if busy else ""
print(f"- load average (1 min): {env['PR_LOAD']}{warn}")
print(f"- frames per mode: {env['PR_FRAMES']}; times and ray counts are medians over the frames, quality is the worst frame's")
if env["PR_NOTE"]:
    print(f"- note: {env['PR_NOTE']}")
print()
print("Commands, from the repository's root:")
print()
print("```sh")
for cmd, _ in runs:
    print(cmd)
print("```")
print()

print("## Summary")
print()
print("| run | spheres | mono frame ms | full: Mrays/s/core | against the first run |")
print("|-----|---------|---------------|--------------------|-----------------------|")
base = runs[0][1]["modes"]["full"]["mrays_per_s_per_core"]
for k, (cmd, r) in enumerate(runs):
    rate = r["modes"]["full"]["mrays_per_s_per_core"]
    print(f"| {title(k, r)} | {r['spheres']} | {r['mono_ms']:.1f} | {rate:.1f} | {rate / base:.2f}× |")
print()

for k, (cmd, r) in enumerate(runs):
    print(f"## {title(k, r)}")
    print()
    print(f"`{cmd}`")
    print()
    print("| mode | left ms | right ms | right / left rays | stereo / mono frame | PSNR vs full | identical | > 2/255 | Mrays/s/core |")
    print("|------|---------|----------|-------------------|---------------------|--------------|-----------|---------|--------------|")
    for name, m in modes(r):
        q = m["quality"]
        print(
            f"| {name} | {m['left']['ms']:.1f} | {m['right']['ms']:.1f} | {pct(m['ratios']['right_rays_over_left'], 0)} "
            f"| {m['stereo_over_mono']:.2f}× | {psnr(q)} | {identical(q)} "
            f"| {over(q)} | {m['mrays_per_s_per_core']:.1f} |"
        )
    print()
    print("Stages, ms (medians; the right eye is reproject + retrace + reshade):")
    print()
    print("| mode | trace left | reproject | retrace | reshade | stereo |")
    print("|------|------------|-----------|---------|---------|--------|")
    for name, m in modes(r):
        s = m["stages"]
        print(
            f"| {name} | {s['trace_left_ms']:.2f} | {s['reproject_ms']:.2f} | {s['retrace_ms']:.2f} "
            f"| {s['reshade_ms']:.2f} | {m['stereo_ms']:.2f} |"
        )
    print()
    anim = [(name, m["animation"]) for name, m in modes(r) if "animation" in m]
    if anim:
        frames = anim[0][1]["frames"]
        print(f"Animation, {frames} frames 1/60 s apart with the head still: stereo ms per frame traced")
        print("fresh against reusing the last frame (medians; [temporal reuse](design/reuse-exactness.md)):")
        print()
        print("| mode | fresh ms | reused ms | reused / fresh | pixels retraced |")
        print("|------|----------|-----------|----------------|-----------------|")
        for name, a in anim:
            ratio = a["reused_ms"] / a["fresh_ms"] if a["fresh_ms"] > 0 else 0
            print(f"| {name} | {a['fresh_ms']:.2f} | {a['reused_ms']:.2f} | {pct(ratio, 0)} | {pct(a['retraced_share'], 2)} |")
        print()
PY
# The page's last part, from the marker on, is written by hand (the scale table, from
# benches/embree-anchor): kept as it is.
marker='<!-- kept by perf-report.sh -->'
if [[ -f $out ]] && grep -qF "$marker" "$out"; then
  sed -n "/$marker/,\$p" "$out" >> "$tmp_page"
fi
chmod 644 "$tmp_page"
mv -f "$tmp_page" "$out"
tmp_page=
echo "perf-report: wrote $out (commit $commit)" >&2
