"""Type stubs of vizretarget (see the module's docstring for what each option means)."""

import os
from typing import Any, Dict, Iterable, Iterator, List, Mapping, Optional, Sequence, Tuple, TypeVar, Union

import numpy as np
import numpy.typing as npt
from PIL import Image as _PIL

__version__: str
__all__: List[str]

# An H x W x 3 or H x W x 4 uint8 array, or a PIL image; results are of the kind given.
_Picture = TypeVar("_Picture", npt.NDArray[np.uint8], _PIL.Image)
_Side = Union[int, str, None]
Size = Union[Tuple[_Side, _Side], Sequence[_Side], str, None]
Marks = Union[Mapping[str, Any], str, "os.PathLike[str]"]
Stats = Dict[str, Any]

def retarget(
    image: _Picture,
    size: Size,
    *,
    method: str = ...,
    regions: str = ...,
    fill: bool = ...,
    layout: bool = ...,
    alpha: float = ...,
    enhance: Tuple[float, float, float] = ...,
    enhance_region: Union[Tuple[float, float, float, float, float], Sequence[Tuple[float, float, float, float, float]]] = ...,
    enhance_mask: Union[str, "os.PathLike[str]", npt.NDArray[np.uint8]] = ...,
    enhance_mask_factor: float = ...,
    marks: Marks = ...,
    paint_out_marks: bool = ...,
    mark_size: str = ...,
) -> _Picture: ...

class Retargeter:
    def __init__(
        self,
        size: Size,
        *,
        regions: str = ...,
        fill: bool = ...,
        layout: bool = ...,
        alpha: float = ...,
        enhance: Tuple[float, float, float] = ...,
        enhance_region: Union[Tuple[float, float, float, float, float], Sequence[Tuple[float, float, float, float, float]]] = ...,
        enhance_mask: Union[str, "os.PathLike[str]", npt.NDArray[np.uint8]] = ...,
        enhance_mask_factor: float = ...,
        marks: Marks = ...,
        paint_out_marks: bool = ...,
        mark_size: str = ...,
        no_reuse: bool = ...,
        reuse_tile: int = ...,
        tile_threshold: float = ...,
        rebuild_fraction: float = ...,
    ) -> None: ...
    def send(self, frame: Union[npt.NDArray[np.uint8], _PIL.Image], marks: Optional[Mapping[str, Any]] = ...) -> None: ...
    def flush(self) -> None: ...
    def __iter__(self) -> Iterator[Tuple[Any, Stats]]: ...
    def __next__(self) -> Tuple[Any, Stats]: ...
    def __len__(self) -> int: ...
    def __enter__(self) -> "Retargeter": ...
    def __exit__(self, *exc: Any) -> None: ...

def retarget_file(
    src: Union[str, "os.PathLike[str]"],
    dst: Union[str, "os.PathLike[str]"],
    size: Size,
    **options: Any,
) -> Dict[str, Any]: ...

def retarget_files(
    pairs: Iterable[Tuple[Union[str, "os.PathLike[str]"], Union[str, "os.PathLike[str]"]]],
    size: Size,
    **options: Any,
) -> List[Dict[str, Any]]: ...

def compare(
    image: Union[npt.NDArray[np.uint8], _PIL.Image],
    size: Size,
    *,
    alpha: float = ...,
    mesh: bool = ...,
    metrics: bool = ...,
) -> Tuple[_PIL.Image, Dict[str, Any]]: ...
