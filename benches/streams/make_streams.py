#!/usr/bin/env python3
"""Animated matplotlib charts as folders of PNG frames, to benchmark vizretarget on streams.

usage: make_streams.py OUT_DIR [--seed N] [--frames N]

Writes OUT_DIR/NAME/frame-0000.png ... for each stream below, and OUT_DIR/streams.json.
  bubbles         gapminder-like scatter with axes, grid and the year: bubbles drift, most
                  grow, some shrink
  bubbles-facets  the same in 2x2 facets sharing their axes, one region (colour) per facet
  bar-race        horizontal bars that change length and reorder by value, a round dot at the
                  end of each bar and a value label beside it
  live-line       a line with markers: a new point each frame, the x window slides by one;
                  the newest point is larger and orange
  dashboard       2x2 panels; only the bottom-right line chart changes, the other three panels
                  are byte-identical in every frame (checked here: the script fails if not)

streams.json: {"seed", "dpi", "streams": [{"name", "dir", "width", "height", "frames": [file
names], "targets": [[w, h], ...] (half the width; 60 % of the height), "marks": [[{"x", "y",
"r", "rgb"}, ...] for each frame]}]}. A mark is a round filled marker without outline: x, y its
centre in pixels from the image's top-left corner (pixel column i covers [i, i+1)), r its radius
in pixels, rgb its colour (one of COLOURS). Centres come from matplotlib's data->display
transform, so they are exact; the pixel under each centre is checked to carry its colour. Marks
never touch one another, so eval_streams.py can find each as a blob of its colour.
The same seed and frame count give the same bytes (Agg, fixed dpi, numpy's seeded generator;
same matplotlib and fonts). Needs numpy, matplotlib and pillow.
"""
import argparse, json, os
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from PIL import Image

DPI = 100
# Mark colours (RGB): pairwise over 100 apart, over 90 from any grey (text, grid, lines).
RED, BLUE, GREEN, ORANGE, PURPLE, TEAL = ((220, 30, 40), (30, 90, 210), (20, 150, 50),
                                          (245, 140, 0), (150, 40, 180), (0, 180, 170))
COLOURS = [RED, BLUE, GREEN, ORANGE, PURPLE, TEAL]
GRID = dict(color="#dddddd", linewidth=0.8)
NAMES = ["Lagos", "Lima", "Oslo", "Perth", "Quito", "Seoul", "Tunis", "Porto", "Dakar", "Hanoi"]


def hexc(c):
    return "#%02x%02x%02x" % c


def tint(c, k=0.45):
    """c mixed with white: over 130 from c, so a tinted bar never joins a mark's blob."""
    return hexc(tuple(int(round(k * v + (1 - k) * 255)) for v in c))


def area_pt2(r_px):
    """Scatter marker size (points^2) of a disc of radius r_px pixels."""
    return (2 * np.asarray(r_px) * 72 / DPI) ** 2


def paths(rng, w, h, n, frames, r_range, moving=True, gap=5, tries=50000):
    """n disc paths (xs, ys, rs in px over the frames) inside a w x h box that never leave it
    and never come within gap px of one another. Moving discs drift right and mostly up with a
    smooth start and stop; 70 % grow, 30 % shrink (to no less than 4 px)."""
    u = np.linspace(0, 1, frames)
    u = u * u * (3 - 2 * u)
    out = []
    for _ in range(tries):
        if len(out) == n:
            return out
        r0 = rng.uniform(*r_range)
        x0, y0 = rng.uniform(0, w), rng.uniform(0, h)
        if moving:
            r1 = r0 * (rng.uniform(0.55, 0.85) if rng.random() < 0.3 else rng.uniform(1.15, 1.6))
            r1 = max(r1, 4.0)
            x1, y1 = x0 + rng.uniform(0.05, 0.3) * w, y0 + rng.uniform(-0.05, 0.3) * h
        else:
            r1, x1, y1 = r0, x0, y0
        xs, ys, rs = x0 + (x1 - x0) * u, y0 + (y1 - y0) * u, r0 + (r1 - r0) * u
        if (xs < rs + 3).any() or (ys < rs + 3).any() or (xs > w - rs - 3).any() or (ys > h - rs - 3).any():
            continue
        if all((np.hypot(xs - qx, ys - qy) > rs + qr + gap).all() for qx, qy, qr in out):
            out.append((xs, ys, rs))
    raise SystemExit(f"make_streams: could not place {n} discs of radius {r_range} in {w:.0f}x{h:.0f} px")


