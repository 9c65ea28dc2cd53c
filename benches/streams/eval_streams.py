#!/usr/bin/env python3
"""Run vizretarget on the streams of make_streams.py, with and without reuse, and judge the frames.

usage: eval_streams.py STREAMS_DIR BIN [--out DIR] [--json]

For each stream in STREAMS_DIR/streams.json and each of its targets W'xH', runs
  BIN STREAMS_DIR/NAME -o OUT/NAME@W'xH'/reuse/ --size W'xH' -q              (reuse: the default)
  BIN STREAMS_DIR/NAME -o OUT/NAME@W'xH'/fresh/ --size W'xH' -q --no-reuse   (every frame alone)
OUT is --out DIR (kept) or a temporary folder (removed at the end). Figures per stream and
target, for the reused (r) and the fresh (f) frames; --json prints them, with every frame's, as
JSON instead of the table:
  frames  output frames of the right size / expected
  marks   marks found / expected, over all frames. A mark (centre, radius, colour from
          streams.json) is found when a blob of its colour (connected pixels within 70 of it,
          at least 6) has its centroid within the mark's radius (times the smaller of W'/W and
          H'/H) plus 3 px of the mark's centre taken to the target by the frame's map. Each
          blob serves one mark, nearest pairs first. The frame's map is one affine map per
          axis (x a + b, y c + d), fitted by least squares to the blobs found within a wide
          reach (a sixth of the target's smaller side) of where the linear map (x W'/W,
          y H'/H) puts the marks, outliers over 3 px dropped; the linear map where fewer than
          three marks pair up. Kept text bands move a plot by whole pixels and margins that
          give way scale it up: still one map per axis, which a fixed linear map misreads.
  round   median roundness of the found marks: minor / major axis from the blob's second
          moments (1 for a circle; a circle squashed to half its width gives 0.5)
  r!=f    share of the pixels more than 48 levels apart (any channel) between the reused and the
          fresh output of a frame: median and worst frame
  still   share of the output pixels that changed at all from the previous output frame, among
          those where the input did not change: the mask of input pixels that changed at all is
          dilated by the resampler's reach (3 source pixels plus the scale factor, the larger of
          W/W' and H/H'; a square, the resampler being separable) and sampled on the output grid
          by the frame's map (as for marks). Median and worst over
          frames 1 to n-1 (frames whose whole output is covered by the mask are left out).
Exits 1 with a message naming the run if BIN fails. Needs numpy, scipy and pillow.
"""
import argparse, json, math, os, shutil, subprocess, sys, tempfile
import numpy as np
from PIL import Image
from scipy import ndimage

COLOUR_DIST = 70     # a blob's pixels lie within this distance (RGB) of the mark's colour
MIN_BLOB = 6         # fewest pixels of a blob
NEAR_PX = 3          # a blob's centroid lies within the mark's radius plus this of its place
APART = 48           # levels (any channel) that make a pixel differ between reuse and fresh
MODES = {"reuse": [], "fresh": ["--no-reuse"]}


def load(path, size):
    """RGB pixels (int32) of path, or None if it is missing or not of the target size."""
    if not os.path.exists(path):
        return None
    im = Image.open(path)
    return np.asarray(im.convert("RGB")).astype(np.int32) if im.size == tuple(size) else None


def blobs(img, colour):
    """Blobs of pixels near colour: arrays of centroids x, y (pixel centres at i + 0.5) and
    roundness (sqrt of the smaller over the larger eigenvalue of the second moments)."""
    lab, n = ndimage.label(np.sqrt(((img - colour) ** 2).sum(-1)) < COLOUR_DIST)
    if n == 0:
        return np.zeros((3, 0))
    ys, xs = np.indices(lab.shape, dtype=float)
    idx = np.arange(1, n + 1)
    cnt = ndimage.sum_labels(np.ones_like(xs), lab, idx)
    keep = cnt >= MIN_BLOB
    m = lambda a: ndimage.sum_labels(a, lab, idx)[keep] / cnt[keep]
    mx, my = m(xs), m(ys)
    vxx, vyy, vxy = m(xs * xs) - mx * mx, m(ys * ys) - my * my, m(xs * ys) - mx * my
    half, disc = (vxx + vyy) / 2, np.sqrt(((vxx - vyy) / 2) ** 2 + vxy ** 2)
    rnd = np.sqrt(np.maximum(half - disc, 1e-9) / np.maximum(half + disc, 1e-9))
    return np.vstack([mx + 0.5, my + 0.5, rnd])


