"""200 stills through Ray Data on 2 CPUs against two command-line processes in parallel.

    python benches/python_ray.py [--cli target/release/vizretarget] [--size 360x640]

Makes 200 stills (1237x744 unless --still says) from the sample streams (each frame,
mirrored or not, shuffled so that neighbours differ), then times (1) two `vizretarget DIR -o OUT/` processes at once,
100 stills each, and (2) `examples/python/ray_batch.py`'s `run` on a local Ray with 2 CPUs,
one `retarget_file` call per still. Ray's start-up (`ray.init`) is apart; the first Ray run
also starts its workers, so it is reported as cold, the next ones as warm. The issue's
target: Ray within 1.3x of the two processes.
"""

from __future__ import annotations

import argparse
import importlib.util
import random
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

from PIL import Image, ImageOps

REPO = Path(__file__).resolve().parents[1]


def make_stills(folder: Path, size: tuple[int, int], n: int = 200) -> list[Path]:
    frames = sorted((REPO / "streams").glob("*/frame-*.png"))
    rng = random.Random(38)
    pictures = []
    for i in range(n):
        with Image.open(frames[i % len(frames)]) as im:
            # A window of 80 to 100 % of the frame somewhere in it: no two stills alike, so
            # that the command line's stream of a folder has nothing to reuse, as in a batch
            # of different charts.
            w, h = im.size
            f = rng.uniform(0.8, 1.0)
            x, y = rng.uniform(0, w * (1 - f)), rng.uniform(0, h * (1 - f))
            im = im.convert("RGB").resize(size, Image.Resampling.BICUBIC, box=(x, y, x + w * f, y + h * f))
            if (i // len(frames)) % 2:
                im = ImageOps.mirror(im)
            pictures.append(im)
    rng.shuffle(pictures)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for i, im in enumerate(pictures):
        paths.append(folder / f"still-{i:03}.png")
        im.save(paths[-1])
    return paths


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--cli", default=str(REPO / "target" / "release" / "vizretarget"))
    p.add_argument("--size", default="360x640")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--still", default="1237x744", help="size of the stills, WxH")
    a = p.parse_args()
    work = Path(tempfile.mkdtemp(prefix="vizretarget-ray-"))
    try:
        w, h = (int(v) for v in a.still.split("x"))
        stills = make_stills(work / "all", (w, h))
        halves = [work / "a", work / "b"]
        for k, h in enumerate(halves):
            h.mkdir()
            for s in stills[k::2]:
                shutil.copy(s, h / s.name)
        cli_times = []
        for r in range(a.runs):
            t = time.perf_counter()
            procs = [
                subprocess.Popen(
                    [a.cli, str(h), "--size", a.size, "-o", f"{work}/cli-{r}-{h.name}/", "-q",
                     "--stats-json", f"{work}/cli-{r}-{h.name}.json"]
                )
                for h in halves
            ]
            assert all(pr.wait() == 0 for pr in procs)
            cli_times.append(time.perf_counter() - t)

        spec = importlib.util.spec_from_file_location("ray_batch", REPO / "examples" / "python" / "ray_batch.py")
        ray_batch = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(ray_batch)
        import ray

        t = time.perf_counter()
        ray.init(num_cpus=2, log_to_driver=False)
        ray.data.DataContext.get_current().enable_progress_bars = False
        startup = time.perf_counter() - t
        ray_times = []
        for r in range(a.runs + 1):
            t = time.perf_counter()
            rows = ray_batch.run(str(work / "all"), str(work / f"ray-{r}"), [a.size], batch_size=10)
            ray_times.append(time.perf_counter() - t)
            assert len(rows) == len(stills)
        ray.shutdown()
        best_cli = min(cli_times)
        import json

        decisions: dict[str, int] = {}
        for h in halves:
            for f in json.loads((work / f"cli-0-{h.name}.json").read_text())["frames"]:
                decisions[f["decision"]] = decisions.get(f["decision"], 0) + 1
        print(f"200 stills {a.still} -> {a.size}, 2 CPUs (s):")
        print(f"  two CLI processes, 100 each: {', '.join(f'{x:.2f}' for x in cli_times)} ({decisions})")
        print(f"  Ray start-up (ray.init, apart): {startup:.2f}")
        print(f"  Ray Data, cold (starts its workers): {ray_times[0]:.2f}")
        print(f"  Ray Data, warm: {', '.join(f'{x:.2f}' for x in ray_times[1:])}")
        print(f"  ratio Ray / CLI (best of each): cold {ray_times[0] / best_cli:.2f}, warm {min(ray_times[1:]) / best_cli:.2f}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