def to_data(ax, xs, ys):
    """Axes-box pixels (from the box's bottom-left corner) to data coordinates."""
    bb = ax.get_window_extent()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    return x0 + xs / bb.width * (x1 - x0), y0 + ys / bb.height * (y1 - y0)


def style(ax, xlabel, ylabel, grid="both"):
    ax.set_xlabel(xlabel, fontsize=10)
    ax.set_ylabel(ylabel, fontsize=10)
    ax.tick_params(labelsize=9)
    for s in ("top", "right"):
        ax.spines[s].set_visible(False)
    if grid:
        ax.grid(True, axis=grid, **GRID)
        ax.set_axisbelow(True)


def figure(w, h, **adjust):
    fig = plt.figure(figsize=(w / DPI, h / DPI), dpi=DPI, facecolor="white")
    fig.subplots_adjust(**adjust)
    return fig


def render(fig, marks):
    """Draws fig; returns its RGB pixels and its marks. marks: (ax, x, y, r_px, colours) in data
    coordinates, one entry per scatter."""
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
    h = rgb.shape[0]
    found = []
    for ax, x, y, r, cs in marks:
        disp = ax.transData.transform(np.column_stack([x, y]))
        for (dx, dy), ri, c in zip(disp, np.broadcast_to(r, len(disp)), cs):
            found.append({"x": round(float(dx), 3), "y": round(float(h - dy), 3),
                          "r": round(float(ri), 3), "rgb": list(c)})
    return rgb, found


# A stream: fn(rng, frames) -> (draw, static); draw(f) -> (fig, marks) of frame f, static(fig)
# -> the axes that must stay byte-identical in every frame (static None: no such axes).

def bubbles(rng, frames):
    regions = [("Africa", RED), ("Americas", BLUE), ("Asia", ORANGE), ("Europe", GREEN), ("Oceania", TEAL)]
    fig0 = figure(800, 500, left=0.09, right=0.97, top=0.9, bottom=0.12)
    bb = fig0.add_subplot(111).get_window_extent()
    plt.close(fig0)
    ps = paths(rng, bb.width, bb.height, 13, frames, (6, 24))
    cs = [regions[i % len(regions)][1] for i in range(len(ps))]

    def draw(f):
        fig = figure(800, 500, left=0.09, right=0.97, top=0.9, bottom=0.12)
        ax = fig.add_subplot(111)
        ax.set_xlim(0, 60); ax.set_ylim(40, 85)
        style(ax, "GDP per capita (k$)", "Life expectancy (years)")
        x, y = to_data(ax, np.array([p[0][f] for p in ps]), np.array([p[1][f] for p in ps]))
        r = np.array([p[2][f] for p in ps])
        ax.scatter(x, y, s=area_pt2(r), c=[hexc(c) for c in cs], linewidths=0, zorder=2)
        ax.text(0.98, 0.04, str(1990 + f), transform=ax.transAxes, ha="right", fontsize=44,
                color="#e8e8e8", zorder=0)
        ax.set_title("Income and health, by country", fontsize=13)
        return fig, [(ax, x, y, r, cs)]
    return draw, None


def bubbles_facets(rng, frames):
    regions = [("Africa", RED), ("Americas", BLUE), ("Asia", ORANGE), ("Europe", GREEN)]
    adjust = dict(left=0.09, right=0.97, top=0.88, bottom=0.1, wspace=0.08, hspace=0.22)
    fig0 = figure(800, 560, **adjust)
    bb = fig0.subplots(2, 2)[0, 0].get_window_extent()
    plt.close(fig0)
    ps = [paths(rng, bb.width, bb.height, 5, frames, (5, 13)) for _ in regions]

    def draw(f):
        fig = figure(800, 560, **adjust)
        axs = fig.subplots(2, 2, sharex=True, sharey=True)
        marks = []
        for ax, (name, c), pp in zip(axs.flat, regions, ps):
            ax.set_xlim(0, 60); ax.set_ylim(40, 85)
            style(ax, "", "")
            x, y = to_data(ax, np.array([p[0][f] for p in pp]), np.array([p[1][f] for p in pp]))
            r = np.array([p[2][f] for p in pp])
            ax.scatter(x, y, s=area_pt2(r), c=hexc(c), linewidths=0, zorder=2)
            ax.set_title(name, fontsize=11)
            marks.append((ax, x, y, r, [c] * len(pp)))
        fig.supxlabel("GDP per capita (k$)", fontsize=10); fig.supylabel("Life expectancy (years)", fontsize=10)
        fig.suptitle(f"Income and health by region, {1990 + f}", fontsize=13)
        return fig, marks
    return draw, None