def pair_marks(img, marks, amap, reach):
    """For each expected mark, the blob (x, y, roundness) paired with it, or None: blobs of
    its colour whose centroid lies within the mark's scaled radius plus reach of where amap
    (ax, bx, ay, by) puts its centre; each blob serves one mark, nearest pairs first."""
    found = [None] * len(marks)
    if img is None:
        return found
    ax, bx, ay, by = amap
    for colour in {tuple(m["rgb"]) for m in marks}:
        cx, cy, rnd = blobs(img, np.array(colour))
        pairs = []
        for i, m in enumerate(marks):
            if tuple(m["rgb"]) != colour:
                continue
            tol = m["r"] * min(ax, ay) + reach
            d = np.hypot(cx - (m["x"] * ax + bx), cy - (m["y"] * ay + by))
            pairs += [(d[j], i, j) for j in np.nonzero(d <= tol)[0]]
        used = set()
        for _, i, j in sorted(pairs):
            if found[i] is None and j not in used:
                found[i] = (float(cx[j]), float(cy[j]), float(rnd[j]))
                used.add(j)
    return found


def fit_map(img, marks, sx, sy):
    """The frame's map (ax, bx, ay, by): least squares, per axis, from the marks paired within
    a wide reach of the linear map, outliers over NEAR_PX dropped; the linear map where fewer
    than three pair up or an axis' marks do not spread."""
    linear = (sx, 0.0, sy, 0.0)
    if img is None:
        return linear
    h, w = img.shape[:2]
    pairs = [(m, f) for m, f in zip(marks, pair_marks(img, marks, linear, min(w, h) / 6)) if f]
    amap = linear
    for _ in range(2):
        if len(pairs) < 3:
            return linear
        fit = []
        for src, out in ((0, 0), (1, 1)):
            u = np.array([p[0]["x" if src == 0 else "y"] for p in pairs])
            v = np.array([p[1][out] for p in pairs])
            if np.ptp(u) < 1e-6:
                return linear
            a, b = np.polyfit(u, v, 1)
            fit += [float(a), float(b)]
        amap = tuple(fit)
        ax, bx, ay, by = amap
        pairs = [p for p in pairs if math.hypot(p[1][0] - (p[0]["x"] * ax + bx),
                                                p[1][1] - (p[0]["y"] * ay + by)) <= NEAR_PX]
    return amap


def find_marks(img, marks, amap):
    """Roundness of the blob found for each expected mark under the frame's map, None where
    none is found."""
    return [f[2] if f else None for f in pair_marks(img, marks, amap, NEAR_PX)]


def still_share(in0, in1, out0, out1, reach, amap):
    """Share of output pixels that changed among those whose input did not change (None if
    the dilated input change covers the whole output or a frame is missing); output pixels
    are taken back to the input by the frame's map amap."""
    if out0 is None or out1 is None:
        return None
    changed = ndimage.maximum_filter((in0 != in1).any(-1), size=2 * math.ceil(reach) + 1)
    (h, w), (th, tw) = in0.shape[:2], out0.shape[:2]
    ax, bx, ay, by = amap
    ys = np.clip(((np.arange(th) + 0.5 - by) / ay).astype(int), 0, h - 1)
    xs = np.clip(((np.arange(tw) + 0.5 - bx) / ax).astype(int), 0, w - 1)
    still = ~changed[ys][:, xs]
    if not still.any():
        return None
    return float(((out0 != out1).any(-1) & still).sum() / still.sum())


def run(binary, src, dst, size, extra, label):
    if os.path.exists(dst):
        shutil.rmtree(dst)
    os.makedirs(dst)
    cmd = [binary, src, "-o", dst + os.sep, "--size", "%dx%d" % tuple(size), "-q"] + extra
    try:
        p = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as e:
        sys.exit(f"eval_streams: cannot run {binary}: {e}")
    if p.returncode != 0:
        sys.exit(f"eval_streams: {label} failed (exit {p.returncode}): {' '.join(cmd)}\n"
                 f"{(p.stderr or p.stdout).strip() or '(no message)'}")


