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


@pytest.mark.parametrize("mode", ["RGB", "RGBA"])
@pytest.mark.parametrize("width", [157, 160])
def test_pil_is_the_numpy_path_byte_for_byte(mode: str, width: int) -> None:
    # PIL images are read in place (Arrow) and given back over the library's pixels: the
    # same bytes as an array in and out, at widths that leave 0 and 1 pixels over a quad.
    arr = chart(h=181, w=width, channels=len(mode))
    size = (width - 41, 177)
    out = vizretarget.retarget(Image.fromarray(arr), size)
    assert (out.mode, out.size) == (mode, size)
    assert out.tobytes() == vizretarget.retarget(arr, size).tobytes()


def test_pil_from_a_file_and_a_result_fed_back_in() -> None:
    # A PNG opened lazily (Pillow loads it when its pixels are asked for), and the result,
    # an image over the extension's memory, retargeted again: as the arrays.
    path = STREAMS / "scatter-map" / "frame-0000.png"
    with Image.open(path) as im:
        rgb = np.asarray(im.convert("RGB"))
    with Image.open(path) as im:
        assert im.mode == "RGB"
        once = vizretarget.retarget(im, "50%x100%")
    twice = vizretarget.retarget(once, (None, 300))
    expected_once = vizretarget.retarget(rgb, "50%x100%")
    assert once.tobytes() == expected_once.tobytes()
    assert twice.tobytes() == vizretarget.retarget(expected_once, (None, 300)).tobytes()


@pytest.mark.parametrize("mode", ["RGB", "RGBA"])
def test_pil_results_outlive_the_call_and_copy_when_written(mode: str) -> None:
    import gc

    arr = chart(channels=len(mode))
    expected = vizretarget.retarget(arr, "50%")
    out = vizretarget.retarget(Image.fromarray(arr), "50%")
    gc.collect()
    assert np.array_equal(np.asarray(out), expected)
    copy = out.copy()
    out.putpixel((0, 0), (1, 2, 3, 4)[: len(mode)])
    out.paste((9, 9, 9, 9)[: len(mode)], (5, 5, 20, 20))
    assert out.getpixel((0, 0)) == (1, 2, 3, 4)[: len(mode)]
    assert np.array_equal(np.asarray(copy), expected)
    assert out.convert("RGBA").mode == "RGBA"


def test_pil_images_not_in_one_piece_are_read_through_numpy() -> None:
    # Pillow exports an image only if its rows follow each other in one block: an image
    # over a buffer read bottom-up, and one over rows with a gap after each, are refused,
    # and read another way, to the same pixels.
    arr = chart(channels=4)
    h, w = arr.shape[:2]
    expected = vizretarget.retarget(arr, "50%")
    flipped = Image.frombuffer("RGBA", (w, h), np.ascontiguousarray(arr[::-1]), "raw", "RGBA", 0, -1)
    padded = np.zeros((h, w + 3, 4), np.uint8)
    padded[:, :w] = arr
    gaps = Image.frombuffer("RGBA", (w, h), padded, "raw", "RGBA", (w + 3) * 4, 1)
    for im in (flipped, gaps):
        with pytest.raises(ValueError):
            im.__arrow_c_array__()
        assert np.array_equal(np.asarray(vizretarget.retarget(im, "50%")), expected)


@pytest.mark.parametrize("mode", ["RGB", "RGBA"])
def test_pil_without_arrow_goes_through_numpy(monkeypatch, mode: str) -> None:
    # An older Pillow (no `Image.fromarrow`, before 11.2.1): the arrays' path, same result.
    arr = chart(channels=len(mode))
    fast = vizretarget.retarget(Image.fromarray(arr), (200, 120))
    monkeypatch.setattr(vizretarget, "_FROMARROW", False)
    slow = vizretarget.retarget(Image.fromarray(arr), (200, 120))
    assert (slow.mode, slow.size) == (fast.mode, fast.size)
    assert slow.tobytes() == fast.tobytes()


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
