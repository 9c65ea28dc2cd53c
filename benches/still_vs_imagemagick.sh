#!/usr/bin/env bash
# Stills, whole process (decode, work, encode), against ImageMagick's -resize of the same file
# to the same size, best of 3 wall times each, with the ratio and vizretarget's per-stage
# milliseconds (--stats). Cases: the crossing-lines scatterplot of issue 21 (1500x800 to
# 750x800, drawn by benches/stills/crossing_lines.py), the first frame of every sample in
# streams/ at half width, and, when they are there, the make_cases.py seed-7 stills
# (../shared/tools) and the real stills of ../shared/data/real at half width (not in the repo:
# made by others).
# Usage: bash benches/still_vs_imagemagick.sh [BIN...]   (default target/release/vizretarget;
# give two binaries to print before and after in one run). Needs python3 with pillow and
# ImageMagick (apt-get install imagemagick).
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -gt 0 ] || { cargo build --release --quiet; set -- target/release/vizretarget; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
im=$(command -v magick || command -v convert) || { echo "needs ImageMagick" >&2; exit 1; }
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"

python3 benches/stills/crossing_lines.py "$tmp/crossing-lines.png"
cases=("$tmp/crossing-lines.png 750x800")
for d in streams/*/; do
  # A stream's first frame; a folder of other samples (streams/marks/) has none.
  f=$(ls "$d" | grep -m1 '^frame-.*\.png$' || true)
  [ -n "$f" ] && cases+=("$d$f half")
done
if [ -f ../shared/tools/make_cases.py ]; then
  python3 ../shared/tools/make_cases.py "$tmp/cases" --seed 7 >/dev/null
  for f in "$tmp"/cases/*.png; do cases+=("$f half"); done
fi
for f in ../shared/data/real/*.png; do [ -f "$f" ] && cases+=("$f half"); done

best() { # best wall time of 3 runs of "$@", in seconds
  local b=999 s e
  for _ in 1 2 3; do
    s=$(date +%s.%N); "$@" >/dev/null 2>&1; e=$(date +%s.%N)
    b=$(echo "if ($e - $s < $b) $e - $s else $b" | bc -l)
  done
  echo "$b"
}
printf '%-28s %-11s %8s' case size imagemagick
for b in "$@"; do printf ' | %8s %6s  %-40s' "$(basename "$b")" ratio "vsm/mesh/solve/render ms"; done
echo
worst=()
for c in "${cases[@]}"; do
  read -r f size <<<"$c"
  if [ "$size" = half ]; then
    size=$(python3 -c "from PIL import Image; w,h=Image.open('$f').size; print(f'{w//2}x{h}')")
  fi
  t_im=$(best "$im" "$f" -resize "$size!" "$tmp/im.png")
  printf '%-28s %-11s %7.3fs' "$(basename "$f")" "$size" "$t_im"
  k=0
  for b in "$@"; do
    t=$(best "$b" "$f" --size "$size" -o "$tmp/out.png" -q)
    stages=$("$b" "$f" --size "$size" -o "$tmp/out.png" --stats 2>&1 |
      sed -n 's/.*vsm \([0-9.]*\) ms, mesh \([0-9.]*\) ms, solve \([0-9.]*\) ms, render \([0-9.]*\) ms.*/\1\/\2\/\3\/\4/p')
    r=$(echo "$t / $t_im" | bc -l)
    printf ' | %7.3fs %5.2fx  %-40s' "$t" "$r" "$stages"
    w=${worst[$k]:-0}
    worst[$k]=$(echo "if ($r > $w) $r else $w" | bc -l)
    k=$((k + 1))
  done
  echo
done
k=0
for b in "$@"; do printf '%s: worst ratio %.2fx\n' "$b" "${worst[$k]}"; k=$((k + 1)); done
