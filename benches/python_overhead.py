"""The Python package's call against the Rust library's, on a 1237x744 still.

    python benches/python_overhead.py [--repeat 40]

Times `vizretarget.retarget(array, size)` from Python (an RGB and an RGBA array, and a PIL
image) and the library's `vizretarget::retarget` on the same picture, timed in Rust inside
the same extension (`_vizretarget._library_ms`), interleaved so both see the same machine.
The overhead is the median of the differences of pairs (the package's call and the
library's, one after the other, in alternating order, so that the load of a shared machine
and the first-call effect cancel out): converting the array in and out, the options, the
GIL. The issue's target: at most
1 ms.
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
    print(f"1237x744 -> {size[0]}x{size[1]}, {a.repeat} pairs per case (ms):")
    for name, x in cases.items():
        py: list[float] = []
        lib: list[float] = []
        for i in range(a.repeat):
            # Which goes first alternates: the first call after another is slower (threads
            # waking, memory given back and taken again), whichever it is.
            if i % 2:
                lib += native._library_ms(rgba, size, 1)
            t = time.perf_counter()
            vizretarget.retarget(x, size)
            py.append((time.perf_counter() - t) * 1e3)
            if not i % 2:
                lib += native._library_ms(rgba, size, 1)
        d = statistics.median(p - q for p, q in zip(py, lib))
        print(
            f"  {name:11s} package {statistics.median(py):6.2f} (min {min(py):6.2f}), "
            f"library {statistics.median(lib):6.2f} (min {min(lib):6.2f}), "
            f"overhead {d:+.2f} (median of the pairs' differences)"
        )


if __name__ == "__main__":
    main()