def med_max(xs):
    xs = [x for x in xs if x is not None]
    return [float(np.median(xs)), float(max(xs))] if xs else [None, None]


def judge(stream, sdir, odir, size):
    """Figures of one stream at one target, from its reused and fresh output folders."""
    w, h, (tw, th) = stream["width"], stream["height"], size
    sx, sy = tw / w, th / h
    reach = 3 + max(w / tw, h / th)
    ins = [load(os.path.join(sdir, stream["dir"], f), (w, h)) for f in stream["frames"]]
    outs = {m: [load(os.path.join(odir, m, f), size) for f in stream["frames"]] for m in MODES}
    frames = []
    for k, marks in enumerate(stream["marks"]):
        fr = {"frame": stream["frames"][k], "expected": len(marks)}
        for m in MODES:
            o = outs[m][k]
            amap = fit_map(o, marks, sx, sy)
            rnd = [x for x in find_marks(o, marks, amap) if x is not None]
            fr[m] = {"ok": o is not None, "found": len(rnd), "map": list(amap),
                     "round": float(np.median(rnd)) if rnd else None, "rounds": rnd,
                     "still": still_share(ins[k - 1], ins[k], outs[m][k - 1], o, reach, amap)
                     if k else None}
        r, f = outs["reuse"][k], outs["fresh"][k]
        fr["apart"] = float((np.abs(r - f).max(-1) > APART).mean()) if r is not None and f is not None else None
        frames.append(fr)
    res = {"target": list(size), "frames_expected": len(frames)}
    for m in MODES:
        rounds = [x for fr in frames for x in fr[m].pop("rounds")]
        res[m] = {"frames": sum(fr[m]["ok"] for fr in frames),
                  "found": sum(fr[m]["found"] for fr in frames),
                  "expected": sum(fr["expected"] for fr in frames),
                  "round": float(np.median(rounds)) if rounds else None,
                  "still": med_max([fr[m]["still"] for fr in frames])}
    res["apart"] = med_max([fr["apart"] for fr in frames])
    res["per_frame"] = frames
    return res


def pct(x):
    return "-" if x is None else f"{100 * x:.2f}%"


def table(report):
    cols = [("stream@target", 24), ("frames r,f", 11), ("marks r", 10), ("marks f", 10),
            ("round r/f", 10), ("r!=f med/max", 15), ("still r med/max", 16), ("still f med/max", 16)]
    lines = ["".join(c.ljust(n) for c, n in cols).rstrip()]
    for key, v in report.items():
        r, f = v["reuse"], v["fresh"]
        rd = lambda x: "-" if x is None else f"{x:.2f}"
        cells = [key, f"{r['frames']},{f['frames']}/{v['frames_expected']}",
                 f"{r['found']}/{r['expected']}", f"{f['found']}/{f['expected']}",
                 f"{rd(r['round'])}/{rd(f['round'])}", "/".join(map(pct, v["apart"])),
                 "/".join(map(pct, r["still"])), "/".join(map(pct, f["still"]))]
        lines.append("".join(c.ljust(n) for c, (_, n) in zip(cells, cols)).rstrip())
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("streams_dir")
    ap.add_argument("bin")
    ap.add_argument("--out", help="keep the outputs here (default: a temporary folder)")
    ap.add_argument("--json", action="store_true", help="print JSON, with per-frame figures")
    a = ap.parse_args()
    spec = os.path.join(a.streams_dir, "streams.json")
    if not os.path.exists(spec):
        sys.exit(f"eval_streams: no {spec}: make the streams with make_streams.py first")
    streams = json.load(open(spec))["streams"]
    binary = os.path.abspath(a.bin) if os.path.exists(a.bin) else a.bin
    out = a.out or tempfile.mkdtemp(prefix="eval_streams-")
    report = {}
    try:
        for s in streams:
            for size in s["targets"]:
                key = f"{s['name']}@{size[0]}x{size[1]}"
                odir = os.path.join(out, key)
                for m, extra in MODES.items():
                    run(binary, os.path.join(a.streams_dir, s["dir"]), os.path.join(odir, m), size,
                        extra, f"{key} ({m})")
                report[key] = judge(s, a.streams_dir, odir, size)
    finally:
        if not a.out:
            shutil.rmtree(out, ignore_errors=True)
    print(json.dumps(report) if a.json else table(report))


if __name__ == "__main__":
    main()
