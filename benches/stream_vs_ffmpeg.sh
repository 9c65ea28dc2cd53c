#!/usr/bin/env bash
# End-to-end stream throughput: raw RGB24 1280x720 frames through stdin -> 720x720 raw frames
# on stdout, vizretarget beside ffmpeg's scale filter on the same frames, for three streams:
# static content, three small marks moving, every frame different. Also the peak memory of
# 5000 raw 640x360 frames through vizretarget. Needs ffmpeg (apt-get install ffmpeg).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --example raw_frames
cargo build --release --quiet
N=${N:-150}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for kind in static movers changing; do
  target/release/examples/raw_frames "$kind" "$N" 1280x720 > "$tmp/$kind.raw"
  t0=$(date +%s.%N)
  target/release/vizretarget - --input-format rgb24 --input-size 1280x720 --size 720x720 \
    --output-format rgb24 -o - -q < "$tmp/$kind.raw" > /dev/null
  t1=$(date +%s.%N)
  ffmpeg -loglevel error -f rawvideo -pix_fmt rgb24 -s 1280x720 -i "$tmp/$kind.raw" \
    -vf scale=720:720 -f rawvideo -pix_fmt rgb24 - > /dev/null
  t2=$(date +%s.%N)
  python3 -c "print(f'$kind: vizretarget {$N/($t1-$t0):.1f} fps, ffmpeg scale {$N/($t2-$t1):.1f} fps ($N frames)')"
done
target/release/examples/raw_frames movers 5000 640x360 > "$tmp/m.raw"
/usr/bin/time -v target/release/vizretarget - --input-format rgb24 --input-size 640x360 --size 360x360 \
  --output-format rgb24 -o - -q < "$tmp/m.raw" 2> "$tmp/time.txt" > /dev/null
echo "5000 frames 640x360 -> 360x360: peak RSS $(grep 'Maximum resident' "$tmp/time.txt" | awk '{print $NF}') kB"
