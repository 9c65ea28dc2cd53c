"""One picture: numpy and PIL in and out, RGB and RGBA, any strides, read-only arrays."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import vizretarget
from conftest import STREAMS, chart, read_rgba, run_cli


@pytest.mark.parametrize("channels", [3, 4])
def test_numpy_round_trip_keeps_kind_and_gives_the_target(channels: int) -> None:
    img = chart(channels=channels)
    out = vizretarget.retarget(img, (160, None))
    assert isinstance(out, np.ndarray) and out.dtype == np.uint8
    assert out.shape == (180, 160, channels)
    # The dots survive: each colour is still there, and white is still the ground.
    for colour in [(228, 26, 28), (55, 126, 184), (77, 175, 74)]:
        assert (out[..., :3] == colour).all(axis=-1).sum() > 50, colour
    assert (out[..., :3] == 255).all(axis=-1).mean() > 0.8
    if channels == 4:
        assert out[0, 0, 3] == 0 and out[-1, -1, 3] == 255


def test_a_still_is_the_command_lines_byte_for_byte(cli, tmp_path) -> None:
    src = STREAMS / "scatter-map" / "frame-0000.png"
    run_cli(cli, src, "--size", "360x405", "-o", tmp_path / "cli.png")
    with Image.open(src) as im:
        rgb = np.asarray(im.convert("RGB"))
        rgba = np.asarray(im.convert("RGBA"))
    expected = read_rgba(tmp_path / "cli.png")
    assert np.array_equal(vizretarget.retarget(rgba, "360x405"), expected)
    assert np.array_equal(vizretarget.retarget(rgb, (360, 405)), expected[..., :3])


@pytest.mark.parametrize("width", [157, 158, 159, 160])
def test_rgb_in_and_out_is_the_rgba_call_at_every_width(width: int) -> None:
    # RGB is widened to RGBA four pixels at a time and packed back the same way: pictures
    # whose pixel counts leave 0 to 3 pixels over (odd heights), in and out.
    rgb = np.ascontiguousarray(chart(h=181, w=width))
    rgba = np.ascontiguousarray(np.dstack([rgb, np.full(rgb.shape[:2], 255, np.uint8)]))
    for size in [(width - 41, None), (width - 1, 177)]:
        out = vizretarget.retarget(rgb, size)
        assert out.shape[2] == 3 and out.flags["C_CONTIGUOUS"]
        assert np.array_equal(out, vizretarget.retarget(rgba, size)[..., :3]), size


@pytest.mark.parametrize(
    "view",
    [
        lambda a: a[:, ::-1],  # negative strides
        lambda a: a[::2, ::2],  # every other row and column
        lambda a: np.asfortranarray(a),  # column-major
        lambda a: np.concatenate([a, a[..., :1]], axis=2)[..., :3],  # channels not packed
        lambda a: a.transpose(1, 0, 2),  # rows are columns
    ],
    ids=["reversed", "strided", "fortran", "channels", "transposed"],
)
def test_any_strides_read_as_the_same_pixels(view) -> None:
    a = view(chart())
    assert not a.flags["C_CONTIGUOUS"]
    dense = np.ascontiguousarray(a)
    size = (a.shape[1] // 2, None)
    assert np.array_equal(vizretarget.retarget(a, size), vizretarget.retarget(dense, size))


def test_read_only_arrays_are_read() -> None:
    a = chart(channels=4)
    expected = vizretarget.retarget(a, "50%")
    a.setflags(write=False)
    assert np.array_equal(vizretarget.retarget(a, "50%"), expected)
    b = np.frombuffer(a.tobytes(), np.uint8).reshape(a.shape)  # a read-only buffer
    assert not b.flags["WRITEABLE"]
    assert np.array_equal(vizretarget.retarget(b, "50%"), expected)


@pytest.mark.parametrize("mode", ["RGB", "RGBA"])
def test_pil_round_trip_keeps_mode_and_pixels(mode: str) -> None:
    arr = chart(channels=len(mode))
    out = vizretarget.retarget(Image.fromarray(arr), (200, 120))
    assert isinstance(out, Image.Image)
    assert (out.mode, out.size) == (mode, (200, 120))
    assert np.array_equal(np.asarray(out), vizretarget.retarget(arr, (200, 120)))


def test_pil_other_modes_come_back_as_rgb_or_rgba() -> None:
    grey = Image.fromarray(chart()).convert("L")
    assert vizretarget.retarget(grey, "50%").mode == "RGB"
    la = Image.fromarray(chart()).convert("LA")
    assert vizretarget.retarget(la, "50%").mode == "RGBA"


def test_sizes_as_the_command_line_writes_them() -> None:
    a = chart()  # 320 x 180
    shapes = {
        "400x": (180, 400),
        "x90": (90, 320),
        "50%x100%": (180, 160),
        "50%": (90, 160),
        (None, 90): (90, 320),
        ("25%", 100): (100, 80),
        None: (180, 320),
    }
    for size, shape in shapes.items():
        assert vizretarget.retarget(a, size).shape[:2] == shape, size


@pytest.mark.parametrize("method", ["linear", "crop", "seam", "grid", "axis"])
def test_other_methods(method: str) -> None:
    out = vizretarget.retarget(chart(), (200, 180), method=method)
    assert out.shape == (180, 200, 3)


def test_marks_as_a_dict_or_a_file_are_drawn(tmp_path) -> None:
    marks = {"points": [{"x": 160, "y": 90, "r": 8, "fill": "#ff00ff"}]}
    plain = vizretarget.retarget(chart(), (200, None))
    out = vizretarget.retarget(chart(), (200, None), marks=marks)
    magenta = (out == (255, 0, 255)).all(axis=-1)
    assert magenta.sum() > 100 and not (plain == (255, 0, 255)).all(axis=-1).any()
    path = tmp_path / "marks.json"
    import json

    path.write_text(json.dumps(marks))
    assert np.array_equal(vizretarget.retarget(chart(), (200, None), marks=path), out)


def test_compare_gives_a_sheet_and_every_methods_measures() -> None:
    sheet, measures = vizretarget.compare(Image.fromarray(chart()), (160, None))
    assert isinstance(sheet, Image.Image) and sheet.width > 2 * 320
    methods = [r["method"] for r in measures["rows"]]
    assert methods == ["mesh", "linear", "crop", "grid", "seam", "axis"]
    assert measures["target"] == {"width": 160, "height": 180}
