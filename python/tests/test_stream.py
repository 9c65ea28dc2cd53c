"""Streams: the command line's frames byte for byte, statistics, threads."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from PIL import Image

import vizretarget
from conftest import STREAMS, read_rgba, run_cli


def load(paths, mode: str = "RGB") -> list[np.ndarray]:
    out = []
    for p in paths:
        with Image.open(p) as im:
            out.append(np.asarray(im.convert(mode)))
    return out


def run_stream(frames, size, **options):
    results = []
    with vizretarget.Retargeter(size, **options) as r:
        for f in frames:
            r.send(f)
            results.extend(r)  # each frame is ready once sent
    results.extend(r)
    return results


@pytest.mark.parametrize(
    "stream, size, options, decisions",
    [
        ("dashboard", "320x360", {}, {"rebuild"}),
        ("dashboard", "320x360", {"regions": "free"}, {"rebuild", "update"}),
        ("graph", "50%x100%", {}, {"rebuild", "reuse"}),
    ],
    ids=["dashboard", "dashboard-free", "graph"],
)
def test_a_stream_is_the_command_lines_byte_for_byte(cli, tmp_path, stream, size, options, decisions) -> None:
    paths = sorted((STREAMS / stream).glob("frame-*.png"))
    flags = [a for k, v in options.items() for a in (f"--{k}", v)]
    run_cli(cli, STREAMS / stream, "--size", size, *flags, "-o", f"{tmp_path}/out/")
    expected = [read_rgba(tmp_path / "out" / p.name) for p in paths]
    got = run_stream(load(paths, "RGBA"), size, **options)
    assert len(got) == len(expected) == len(paths) > 10
    for i, ((img, stats), exp) in enumerate(zip(got, expected)):
        assert stats["frame_index"] == i
        assert np.array_equal(img, exp), f"frame {i} differs from the command line's"
    # The reuse policy ran as on the command line (what it decides depends on the stream).
    assert {s["decision"] for _, s in got} == decisions


def test_per_frame_statistics_are_a_dict(dashboard_frames) -> None:
    (img, stats), *_ = run_stream(load(dashboard_frames[:2]), (320, None))
    assert img.shape == (360, 320, 3)
    assert stats["vertices"] > 0 and stats["triangles"] > 0
    assert set(stats["ms"]) == {"vsm", "mesh", "solve", "render", "total"}
    assert stats["ms"]["total"] == pytest.approx(sum(stats["ms"][k] for k in ("vsm", "mesh", "solve", "render")))


def test_pil_frames_come_back_as_pil(dashboard_frames) -> None:
    frames = [Image.open(p) for p in dashboard_frames[:3]]
    got = run_stream(frames, "50%")
    assert [im.size for im, _ in got] == [(320, 180)] * 3
    arrays = run_stream(load(dashboard_frames[:3]), "50%")
    for (im, _), (a, _) in zip(got, arrays):
        assert im.mode == "RGB" and im.tobytes() == a.tobytes()


def test_two_threads_at_once(dashboard_frames) -> None:
    frames = load(dashboard_frames[:8])
    alone = [img for img, _ in run_stream(frames, (320, None))]
    results: dict[int, list] = {}
    errors: list[BaseException] = []

    def work(k: int) -> None:
        try:
            results[k] = [img for img, _ in run_stream(frames, (320, None))]
        except BaseException as e:  # noqa: BLE001 - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for k in range(2):
        assert all(np.array_equal(a, b) for a, b in zip(results[k], alone)), k

    # One retargeter fed by two threads: every frame comes out once, in the order taken.
    shared = vizretarget.Retargeter((320, None))
    tagged = [np.ascontiguousarray(f) for f in frames]

    def feed(part: list) -> None:
        try:
            for f in part:
                shared.send(f)
        except BaseException as e:  # noqa: BLE001
            errors.append(e)

    threads = [threading.Thread(target=feed, args=(tagged[k::2],)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    shared.flush()
    out = list(shared)
    assert not errors, errors
    assert [s["frame_index"] for _, s in out] == list(range(8))


def test_a_relative_size_is_the_first_frames_and_sending_after_flush_is_refused(dashboard_frames) -> None:
    f = load(dashboard_frames[:1])[0]
    r = vizretarget.Retargeter("50%")
    r.send(f)
    r.send(f[::2, ::2])  # another size: to the same target, as the command line does
    r.flush()
    with pytest.raises(RuntimeError, match="after flush"):
        r.send(f)
    assert [img.shape for img, _ in r] == [(180, 320, 3)] * 2
