"""Every bad input is an exception naming what is wrong: ValueError for an argument,
OSError for a file."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import vizretarget
from conftest import chart


@pytest.mark.parametrize(
    "image, message",
    [
        (np.zeros((10, 10, 3), np.float32), "expected dtype uint8.*float32|expected dtype uint8.*<f4"),
        (np.zeros((10, 10, 3), np.uint16), "expected dtype uint8"),
        (np.zeros((10, 10), np.uint8), r"expected shape \(H, W, 3\) or \(H, W, 4\), got \[10, 10\]"),
        (np.zeros((10, 10, 2), np.uint8), r"got \[10, 10, 2\]"),
        (np.zeros((10, 10, 5), np.uint8), r"got \[10, 10, 5\]"),
        (np.zeros((2, 10, 10, 3), np.uint8), r"got \[2, 10, 10, 3\]"),
        (np.zeros((0, 10, 3), np.uint8), "image: invalid size 10x0"),
        ([[[0, 0, 0]]], "expected a numpy uint8 array.*got list"),
        ("chart.png", "expected a numpy uint8 array.*got str"),
    ],
    ids=["float32", "uint16", "2d", "2-channels", "5-channels", "4d", "empty", "list", "str"],
)
def test_bad_images(image, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        vizretarget.retarget(image, (5, 5))


@pytest.mark.parametrize(
    "size, message",
    [
        ((0, 10), "size: 0 px is out of range: each side must be 1 to 16384"),
        ("0x10", "size: 0 px is out of range"),
        ((20000, None), "size: 20000 px is out of range"),
        ("0%", "size: '0%' is out of range"),
        ("wide", "size: 'wide' is not a whole number of pixels or a percentage"),
        ("x", "size: 'x' gives neither side"),
        ((1.5, 2), "size: each side is a whole number of pixels.*got float"),
        ((1, 2, 3), r"size: expected \(width, height\)"),
        (("200000%", None), r"size: 200000% of the input's width \(320 px\) is 640000 px, out of range"),
    ],
)
def test_bad_sizes(size, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        vizretarget.retarget(chart(), size)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"colour": "red"}, "unknown option 'colour': allowed method, regions"),
        ({"no_reuse": True}, "unknown option 'no_reuse'"),  # for streams, not one picture
        ({"alpha": 2}, "invalid option: alpha 2 is out of range: allowed 4 to 200"),
        ({"alpha": "fine"}, "option alpha: .*got str"),
        ({"method": "blur"}, 'unknown method "blur": allowed mesh, linear, crop, grid, seam, axis'),
        ({"method": "seam", "enhance": (1, 1, 2)}, "option method: marks, paint_out_marks and enhance\\* work with method mesh"),
        ({"regions": "some"}, 'option regions: unknown regions "some": allowed affine, auto, free'),
        ({"mark_size": "huge"}, "unknown mark size"),
        ({"enhance": (1, 1, 9)}, "enhancement of saliency level 3 9 is out of range: allowed 0.25 to 4"),
        ({"enhance": (1, 1)}, "option enhance"),
        ({"enhance_region": (1, 2, 3)}, r"option enhance_region: expected \(x, y, width, height, factor\)"),
        ({"enhance_region": [(0, 0, -5, 5, 2)]}, "enhancement region 1 .* needs finite numbers"),
        ({"enhance_region": (0, 0, 5, 5, 8)}, "the factor of enhancement region 1 8 is out of range"),
        ({"enhance_mask": np.zeros((4, 4, 3), np.uint8), "enhance_mask_factor": 9}, "the mask's factor 9 is out of range"),
    ],
)
def test_bad_options(options, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        vizretarget.retarget(chart(), (100, None), **options)


@pytest.mark.parametrize(
    "marks, message",
    [
        ({"points": [{"x": 1}]}, "marks: missing field `y`"),
        ({"points": [{"x": 10, "y": 10, "r": -3}]}, r"marks: points\[0\]: radius -3 is out of range"),
        ({"points": [{"x": 10, "y": 10, "r": 3, "fill": "no"}]}, '"no" is not a colour'),
        ({"edges": [{"from": 0, "to": 5}]}, r'edges\[0\]: "from" is point 0, but there are 0 points'),
        ({"points": [{"x": float("nan"), "y": 1, "r": 2}]}, "JSON has no NaN"),
        ([1, 2], "marks: "),
    ],
    ids=["no-y", "negative-radius", "bad-colour", "edge-to-nothing", "nan", "a-list"],
)
def test_bad_marks(marks, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        vizretarget.retarget(chart(), (100, None), marks=marks)


def test_bad_stream_options_and_frames() -> None:
    with pytest.raises(ValueError, match="reuse tile 2 px is out of range: allowed 4 to 1024"):
        vizretarget.Retargeter((100, None), reuse_tile=2)
    with pytest.raises(ValueError, match="reuse rebuild fraction 2 is out of range"):
        vizretarget.Retargeter((100, None), rebuild_fraction=2)
    with pytest.raises(ValueError, match="option method: streams are retargeted with mesh"):
        vizretarget.Retargeter((100, None), method="seam")
    r = vizretarget.Retargeter((100, None))
    with pytest.raises(ValueError, match="frame: expected dtype uint8"):
        r.send(np.zeros((10, 10, 3)))


def test_files_that_cannot_be_read_or_written_are_os_errors(tmp_path) -> None:
    with pytest.raises(FileNotFoundError, match="nomarks.json"):
        vizretarget.retarget(chart(), (100, None), marks=tmp_path / "nomarks.json")
    with pytest.raises(FileNotFoundError, match="missing.png"):
        vizretarget.retarget_file(tmp_path / "missing.png", tmp_path / "out.png", "50%")
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"\x89PNG\r\n\x1a\n not really")
    with pytest.raises(OSError, match="bad.png"):
        vizretarget.retarget_file(bad, tmp_path / "out.png", "50%")
    good = tmp_path / "good.png"
    Image.fromarray(chart()).save(good)
    with pytest.raises(OSError, match="no-such-folder"):
        vizretarget.retarget_file(good, tmp_path / "no-such-folder" / "out.png", "50%")
    with pytest.raises(ValueError, match="out.bmp"):
        vizretarget.retarget_file(good, tmp_path / "out.bmp", "50%")
    with pytest.raises(ValueError, match="unknown option 'colour'"):
        vizretarget.retarget_file(good, tmp_path / "out.png", "50%", colour=1)
