#!/usr/bin/env bash
# Soak test of the viewer (not run in CI): the window under Xvfb for DURATION seconds
# (default 600) while xdotool drags the panel's sliders, toggles the mask (M), pauses (Space),
# switches modes and resizes the window. RSS is recorded every 10 s; the run fails if the
# viewer dies or its memory grows past the warm-up.
#
#   scripts/soak.sh [DURATION_S] [SCENE]
#
# Needs: xvfb xauth xdotool (apt-get install xvfb xauth xdotool), a release build.
set -euo pipefail
cd "$(dirname "$0")/.."

duration=${1:-600}
scene=${2:-assets/scenes/seed.toml}
warmup=60          # seconds before the baseline is taken
slack_kib=$((32 * 1024))  # growth allowed past the warm-up maximum, plus 10 %

for tool in Xvfb xdotool; do
  command -v "$tool" >/dev/null || { echo "soak: $tool not found (apt-get install xvfb xauth xdotool)" >&2; exit 2; }
done
cargo build --release --quiet
bin=target/release/stereotrace

display=:$((90 + RANDOM % 9))
Xvfb "$display" -screen 0 1920x1080x24 -nolisten tcp >/dev/null 2>&1 &
xvfb=$!
log=$(mktemp -d)/soak
mkdir -p "$log"
cleanup() { kill "$viewer" "$xvfb" 2>/dev/null || true; }
trap cleanup EXIT
sleep 1

DISPLAY=$display "$bin" --scene "$scene" >"$log/viewer.out" 2>"$log/viewer.err" &
viewer=$!
export DISPLAY=$display

# Wait for the window.
win=""
for _ in $(seq 1 100); do
  win=$(xdotool search --pid "$viewer" 2>/dev/null | head -n 1 || true)
  [ -n "$win" ] && break
  sleep 0.2
done
[ -n "$win" ] || { echo "soak: the viewer window never appeared" >&2; cat "$log/viewer.err" >&2; exit 1; }

rss() { awk '/^VmRSS:/ {print $2}' "/proc/$viewer/status" 2>/dev/null || echo 0; }

sizes=("1600 600" "800 300" "1920 1080" "300 200" "1280 720" "1 1" "8200 600")
keys=(m space m 1 2 3 4 space)
start=$(date +%s)
next_sample=$start
warm_max=0
max_after=0
printf '%6s %10s %s\n' "t (s)" "RSS (KiB)" "action"
step=0
while :; do
  now=$(date +%s)
  elapsed=$((now - start))
  [ "$elapsed" -ge "$duration" ] && break
  if ! kill -0 "$viewer" 2>/dev/null; then
    echo "soak: FAIL: the viewer died after ${elapsed}s" >&2
    tail -n 20 "$log/viewer.err" >&2
    exit 1
  fi
  step=$((step + 1))
  action=""
  case $((step % 6)) in
    0) read -r w h <<<"${sizes[$((step / 6 % ${#sizes[@]}))]}"
       xdotool windowsize "$win" "$w" "$h" 2>/dev/null || true; action="resize ${w}x${h}" ;;
    1|2|3) x=$((40 + RANDOM % 220)); y=$((60 + RANDOM % 260)); dx=$((RANDOM % 200 - 100))
       xdotool mousemove --window "$win" "$x" "$y" mousedown 1 mousemove_relative -- "$dx" 0 mouseup 1 2>/dev/null || true
       action="drag at $x,$y by $dx" ;;
    4) k=${keys[$((step / 6 % ${#keys[@]}))]}
       xdotool windowfocus "$win" key "$k" 2>/dev/null || true; action="key $k" ;;
    5) xdotool windowminimize "$win" 2>/dev/null || true; sleep 0.5
       xdotool windowmap "$win" 2>/dev/null || true; action="minimise and restore" ;;
  esac
  if [ "$now" -ge "$next_sample" ]; then
    r=$(rss)
    printf '%6d %10d %s\n' "$elapsed" "$r" "$action"
    if [ "$elapsed" -lt "$warmup" ]; then
      [ "$r" -gt "$warm_max" ] && warm_max=$r
    else
      [ "$r" -gt "$max_after" ] && max_after=$r
    fi
    next_sample=$((next_sample + 10))
  fi
  sleep 0.5
done

limit=$((warm_max + warm_max / 10 + slack_kib))
echo "warm-up max RSS ${warm_max} KiB; after warm-up max ${max_after} KiB; limit ${limit} KiB"
if [ "$max_after" -gt "$limit" ]; then
  echo "soak: FAIL: memory grew past the warm-up" >&2
  exit 1
fi
echo "soak: PASS (${duration}s, viewer alive, RSS flat)"