def bar_race(rng, frames):
    n = len(COLOURS)
    names = list(rng.choice(NAMES, n, replace=False))
    v = rng.uniform(20, 60, n)[:, None] + np.cumsum(rng.uniform(0.2, 3.2, (n, frames)), axis=1)
    xmax = float(v.max()) * 1.2
    r_dot = 9.0

    def draw(f):
        fig = figure(800, 500, left=0.12, right=0.96, top=0.9, bottom=0.1)
        ax = fig.add_subplot(111)
        vals = v[:, f]
        rank = np.argsort(np.argsort(-vals))  # 0 for the largest
        y = n - 1 - rank
        ax.barh(y, vals, height=0.62, color=[tint(c) for c in COLOURS], linewidth=0, zorder=1)
        ax.scatter(vals, y, s=area_pt2(r_dot), c=[hexc(c) for c in COLOURS], linewidths=0, zorder=2)
        for vi, yi in zip(vals, y):
            ax.annotate(f"{vi:,.1f}", (vi, yi), xytext=(14, 0), textcoords="offset points",
                        va="center", fontsize=10, color="#333333")
        ax.set_yticks(y, names)
        ax.set_xlim(0, xmax); ax.set_ylim(-0.6, n - 0.4)
        style(ax, "Visitors (thousands)", "", grid="x")
        ax.set_title(f"Most visited cities, week {f + 1}", fontsize=13)
        return fig, [(ax, vals, y, r_dot, COLOURS)]
    return draw, None


def live_line(rng, frames):
    window = 16
    series = 50 + np.cumsum(rng.normal(0, 4, window + frames - 1))
    lo, hi = series.min(), series.max()
    ylim = (lo - 0.15 * (hi - lo), hi + 0.15 * (hi - lo))

    def draw(f):
        fig = figure(800, 500, left=0.09, right=0.97, top=0.9, bottom=0.12)
        ax = fig.add_subplot(111)
        x = np.arange(f, f + window)
        y = series[f:f + window]
        ax.plot(x, y, color="#888888", linewidth=1.5, zorder=1)
        r = np.full(window, 6.0); r[-1] = 8.0
        cs = [BLUE] * (window - 1) + [ORANGE]
        ax.scatter(x, y, s=area_pt2(r), c=[hexc(c) for c in cs], linewidths=0, zorder=2)
        ax.set_xlim(f - 0.6, f + window - 0.4); ax.set_ylim(*ylim)
        style(ax, "Minute", "Requests per second")
        ax.set_title("Requests, last 16 minutes (live)", fontsize=13)
        return fig, [(ax, x, y, r, cs)]
    return draw, None


def dashboard(rng, frames):
    adjust = dict(left=0.08, right=0.97, top=0.88, bottom=0.09, wspace=0.28, hspace=0.42)
    fig0 = figure(800, 560, **adjust)
    bb = fig0.subplots(2, 2)[0, 0].get_window_extent()
    plt.close(fig0)
    dots = paths(rng, bb.width, bb.height, 18, 1, (4, 6), moving=False)
    bars = np.sort(rng.uniform(10, 95, 6))
    hist = rng.normal(50, 15, 600)
    months = np.arange(1, 13)
    line = 50 + np.cumsum(rng.normal(0, 1.5, (frames, 12)), axis=0) + 10 * np.sin(months / 2)
    names = list(rng.choice(NAMES, 6, replace=False))

    def draw(f):
        fig = figure(800, 560, **adjust)
        axs = fig.subplots(2, 2)
        ax = axs[0, 0]
        ax.set_xlim(0, 100); ax.set_ylim(10, 60)
        x, y = to_data(ax, np.array([d[0][0] for d in dots]), np.array([d[1][0] for d in dots]))
        r = np.array([d[2][0] for d in dots])
        ax.scatter(x, y, s=area_pt2(r), c=hexc(RED), linewidths=0)
        style(ax, "Income (k$)", "Age (years)")
        ax.set_title("Income and age", fontsize=11)
        marks = [(ax, x, y, r, [RED] * len(dots))]
        ax = axs[0, 1]
        ax.barh(names, bars, color=hexc(GREEN), height=0.7, linewidth=0)
        ax.set_xlim(0, 100)
        style(ax, "Coverage (%)", "", grid="x")
        ax.set_title("Coverage", fontsize=11)
        ax = axs[1, 0]
        ax.hist(hist, bins=16, range=(10, 90), color=hexc(PURPLE), rwidth=0.85, linewidth=0)
        style(ax, "Score", "Count", grid="y")
        ax.set_title("Scores", fontsize=11)
        ax = axs[1, 1]
        r = np.full(12, 5.0)
        ax.plot(months, line[f], color="#888888", linewidth=1.2, zorder=1)
        ax.scatter(months, line[f], s=area_pt2(r), c=hexc(ORANGE), linewidths=0, zorder=2)
        ax.set_xlim(0.3, 12.7); ax.set_ylim(line.min() - 8, line.max() + 8)
        style(ax, "Month", "Index")
        ax.set_title("Index this year (live)", fontsize=11)
        marks.append((ax, months, line[f], r, [ORANGE] * 12))
        fig.suptitle("Regional overview", fontsize=14)
        return fig, marks
    return draw, lambda fig: fig.axes[:3]


