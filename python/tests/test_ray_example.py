"""examples/python/ray_batch.py on a local Ray with 2 CPUs: every picture to every size,
each the same as the package's own call gives."""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

import vizretarget
from conftest import REPO, STREAMS, read_rgba

pytest.importorskip("ray")


def test_ray_batch_writes_every_size(tmp_path) -> None:
    src = tmp_path / "charts"
    src.mkdir()
    pictures = sorted((STREAMS / "scatter-map").glob("*.png"))[:4] + sorted((STREAMS / "graph").glob("*.png"))[:2]
    for i, p in enumerate(pictures):
        shutil.copy(p, src / f"chart-{i}.png")
    dst = tmp_path / "out"
    r = subprocess.run(
        [sys.executable, str(REPO / "examples" / "python" / "ray_batch.py"), str(src), str(dst),
         "--sizes", "360x640,50%", "--num-cpus", "2", "--batch-size", "2"],
        capture_output=True, text=True, timeout=600,
    )
    assert r.returncode == 0, r.stderr[-3000:]
    assert "12 outputs" in r.stdout, r.stdout
    for i in range(len(pictures)):
        for size, folder in [("360x640", "360x640"), ("50%", "50pc")]:
            out = read_rgba(dst / folder / f"chart-{i}.png")
            expected = read_rgba(src / f"chart-{i}.png")
            assert np.array_equal(out, vizretarget.retarget(expected, size)), (i, size)
