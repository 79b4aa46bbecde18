#!/usr/bin/env bash
# Checksums of everything a build renders, for proving that a change keeps the output byte
# for byte: every bundled scene, every mode, two sizes and times, masks, supersampling, and
# animations with and without temporal reuse; and the deterministic keys of the JSON report
# (rays, pixel classes, quality; not the times, and not the keys added since c970a4e,
# `spheres` and the heap bytes under `memory`, so that its list still compares).
#
#   scripts/same-bytes.sh BINARY OUT.txt        # then: diff before.txt after.txt
#
# A developer's tool, not part of CI (it takes a minute or two).
set -euo pipefail
bin=$(realpath "$1")
out=$(realpath -m "$2")
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

modes=("full" "copy" "copy --retrace-edges" "reshade" "reshade --retrace-edges" "exact")
keys='import json,sys
r=json.load(sys.stdin)
def strip(v):
    if isinstance(v,dict): return {k:strip(x) for k,x in v.items() if not (k.endswith("ms") or k in ("stages","ratios","threads","lanes","mrays_per_s_per_core","memory","spheres"))}
    return v
print(json.dumps(strip(r),sort_keys=True))'

{
  for scene in seed many thousand window; do
    for size in "320 180 0" "203 97 1.3"; do
      read -r w h t <<<"$size"
      for mode in "${modes[@]}"; do
        tag="$scene-${w}x$h-t$t-${mode// /}"
        # shellcheck disable=SC2086
        "$bin" render --scene "assets/scenes/$scene.toml" --width "$w" --height "$h" --time "$t" --mode $mode \
          --left "$work/l.png" --right "$work/r.png" --mask "$work/m.png" --json >"$work/j.json"
        echo "$tag $(cat "$work/l.png" "$work/r.png" "$work/m.png" | sha256sum | cut -c1-16)" \
          "$(python3 -c "$keys" <"$work/j.json" | sha256sum | cut -c1-16)"
      done
    done
  done
  for mode in "${modes[@]}"; do
    # shellcheck disable=SC2086
    "$bin" render --scene assets/scenes/seed.toml --width 1280 --height 720 --mode $mode \
      --left "$work/l.png" --right "$work/r.png" --mask "$work/m.png"
    echo "seed-1280x720-${mode// /} $(cat "$work/l.png" "$work/r.png" "$work/m.png" | sha256sum | cut -c1-16)"
    for scene in seed window; do
      # shellcheck disable=SC2086
      "$bin" render --scene "assets/scenes/$scene.toml" --width 160 --height 90 --time 0.7 --mode $mode \
        --supersample 2 --left "$work/l.png" --right "$work/r.png" --mask "$work/m.png" --json >"$work/j.json"
      echo "$scene-ss2-${mode// /} $(cat "$work/l.png" "$work/r.png" "$work/m.png" | sha256sum | cut -c1-16)" \
        "$(python3 -c "$keys" <"$work/j.json" | sha256sum | cut -c1-16)"
    done
    for scene in seed window thousand; do
      for reuse in "" "--no-reuse"; do
        rm -rf "$work/anim"
        # shellcheck disable=SC2086
        "$bin" render --scene "assets/scenes/$scene.toml" --width 240 --height 135 --mode $mode --frames 5 --fps 60 \
          $reuse --out-dir "$work/anim" 2>/dev/null
        echo "$scene-anim${reuse}-${mode// /} $(cat "$work"/anim/*.png | sha256sum | cut -c1-16)"
      done
    done
  done
} >"$out"
echo "wrote $(wc -l <"$out") checksums to $out"
