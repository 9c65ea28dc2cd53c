#!/usr/bin/env bash
# The GIF sink beside ffmpeg's two-pass palettegen/paletteuse on the same 60 frames of 640x720
# (drawn by benches/gif_sink.rs). ffmpeg reads raw RGB so that neither side pays for decoding.
# Usage: bash benches/gif_vs_ffmpeg.sh [WORKDIR]   (default /tmp/gif-vs-ffmpeg)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-/tmp/gif-vs-ffmpeg}
mkdir -p "$dir"
GIF_SINK_FRAMES="$dir" cargo bench --bench gif_sink 2>/dev/null | grep '^gif_sink:'
ffmpeg -loglevel error -y -i "$dir/frame-%03d.png" -f rawvideo -pix_fmt rgb24 "$dir/frames.rgb"
best() { # best wall time of 3 runs of "$@", in seconds
    local b=999
    for _ in 1 2 3; do
        local s e
        s=$(date +%s.%N); "$@"; e=$(date +%s.%N)
        b=$(echo "if ($e - $s < $b) $e - $s else $b" | bc -l)
    done
    echo "$b"
}
run_ffmpeg() { # $1: filter graph, $2: output
    ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgb24 -s 640x720 -r 25 -i "$dir/frames.rgb" \
        -vf "$1" "$2"
}
graphs=(
    "split[a][b];[a]palettegen[p];[b][p]paletteuse"
    "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse=diff_mode=rectangle"
    "split[a][b];[a]palettegen[p];[b][p]paletteuse=dither=bayer"
)
for k in "${!graphs[@]}"; do
    out="$dir/ffmpeg-$k.gif"
    t=$(best run_ffmpeg "${graphs[$k]}" "$out")
    printf 'ffmpeg %s: %.3f s = %.1f frames/s, %d KiB\n' "${graphs[$k]}" "$t" \
        "$(echo "60 / $t" | bc -l)" $(( $(stat -c %s "$out") / 1024 ))
done
echo "vizretarget GIF: $dir/vizretarget.gif ($(( $(stat -c %s "$dir/vizretarget.gif") / 1024 )) KiB)"
