#!/usr/bin/env bash
# Regenerates the figures of docs/paper.md (our versions of the seed paper's figures) in
# docs/img/, and the reports their numbers come from in docs/paper-data/, with the release
# binary. Every command here is the one docs/paper.md shows beside its figure.
#
# Usage: scripts/paper-figures.sh            (from anywhere; writes into the repository)
#
# Rays, pixel classes and quality are the same on every machine, thread count and SIMD width;
# times (the *_ms keys, the sweep's time curves) are this machine's and vary from run to run.
set -euo pipefail
cd "$(dirname "$0")/.."

if [[ $# -gt 0 ]]; then
  sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi

st() { cargo run --release --locked --quiet -- "$@"; }

img=docs/img
data=docs/paper-data
mkdir -p "$img" "$data"

echo "== building the release binary"
cargo build --release --locked --quiet

echo "== Fig. 1: the stereo pair, copy mode (the paper) and exact mode (ours)"
st render --mode copy --width 640 --height 360 --out "$img/fig1-copy-pair.png" --json >"$data/fig1-copy.json"
st render --mode exact --width 640 --height 360 --out "$img/fig1-exact-pair.png" --json >"$data/fig1-exact.json"
st render --mode reshade --width 640 --height 360 --json >"$data/fig1-reshade.json"

echo "== Fig. 2: the debug-colour mask, copy mode and exact mode"
st render --mode copy --width 640 --height 360 --mask "$img/fig2-copy-mask.png"
st render --mode exact --width 640 --height 360 --mask "$img/fig2-exact-mask.png"

echo "== Fig. 3: the lighting seams, a crop of the right eye and where it differs from a full trace"
for mode in copy reshade exact; do
  st render --mode "$mode" --width 1280 --height 720 --crop 0,200,420,330 \
    --right "$img/fig3-$mode-right.png" --diff "$img/fig3-$mode-diff.png" --json >"$data/fig3-$mode.json"
done

echo "== §5.1: the ray shares (bench), and the IPD sweep"
st bench --frames 5 --json >"$data/bench.json"
st sweep --param ipd --from 0 --to 2 --steps 11 --frames 3 --csv "$data/sweep-ipd.csv" --plot "$img/sweep-ipd.png"

echo "== the timewarp: PSNR of the displayed frame against its age, seed scene turning 30°/s"
st timewarp --scene assets/scenes/seed.toml --width 800 --height 600 --motion yaw=30 --display-hz 90 \
  --trace-every 1..6 --plot "$img/timewarp-seed.png" --json >"$data/timewarp-seed.json"

echo "== done: $(ls "$img" | wc -l) images in $img, reports in $data"