STREAMS = [("bubbles", bubbles), ("bubbles-facets", bubbles_facets), ("bar-race", bar_race),
           ("live-line", live_line), ("dashboard", dashboard)]


def static_boxes(fig, axes, pad=2):
    """Pixel boxes (r0, r1, c0, c1) around the given axes, with their labels and titles."""
    renderer = fig.canvas.get_renderer()
    h = fig.canvas.get_width_height()[1]
    boxes = []
    for ax in axes:
        b = ax.get_tightbbox(renderer)
        boxes.append((max(0, int(h - b.y1) - pad), int(np.ceil(h - b.y0)) + pad,
                      max(0, int(b.x0) - pad), int(np.ceil(b.x1)) + pad))
    return boxes


def make(out, name, draw, static, frames):
    """Renders and checks the frames of one stream into out/name; returns its streams.json entry."""
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    files, marks, boxes, first = [], [], None, None
    for f in range(frames):
        fig, spec = draw(f)
        rgb, m = render(fig, spec)
        if static and boxes is None:
            boxes, first = static_boxes(fig, static(fig)), rgb
        plt.close(fig)
        for k, (r0, r1, c0, c1) in enumerate(boxes or []):
            diff = int((rgb[r0:r1, c0:c1] != first[r0:r1, c0:c1]).any(-1).sum())
            if diff:
                raise SystemExit(f"make_streams: {name}: static panel {k} differs from frame 0 in "
                                 f"frame {f} ({diff} pixels); static panels must be byte-identical")
        h, w = rgb.shape[:2]
        for mk in m:
            px = rgb[min(h - 1, int(mk["y"])), min(w - 1, int(mk["x"]))].astype(int)
            if np.abs(px - mk["rgb"]).max() > 40:
                raise SystemExit(f"make_streams: {name} frame {f}: no mark colour {mk['rgb']} at "
                                 f"({mk['x']}, {mk['y']}), found {px.tolist()}")
        files.append(f"frame-{f:04d}.png")
        Image.fromarray(rgb).save(os.path.join(d, files[-1]))
        marks.append(m)
    return {"name": name, "dir": name, "width": w, "height": h, "frames": files,
            "targets": [[w // 2, h], [w, int(round(h * 0.6))]], "marks": marks}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--frames", type=int, default=24)
    a = ap.parse_args()
    if a.frames < 2:
        ap.error("--frames must be at least 2")
    os.makedirs(a.out, exist_ok=True)
    streams = []
    for i, (name, fn) in enumerate(STREAMS):
        draw, static = fn(np.random.default_rng([a.seed, i]), a.frames)
        streams.append(make(a.out, name, draw, static, a.frames))
        s = streams[-1]
        print(f"{name:15s} {len(s['frames'])} frames {s['width']}x{s['height']}, "
              f"{sum(map(len, s['marks']))} marks, targets {s['targets']}")
    with open(os.path.join(a.out, "streams.json"), "w") as f:
        json.dump({"seed": a.seed, "dpi": DPI, "streams": streams}, f, indent=1)
    print(f"{len(streams)} streams in {a.out}")


if __name__ == "__main__":
    main()
