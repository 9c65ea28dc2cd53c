"""retarget_file: what the command line reads and writes, with the command line's bytes."""

from __future__ import annotations

import subprocess

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


def test_a_batch_is_each_file_alone_byte_for_byte(cli, tmp_path) -> None:
    # Different pictures one after another: nothing of one (mesh, layout) may reach the
    # next, as it would in a stream; each file is the command line's for that picture alone.
    srcs = [STREAMS / "dashboard" / "frame-0003.png", STREAMS / "scatter-map" / "frame-0000.png",
            STREAMS / "graph" / "frame-0001.png", STREAMS / "dashboard" / "frame-0000.png"]
    pairs = [(s, tmp_path / f"batch-{i}.png") for i, s in enumerate(srcs)]
    done = vizretarget.retarget_files(pairs, "360x300")
    assert [d["frames"] for d in done] == [1] * len(srcs)
    for i, (s, d) in enumerate(pairs):
        run_cli(cli, s, "--size", "360x300", "-o", tmp_path / f"cli-{i}.png")
        assert d.read_bytes() == (tmp_path / f"cli-{i}.png").read_bytes(), s
        vizretarget.retarget_file(s, tmp_path / f"one-{i}.png", "360x300")
        assert d.read_bytes() == (tmp_path / f"one-{i}.png").read_bytes(), s
    # A stream among the pictures goes through the pipeline, as retarget_file runs it.
    mixed = vizretarget.retarget_files([(srcs[0], tmp_path / "m.png"), (STREAMS / "graph.gif", tmp_path / "m.gif")], "50%x100%")
    assert mixed[0]["frames"] == 1 and mixed[1]["frames"] > 1
    assert vizretarget.retarget_files([], "50%") == []


def test_a_batch_stops_at_the_first_error_after_writing_what_came_before(tmp_path) -> None:
    src = STREAMS / "dashboard" / "frame-0003.png"
    with pytest.raises(OSError, match="missing.png"):
        vizretarget.retarget_files(
            [(src, tmp_path / "a.png"), (tmp_path / "missing.png", tmp_path / "b.png"), (src, tmp_path / "c.png")], "50%"
        )
    assert (tmp_path / "a.png").is_file()
    assert not (tmp_path / "b.png").exists() and not (tmp_path / "c.png").exists()
    with pytest.raises(ValueError, match="standard input"):
        vizretarget.retarget_files([(src, tmp_path / "a.png"), ("-", tmp_path / "b.png")], "50%")
    with pytest.raises(OSError):  # the folder to write into is missing
        vizretarget.retarget_files([(src, tmp_path / "no" / "such" / "a.png")], "50%")


def test_a_batch_reads_ahead_but_makes_nothing_for_the_jobs_after_an_error(tmp_path) -> None:
    # Each picture is read while the one before it is retargeted. One into a folder keeps
    # its name; a folder is made only once the jobs before it went through.
    src = STREAMS / "dashboard" / "frame-0003.png"
    done = vizretarget.retarget_files([(src, tmp_path / "a.png"), (src, f"{tmp_path / 'into'}/")], "50%")
    assert [d["frames"] for d in done] == [1, 1]
    assert (tmp_path / "into" / "frame-0003.png").read_bytes() == (tmp_path / "a.png").read_bytes()
    # A stream that fails when it opens its output (on the calling thread, after the
    # picture behind it was read).
    with pytest.raises(OSError):
        vizretarget.retarget_files(
            [(STREAMS / "dashboard", tmp_path / "no" / "such.gif"), (src, f"{tmp_path / 'later'}/")], "50%"
        )
    assert not (tmp_path / "later").exists()


def test_a_gif_cut_short_is_what_the_command_line_makes_of_it(cli, tmp_path) -> None:
    # Its blocks cannot be walked to the end: into a folder it is a stream, which keeps the
    # frames before the fault and then fails, as the command line does; into one picture
    # it is read as one.
    data = (STREAMS / "graph.gif").read_bytes()
    cut = tmp_path / "cut.gif"
    cut.write_bytes(data[: len(data) * 2 // 3])
    r = subprocess.run([str(cli), str(cut), "--size", "50%x100%", "-o", f"{tmp_path / 'cli'}/", "-q"], capture_output=True, text=True)
    assert r.returncode == 1 and "corrupt GIF" in r.stderr
    with pytest.raises((OSError, ValueError), match="corrupt GIF"):
        vizretarget.retarget_file(cut, f"{tmp_path / 'py'}/", "50%x100%")
    names = sorted(p.name for p in (tmp_path / "cli").iterdir())
    assert len(names) > 1 and names == sorted(p.name for p in (tmp_path / "py").iterdir())
    for n in names:
        assert (tmp_path / "py" / n).read_bytes() == (tmp_path / "cli" / n).read_bytes(), n
    run_cli(cli, cut, "--size", "50%x100%", "-o", tmp_path / "cli.png")
    vizretarget.retarget_file(cut, tmp_path / "py.png", "50%x100%")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()
