"""The Python package's call against the Rust library's, on a 1237x744 still.

    python benches/python_overhead.py [--repeat 40]

Times `vizretarget.retarget(array, size)` from Python (an RGB and an RGBA array, and a PIL
image) and the library's `vizretarget::retarget` on the same picture, timed in Rust inside
the same extension (`_vizretarget._library_ms`), interleaved so both see the same machine.
The overhead is the difference of the medians: converting the array in and out, the
options, the GIL. The issue's target: at most 1 ms.
"""

from __future__ import annotations

import argparse
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


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--repeat", type=int, default=40)
    a = p.parse_args()
    rgb = still()
    rgba = np.ascontiguousarray(np.dstack([rgb, np.full(rgb.shape[:2], 255, np.uint8)]))
    pil = Image.fromarray(rgb)
    size = (618, 744)
    cases = {"numpy RGBA": rgba, "numpy RGB": rgb, "PIL RGB": pil}
    for x in cases.values():  # warm up
        vizretarget.retarget(x, size)
    native._library_ms(rgba, size, 2)
    times: dict[str, list[float]] = {k: [] for k in cases}
    times["library (Rust)"] = []
    for _ in range(a.repeat):
        for k, x in cases.items():
            t = time.perf_counter()
            vizretarget.retarget(x, size)
            times[k].append((time.perf_counter() - t) * 1e3)
        times["library (Rust)"] += native._library_ms(rgba, size, 1)
    lib = statistics.median(times["library (Rust)"])
    print(f"1237x744 -> {size[0]}x{size[1]}, median of {a.repeat} calls each (ms):")
    for k, v in times.items():
        med = statistics.median(v)
        extra = "" if k.startswith("library") else f"   overhead {med - lib:+.2f} ms"
        print(f"  {k:15s} {med:8.2f}  (min {min(v):.2f}){extra}")


if __name__ == "__main__":
    main()
