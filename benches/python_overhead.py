"""The Python package's call against the Rust library's, on a 1237x744 still.

    python benches/python_overhead.py [--pairs 200]

Times `vizretarget.retarget(x, size)` from Python (an RGBA and an RGB array, an RGBA and
an RGB PIL image) and the library's `vizretarget::retarget` on the same picture, timed in Rust inside
the same extension (`_vizretarget._library_ms`: same allocator, same threads), in pairs one
after the other, which goes first alternating (the first call after another is slower,
whichever it is). The overhead is what the package adds: converting the picture in and
out, reading the options, the GIL, the Python wrapper. The issue's target: at most 1 ms.

On a shared machine a call's time varies by several milliseconds with the load, far more
than the overhead, so two estimates are given:

- `wall`: the median of the pairs' differences of wall time, with a 95 % confidence
  interval (the order statistics of the differences that bracket their median);
- `outside`: the same, of each call's time outside the library's four stages (the call's
  wall time less the stage total the library reports for that very frame,
  `FrameStats::times`): the load slows the stages, and this takes them out of both sides.
  What remains is the same on both sides (setting up the retargeter, one copy of the
  picture: the library's `retarget` clones it, the package copies the array, or a PIL
  image's pixels, which Pillow exports in place as Arrow) but for the package's own work.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from pathlib import Path

import numpy as np
from PIL import Image

import vizretarget
from vizretarget import _vizretarget as native

REPO = Path(__file__).resolve().parents[1]


def still() -> np.ndarray:
    """A 1237x744 dashboard: the sample frame scaled up (content and structure kept)."""
    with Image.open(REPO / "streams" / "dashboard" / "frame-0000.png") as im:
        return np.asarray(im.convert("RGB").resize((1237, 744), Image.Resampling.BICUBIC))


class Recorder:
    """Stands in for the extension in the package's module to keep the statistics of the
    last call, which `vizretarget.retarget` drops: one more Python call, counted in the
    package's time."""

    def __init__(self) -> None:
        self.stages_ms = 0.0

    def retarget(self, image, size, options):
        out, stats = native.retarget(image, size, options)
        self.stages_ms = stats["ms"]["total"]
        return out, stats

    def __getattr__(self, name):
        return getattr(native, name)


def median_ci(d: list[float]) -> tuple[float, float, float]:
    """The median of `d` and a 95 % confidence interval for it (binomial order statistics)."""
    s = sorted(d)
    n = len(s)
    k = max(0, math.floor(n / 2 - 0.98 * math.sqrt(n)))
    return statistics.median(s), s[k], s[n - 1 - k]


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--pairs", type=int, default=200)
    a = p.parse_args()
    rgb = still()
    rgba = np.ascontiguousarray(np.dstack([rgb, np.full(rgb.shape[:2], 255, np.uint8)]))
    size = (618, 744)
    cases = {"numpy RGBA": rgba, "numpy RGB": rgb, "PIL RGBA": Image.fromarray(rgba), "PIL RGB": Image.fromarray(rgb)}
    recorder = Recorder()
    vizretarget._native = recorder
    for x in cases.values():  # warm up
        vizretarget.retarget(x, size)
    native._library_ms(rgba, size, 2)
    print(f"1237x744 -> {size[0]}x{size[1]}, {a.pairs} pairs per case (ms):")
    for name, x in cases.items():
        py: list[tuple[float, float]] = []
        lib: list[tuple[float, float]] = []
        for i in range(a.pairs):
            if i % 2:
                lib += native._library_ms(rgba, size, 1)
            t = time.perf_counter()
            out = vizretarget.retarget(x, size)
            py.append(((time.perf_counter() - t) * 1e3, recorder.stages_ms))
            del out
            if not i % 2:
                lib += native._library_ms(rgba, size, 1)
        wall = median_ci([p[0] - q[0] for p, q in zip(py, lib)])
        outside = median_ci([(p[0] - p[1]) - (q[0] - q[1]) for p, q in zip(py, lib)])
        print(
            f"  {name:10s} package {statistics.median(v for v, _ in py):5.2f}, "
            f"library {statistics.median(v for v, _ in lib):5.2f}; overhead: "
            f"wall {wall[0]:+.2f} [{wall[1]:+.2f}, {wall[2]:+.2f}], "
            f"outside {outside[0]:+.2f} [{outside[1]:+.2f}, {outside[2]:+.2f}]"
        )
    vizretarget._native = native


if __name__ == "__main__":
    main()
