#!/usr/bin/env bash
# Do two builds draw the same bytes? For refactors that must not change any output.
# Runs BIN_A and BIN_B (`vizretarget` binaries) on:
#   - every sample in streams/ (the GIF to a GIF, the folder of PNG frames to a folder);
#   - the make_cases.py seed-7 stills at their targets and its stream folder (../shared/tools);
#   - the make_charts.py seed-7 charts at half width and 60 % height;
#   - the real stills of ../shared/data/real at half width and 60 % height (made by others, not
#     in the repo; skipped when absent);
# each under the default regions and again under `--regions free` (the paper's warp everywhere)
# and `--regions auto`, so that the mesh, the solve and the warp's render are exercised too;
# and compares every output file byte for byte. Prints each difference; exits 1 if any.
# Usage: bash benches/same_outputs.sh BIN_A BIN_B   (needs python3 with numpy, pillow,
# matplotlib for the generated cases).
set -uo pipefail
[ $# -eq 2 ] || { echo "usage: $0 BIN_A BIN_B" >&2; exit 2; }
A=$(readlink -f "$1"); B=$(readlink -f "$2")
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
jobs=()   # "IN|ARGS|NAME": NAME ending in / is a folder output
for s in streams/*; do
  n=$(basename "$s")
  if [ -d "$s" ]; then jobs+=("$s|--width 240|$n/"); else jobs+=("$s|--width 240|$n"); fi
done
if [ -f ../shared/tools/make_cases.py ]; then
  python3 ../shared/tools/make_cases.py "$tmp/cases" --seed 7 >/dev/null
  while IFS='|' read -r in size name; do jobs+=("$in|--size $size|cases-$name"); done < <(
    python3 - "$tmp/cases" <<'PY'
import json, os, sys
d = sys.argv[1]
for c in json.load(open(os.path.join(d, "cases.json"))):
    w, h = c["target"]
    if "frames" in c:
        print(f"{os.path.join(d, c['dir'])}|{w}x{h}|{c['dir']}/")
    else:
        print(f"{os.path.join(d, c['file'])}|{w}x{h}|{c['file']}")
PY
  )
fi
stills=()
if [ -f ../shared/tools/make_charts.py ]; then
  python3 ../shared/tools/make_charts.py "$tmp/charts" --seed 7 >/dev/null 2>&1 &&
    stills+=("$tmp"/charts/*.png)
fi
for f in ../shared/data/real/*.png; do [ -f "$f" ] && stills+=("$f"); done
for f in "${stills[@]}"; do
  read -r w h < <(python3 -c "from PIL import Image; print(*Image.open('$f').size)")
  n=$(basename "$f" .png)
  jobs+=("$f|--size $((w / 2))x$h|$n@halfw.png" "$f|--size ${w}x$((h * 6 / 10))|$n@h60.png")
done
differ=0; total=0
for j0 in "${jobs[@]}"; do
 for regions in affine free auto; do
  IFS='|' read -r in args name <<<"$j0"
  args="$args --regions $regions"; name="$regions/$name"
  for side in A B; do
    bin=$A; [ $side = B ] && bin=$B
    out="$tmp/$side/$name"; mkdir -p "$(dirname "$out")"
    # shellcheck disable=SC2086
    "$bin" "$in" -o "$out" $args -q 2>"$tmp/err" || { echo "$name ($side): failed: $(tail -1 "$tmp/err")"; differ=1; }
  done
  total=$((total + 1))
  if ! diff -rq "$tmp/A/$name" "$tmp/B/$name" >/dev/null 2>&1; then
    echo "differs: $name"; differ=1
  fi
 done
done
echo "$total cases; $([ $differ = 0 ] && echo "all outputs identical" || echo "some differ")"
exit $differ
