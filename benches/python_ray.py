"""200 stills through Ray Data on 2 CPUs against two command-line processes in parallel.

    python benches/python_ray.py [--cli target/release/vizretarget] [--size 360x640] [--runs 3]

Makes 200 stills (1237x744 unless --still says) from the sample streams (a window of each
frame, mirrored or not, shuffled so that neighbours differ), then times (1) two
`vizretarget DIR -o OUT/` processes at once, 100 stills each, and (2)
`examples/python/ray_batch.py`'s `run` on a local Ray with 2 CPUs, one `retarget_files` call
per batch (of 50 unless --batch-size says; one Ray Data block a batch: a batch function that
does nothing took 0.07 to 0.10 s over 200 items in batches of 50, 0.21 to 0.23 s in batches
of 10, on the loaded VM, against 1.5 to 2.0 s with a block an item). Ray's start-up (`ray.init`) is apart; the first Ray run also starts its workers,
so it is reported as cold, the next ones as warm. The warm runs and the command line's take
turns (which goes first alternating), so that both see the same load of a shared machine;
each pair gives a ratio. The CPU time each side used is reported too (the command lines';
Ray's processes' and this one's, where Ray's psutil is there; a process is Ray's if its
command line names ray, so another user's Ray on the machine would count too): on a machine others share, a
side's wall time depends on how many threads it has runnable, its CPU time much less.
The issue's target: Ray within 1.3x of the two processes.

Then checks that Ray's files are the command line's for each picture alone (a few of them:
the folder stream of (1) carries a layout from one frame to the next, so its files are not).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import random
import resource
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


def children_cpu() -> float:
    """CPU seconds of this process' finished children (the command lines)."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def ray_cpu() -> float:
    """CPU seconds so far of this process and Ray's (workers, raylet, GCS): NaN without
    psutil (Ray ships one, importable once `ray` is)."""
    try:
        import psutil
    except ImportError:
        return float("nan")
    total = 0.0
    for p in psutil.process_iter():
        try:
            if p.pid == os.getpid() or "ray" in " ".join(p.cmdline()):
                t = p.cpu_times()
                total += t.user + t.system
        except (psutil.Error, OSError):
            pass
    return total


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--cli", default=str(REPO / "target" / "release" / "vizretarget"))
    p.add_argument("--size", default="360x640")
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--still", default="1237x744", help="size of the stills, WxH")
    p.add_argument("--batch-size", type=int, default=50, help="stills per Ray task")
    p.add_argument("--check", type=int, default=10, help="Ray's files compared with the command line's")
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

        def cli_run(r: int) -> float:
            c = children_cpu()
            t = time.perf_counter()
            procs = [
                subprocess.Popen(
                    [a.cli, str(h), "--size", a.size, "-o", f"{work}/cli-{r}-{h.name}/", "-q",
                     "--stats-json", f"{work}/cli-{r}-{h.name}.json"]
                )
                for h in halves
            ]
            assert all(pr.wait() == 0 for pr in procs)
            wall = time.perf_counter() - t
            cli_cpu.append(children_cpu() - c)
            return wall

        cli_cpu: list[float] = []
        ray_cpus: list[float] = []
        spec = importlib.util.spec_from_file_location("ray_batch", REPO / "examples" / "python" / "ray_batch.py")
        ray_batch = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(ray_batch)
        import ray

        def ray_run(r: int) -> float:
            c = ray_cpu()
            t = time.perf_counter()
            rows = ray_batch.run(str(work / "all"), str(work / f"ray-{r}"), [a.size], batch_size=a.batch_size)
            assert len(rows) == len(stills)
            wall = time.perf_counter() - t
            ray_cpus.append(ray_cpu() - c)
            return wall

        t = time.perf_counter()
        ray.init(num_cpus=2, log_to_driver=False)
        ray.data.DataContext.get_current().enable_progress_bars = False
        startup = time.perf_counter() - t
        cold_cli = cli_run(0)
        cold_ray = ray_run(0)
        cli_times, ray_times = [], []
        for r in range(1, a.runs + 1):
            if r % 2:
                cli_times.append(cli_run(r))
                ray_times.append(ray_run(r))
            else:
                ray_times.append(ray_run(r))
                cli_times.append(cli_run(r))
        ray.shutdown()
        import json
        import statistics

        decisions: dict[str, int] = {}
        for h in halves:
            for f in json.loads((work / f"cli-0-{h.name}.json").read_text())["frames"]:
                decisions[f["decision"]] = decisions.get(f["decision"], 0) + 1
        # Ray's files against the command line's for each picture alone.
        for s in stills[:: len(stills) // a.check]:
            alone = work / f"alone-{s.name}"
            subprocess.run([a.cli, str(s), "--size", a.size, "-o", str(alone), "-q"], check=True)
            assert (work / "ray-0" / ray_batch.size_dir(a.size) / s.name).read_bytes() == alone.read_bytes(), s.name
        ratios = [x / y for x, y in zip(ray_times, cli_times)]
        print(f"200 stills {a.still} -> {a.size}, 2 CPUs, batches of {a.batch_size} (s):")
        print(f"  two CLI processes, 100 each: first {cold_cli:.2f}, then {', '.join(f'{x:.2f}' for x in cli_times)} ({decisions})")
        print(f"  Ray start-up (ray.init, apart): {startup:.2f}")
        print(f"  Ray Data, cold (starts its workers): {cold_ray:.2f} ({cold_ray / cold_cli:.2f}x the CLI run before it)")
        print(f"  Ray Data, warm, in turn with the CLI: {', '.join(f'{x:.2f}' for x in ray_times)}")
        print(f"  ratio Ray / CLI, warm: pairs {', '.join(f'{x:.2f}' for x in ratios)}; median {statistics.median(ratios):.2f}; best of each {min(ray_times) / min(cli_times):.2f}")
        if ray_cpus[0] == ray_cpus[0]:  # psutil was there
            cpu = [x / y for x, y in zip(ray_cpus[1:], cli_cpu[1:])]
            print(f"  CPU time, warm (s): CLI {', '.join(f'{x:.2f}' for x in cli_cpu[1:])}; Ray (its processes and this one) {', '.join(f'{x:.2f}' for x in ray_cpus[1:])}; ratio median {statistics.median(cpu):.2f}")
        print(f"  Ray's files = the command line's for each picture alone: {len(stills[:: len(stills) // a.check])} checked")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
