"""examples/python/ray_batch.py on a local Ray with 2 CPUs: every picture to every size,
each the very file the command line writes for that picture alone."""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

import vizretarget
from conftest import REPO, STREAMS, read_rgba, run_cli

pytest.importorskip("ray")


def test_ray_batch_writes_every_size(cli, tmp_path) -> None:
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
            out = dst / folder / f"chart-{i}.png"
            alone = tmp_path / f"cli-{i}-{folder}.png"
            run_cli(cli, src / f"chart-{i}.png", "--size", size, "-o", alone)
            assert out.read_bytes() == alone.read_bytes(), (i, size)
            with_array = vizretarget.retarget(read_rgba(src / f"chart-{i}.png"), size)
            assert np.array_equal(read_rgba(out), with_array), (i, size)
