"""retarget_file: what the command line reads and writes, with the command line's bytes."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import vizretarget
from conftest import STREAMS, read_rgba, run_cli


def test_a_still_as_the_command_line_writes_it(cli, tmp_path) -> None:
    src = STREAMS / "dashboard" / "frame-0003.png"
    run_cli(cli, src, "--width", "50%", "-o", tmp_path / "cli.png")
    done = vizretarget.retarget_file(src, tmp_path / "py.png", (("50%"), None))
    assert done["frames"] == 1
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
    # One picture into a folder keeps its name, as on the command line.
    vizretarget.retarget_file(src, f"{tmp_path}/into/", "50%x100%")
    assert np.array_equal(read_rgba(tmp_path / "into" / "frame-0003.png"), read_rgba(tmp_path / "cli.png"))


def test_an_animated_gif_to_a_gif_and_to_a_folder(cli, tmp_path) -> None:
    src = STREAMS / "graph.gif"
    done = vizretarget.retarget_file(src, tmp_path / "py.gif", "400x")
    run_cli(cli, src, "--size", "400x", "-o", tmp_path / "cli.gif")
    with Image.open(src) as im:
        n = im.n_frames
    assert done["frames"] == n > 1
    assert done["reused"] + done["updated"] + done["rebuilt"] == n
    assert (tmp_path / "py.gif").read_bytes() == (tmp_path / "cli.gif").read_bytes()
    vizretarget.retarget_file(src, f"{tmp_path}/frames/", "400x")
    assert len(list((tmp_path / "frames").glob("*.png"))) == n
    with pytest.raises(ValueError, match=f"an animated GIF of {n} frames does not fit in one picture"):
        vizretarget.retarget_file(src, tmp_path / "one.png", "400x")


def test_a_folder_of_frames_with_reuse(cli, tmp_path) -> None:
    src = STREAMS / "dashboard"
    done = vizretarget.retarget_file(src, f"{tmp_path}/py/", (320, None), regions="free")
    run_cli(cli, src, "--width", "320", "--regions", "free", "-o", f"{tmp_path}/cli/")
    names = sorted(p.name for p in src.glob("*.png"))
    assert done["frames"] == len(names) and done["updated"] > 0
    for n in names:
        assert (tmp_path / "py" / n).read_bytes() == (tmp_path / "cli" / n).read_bytes(), n
    with pytest.raises(ValueError, match="one picture cannot hold a folder"):
        vizretarget.retarget_file(src, tmp_path / "one.png", (320, None))
