"""Content-aware resizing of visualizations: numpy arrays and PIL images in and out.

vizretarget resizes a chart, a map, a node-link graph or a dashboard to another size or
aspect ratio so that its marks keep their shape: round dots stay round, text stays
readable, lines stay straight, while empty or uniform areas absorb the change. This package
is the Rust library's Python binding: the same method and the same options as the command
line ``vizretarget``, with the GIL released while it works.

    >>> import numpy as np, vizretarget
    >>> chart = np.full((300, 600, 3), 255, np.uint8)      # H x W x 3 (or 4), uint8
    >>> vizretarget.retarget(chart, (300, None)).shape     # half the width, same height
    (300, 300, 3)

- :func:`retarget` one picture (a numpy array or a ``PIL.Image``; returns the same kind);
- :class:`Retargeter` a stream of frames, reusing the mesh from frame to frame;
- :func:`retarget_file` whatever the command line reads and writes (a picture, an animated
  GIF, a folder of frames); :func:`retarget_files` many of them, each as alone, the writing
  of one overlapping the work on the next;
- :func:`compare` every method side by side, with their measures.

Sizes: ``(width, height)`` in pixels, ``None`` for a side to keep, a side as a string
(``"50%"``); or one string as the command line's ``--size`` takes it (``"400x600"``,
``"50%x100%"``, ``"400x"``, ``"x300"``), or one side alone for both (``"50%"``).

Options are the command line's, as keywords: ``alpha`` (mesh spacing, 4 to 200),
``regions`` (``"affine"``, ``"auto"``, ``"free"``), ``fill``, ``method`` (``"mesh"``,
``"linear"``, ``"crop"``, ``"grid"``, ``"seam"``, ``"axis"``), ``enhance`` (three factors),
``enhance_region`` (``(x, y, w, h, factor)`` or a list of them), ``enhance_mask`` (a path
or an array) and ``enhance_mask_factor``, ``marks`` (a dict in the JSON format of
``--marks``, or its path), ``paint_out_marks``, ``mark_size`` (``"mesh"``, ``"keep"``);
for streams ``no_reuse``, ``reuse_tile``, ``tile_threshold``, ``rebuild_fraction``; for
files ``max_pixels``, ``max_frames``, ``memory_limit``, ``fps``. The library checks them:
a bad one raises ``ValueError`` with the command line's message; a file that cannot be read
or written raises ``OSError``.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, Iterator, List, Optional, Tuple

import numpy as np

from . import _vizretarget as _native

__version__: str = _native.__version__
__all__ = ["retarget", "Retargeter", "retarget_file", "retarget_files", "compare", "__version__"]


def _is_pil(image: Any) -> bool:
    return type(image).__module__.startswith("PIL.") and hasattr(image, "mode")


def _to_array(image: Any) -> Tuple[Any, Optional[str]]:
    """The picture as the library reads it, and the PIL mode to give back (None: an
    array). PIL images other than RGB and RGBA come back as RGBA if they have transparency,
    else RGB. An RGB or RGBA image goes to the extension as it is: it reads Pillow's pixels
    in place (the Arrow C data interface, Pillow 11.2.1 on) with one copy, as from an RGBA
    array; with an older Pillow, through numpy (Pillow's ``tobytes``, a copy more)."""
    if not _is_pil(image):
        return image, None
    mode = image.mode
    if mode not in ("RGB", "RGBA"):
        transparent = "A" in mode or "transparency" in image.info
        mode = "RGBA" if transparent else "RGB"
        image = image.convert(mode)
    return (image if _fromarrow() else np.asarray(image)), mode


def _from_array(out: Any, mode: Optional[str]) -> Any:
    if mode is None:
        return out
    from PIL import Image

    if not isinstance(out, np.ndarray):
        # Over the extension's pixels, without a copy (Pillow copies them if the image is
        # written).
        return Image.fromarrow(out, mode, out.size)
    h, w = out.shape[:2]
    return Image.frombuffer(mode, (w, h), out, "raw", mode, 0, 1)


# Whether Pillow has `Image.fromarrow` (11.2.1 and later): PIL images then go in and out
# through the Arrow C data interface. Looked up at the first PIL image (Pillow is imported
# by then), so that importing the package does not import Pillow.
_FROMARROW: Optional[bool] = None


def _fromarrow() -> bool:
    global _FROMARROW
    if _FROMARROW is None:
        from PIL import Image

        _FROMARROW = hasattr(Image, "fromarrow")
    return _FROMARROW


def retarget(image: Any, size: Any, **options: Any) -> Any:
    """Resize a visualization to ``size`` so that its marks keep their shape.

    ``image`` is a numpy ``uint8`` array ``H x W x 3`` or ``H x W x 4`` (any strides;
    read-only is fine) or a ``PIL.Image``; the result is the same kind with as many
    channels. ``size`` is ``(width, height)`` with ``None`` for a side to keep, or a string
    as the command line's ``--size`` takes it (``"400x"``, ``"50%x100%"``), or ``"50%"``
    for both sides. ``options`` are the command line's (see the module's help), e.g.
    ``method="seam"``, ``regions="free"``, ``marks={"points": [...]}``.

    Raises ``ValueError`` for a bad argument, naming it.

    >>> import numpy as np, vizretarget
    >>> out = vizretarget.retarget(np.zeros((100, 200, 4), np.uint8), (100, 100))
    >>> out.shape
    (100, 100, 4)
    """
    array, mode = _to_array(image)
    out, _stats = _native.retarget(array, size, options)
    return _from_array(out, mode)


class Retargeter:
    """Retargets a stream of frames to one size, reusing the mesh from frame to frame.

    The frames are the command line's for the same input, byte for byte. Send frames with
    :meth:`send`; iterate to take the results ready so far, each as ``(image, stats)`` with
    ``image`` of the kind sent and ``stats`` a dict (``frame_index``, ``decision``:
    ``"rebuild"``, ``"update"`` or ``"reuse"``, ``vertices``, ``triangles``, ``dof``,
    ``ms`` per stage, ...). A relative ``size`` (``"50%"``, ``(360, None)``) is taken from
    the first frame; later frames must be of its size. Leaving a ``with`` block flushes.

    Several threads may send to one retargeter (each frame is taken whole, in the order
    the threads get to it); retargeters in different threads work at the same time.

    >>> import numpy as np, vizretarget
    >>> frames = [np.full((120, 160, 3), 255, np.uint8) for _ in range(3)]
    >>> with vizretarget.Retargeter((80, None)) as r:
    ...     for f in frames:
    ...         r.send(f)
    >>> [stats["decision"] for _, stats in r]
    ['rebuild', 'reuse', 'reuse']
    """

    def __init__(self, size: Any, **options: Any) -> None:
        self._native = _native.Retargeter(size, options)

    def send(self, frame: Any, marks: Optional[Dict[str, Any]] = None) -> None:
        """Retarget ``frame`` (an array or a ``PIL.Image``); its result is then ready to
        iterate. ``marks``: this frame's vector marks (a dict as ``--marks`` reads)."""
        array, mode = _to_array(frame)
        self._native.send(array, mode, marks)

    def flush(self) -> None:
        """End the stream: results not taken yet stay available; sending is refused."""
        self._native.flush()

    def __iter__(self) -> Iterator[Tuple[Any, Dict[str, Any]]]:
        return self

    def __next__(self) -> Tuple[Any, Dict[str, Any]]:
        got = self._native.receive()
        if got is None:
            raise StopIteration
        array, stats, mode = got
        return _from_array(array, mode), stats

    def __len__(self) -> int:
        """Results ready and not taken yet."""
        return self._native.pending()

    def __enter__(self) -> "Retargeter":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.flush()


def retarget_file(
    src: "os.PathLike[str] | str", dst: "os.PathLike[str] | str", size: Any, **options: Any
) -> Dict[str, Any]:
    """Retarget a file or folder as the command line would: ``vizretarget SRC -o DST``.

    ``src`` is a PNG, JPEG, WebP or GIF (animated or not) or a folder of frames; ``dst``
    is a ``.png``, ``.jpg`` or ``.webp`` (one picture), a ``.gif``, or a folder (existing, or
    ending in ``/``). A stream goes through the threaded pipeline with mesh reuse. Returns
    ``{"frames", "reused", "updated", "rebuilt", "seconds"}``.

    Raises ``OSError`` when a file cannot be read or written, ``ValueError`` for a bad
    argument (an animated GIF into one ``.png``, an option out of range).
    """
    return _native.retarget_file(os.fspath(src), os.fspath(dst), size, options)


def retarget_files(
    pairs: "Iterable[Tuple[os.PathLike[str] | str, os.PathLike[str] | str]]",
    size: Any,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Retarget each ``(src, dst)`` of ``pairs`` as :func:`retarget_file` would, in order.

    The files are the same as one call each gives (those of the command line for each
    ``src`` alone: no mesh or layout is carried from one picture to the next), but a
    picture is encoded and synced to disk on a second thread while the next one is read and
    retargeted, as the command line's stream writes its frames: the unit of work for a
    batch (Ray Data's ``map_batches``). ``size`` and ``options`` are for every pair.
    Returns one dict per pair, as :func:`retarget_file`.

    Stops at the first error (``OSError``, ``ValueError`` as :func:`retarget_file`), once
    the pictures before it are written.
    """
    return _native.retarget_files([(os.fspath(s), os.fspath(d)) for s, d in pairs], size, options)


def compare(image: Any, size: Any, **options: Any) -> Tuple[Any, Dict[str, Any]]:
    """Every method on ``image`` side by side: ``(sheet, measures)``.

    ``sheet`` is a ``PIL.Image``: the original and each method's output (mesh, linear,
    crop, grid, seam, axis), labelled. ``measures`` is a dict as ``vizretarget compare
    --json`` prints: ``{"source", "target", "rows": [{"method", "saliency_mean",
    "distortion", "salient_area_kept", "ms", ...}]}``. Options: ``alpha``, ``mesh`` (draw
    the mesh), ``metrics`` (measures under the labels).
    """
    from PIL import Image

    array, _mode = _to_array(image)
    sheet, measures = _native.compare(array, size, options)
    return Image.fromarray(sheet), json.loads(measures)
