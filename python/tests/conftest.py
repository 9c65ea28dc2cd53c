"""Shared fixtures: the repository, the command line built from it, sample pictures."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

REPO = Path(__file__).resolve().parents[2]
STREAMS = REPO / "streams"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The command line binary (`cargo build --release`, which `cargo test --release` also
    builds), or $VIZRETARGET_CLI: the tests compare the package's frames with its."""
    path = Path(os.environ.get("VIZRETARGET_CLI", REPO / "target" / "release" / "vizretarget"))
    if not path.is_file():
        pytest.fail(f"{path}: no command line to compare with; run cargo build --release first")
    return path


def run_cli(cli: Path, *args: object) -> None:
    r = subprocess.run([str(cli), *map(str, args), "-q"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def read_rgba(path: Path) -> np.ndarray:
    with Image.open(path) as im:
        return np.asarray(im.convert("RGBA"))


def chart(h: int = 180, w: int = 320, channels: int = 3) -> np.ndarray:
    """A scatterplot: coloured dots and an axis on white, with a transparent corner when
    RGBA."""
    yy, xx = np.mgrid[0:h, 0:w]
    img = np.full((h, w, channels), 255, np.uint8)
    for cx, cy, r, c in [(60, 50, 12, (228, 26, 28)), (160, 120, 9, (55, 126, 184)), (250, 70, 15, (77, 175, 74))]:
        img[(xx - cx) ** 2 + (yy - cy) ** 2 <= r * r, :3] = c
    img[h - 20, 10 : w - 10, :3] = 0
    if channels == 4:
        img[:20, :20, 3] = 0
    return img


@pytest.fixture
def dashboard_frames() -> list[Path]:
    return sorted((STREAMS / "dashboard").glob("frame-*.png"))
