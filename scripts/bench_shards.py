"""Shards (issue 24): how evenly a split divides the search, and what Dask workers gain. Run it
in the environment scripts/test makes (wedged and dask[distributed] installed), after
`cargo build --release`:

    target/venv/bin/python scripts/bench_shards.py --n 30 --shards 16 --spread --dask

The problem is the 2D plug of the scale issues (examples/plug2d.toml with nx = ny = n,
triangles, mu = 2; m = 2n contact nodes), method pattern-search.

- `--spread`: the command, each shard on one thread (RAYON_NUM_THREADS=1; `--jobs` of them at
  once), each shard's search nodes (all it visited; the split's walks over the top of the tree,
  which every shard makes, given apart) and seconds, and the largest shard's share against 3/N.
- `--dask`: `wedged.distributed.enumerate` with `--shards` tasks on a LocalCluster of 1 and
  then 2 worker processes, one thread each (RAYON_NUM_THREADS=1 in the workers), whole calls
  timed, and the merged answer compared with one run of the command (pieces, witnesses,
  statuses: everything but `info`).

Prints Markdown tables for BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIN = ROOT / "target" / "release" / "wedged"


def plug(directory: Path, n: int) -> Path:
    text = (ROOT / "examples" / "plug2d.toml").read_text()
    text = text.replace("mu = 1.8", "mu = 2.0")
    text = text.replace("nx = 8 ", f"nx = {n} ").replace("ny = 6 ", f"ny = {n} ")
    text = text.replace('element = "quad"', 'element = "tri"')
    path = directory / f"plug_{n}.toml"
    path.write_text(text)
    return path


def stable(doc: dict) -> dict:
    out = {k: v for k, v in doc.items() if k != "info"}
    if "model" in out:
        out["model"] = {k: v for k, v in out["model"].items() if k != "seconds_condense"}
    return out


def run(args: list[str], threads: int | None = None) -> float:
    env = dict(os.environ)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = str(threads)
    start = time.perf_counter()
    subprocess.run([str(BIN), *args], check=True, capture_output=True, env=env)
    return time.perf_counter() - start


def spread(problem: Path, shards: int, directory: Path, jobs: int) -> None:
    from concurrent.futures import ThreadPoolExecutor

    def one(i: int) -> float:
        part = directory / f"part-{i}.json"
        return run(["enumerate", str(problem), "--shard", f"{i}/{shards}", "--json", str(part)], 1)

    with ThreadPoolExecutor(jobs) as pool:
        times = list(pool.map(one, range(1, shards + 1)))
    rows = []
    for i, seconds in zip(range(1, shards + 1), times):
        part = directory / f"part-{i}.json"
        doc = json.loads(part.read_text())
        s = doc["shard"]
        rows.append((i, doc["info"]["nodes_visited"], s["split_nodes"], s["own_units"], seconds))
    total = sum(r[1] - r[2] for r in rows)
    print(f"\nsplit at depth {s['split_depth']} into {s['units']} units\n")
    print("| shard | own units | nodes (split's walks apart) | split's walks | seconds (1 thread) |")
    print("|---|---|---|---|---|")
    for i, nodes, split, own, seconds in rows:
        print(f"| {i} | {own} | {nodes - split:,} | {split:,} | {seconds:.2f} |")
    largest = max(r[1] - r[2] for r in rows)
    times = [r[4] for r in rows]
    print(
        f"\nlargest shard: {largest / total:.3f} of the shards' nodes (3/N = {3 / shards:.3f}, "
        f"1/N = {1 / shards:.3f}); seconds min {min(times):.2f}, max {max(times):.2f}, "
        f"sum {sum(times):.2f}"
    )


def dask(problem: Path, shards: int, whole: dict) -> None:
    os.environ["RAYON_NUM_THREADS"] = "1"  # the workers inherit it
    from dask.distributed import Client, LocalCluster

    import wedged.distributed

    print("\n| workers | shards | seconds | same answer as one run |")
    print("|---|---|---|---|")
    times = {}
    for workers in (1, 2):
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster, Client(cluster) as client:
            start = time.perf_counter()
            result = wedged.distributed.enumerate(str(problem), client=client, shards=shards)
            times[workers] = time.perf_counter() - start
        same = stable(json.loads(result.to_json())) == stable(whole)
        print(f"| {workers} | {shards} | {times[workers]:.1f} | {same} |", flush=True)
    print(f"\n2 workers against 1: {times[1] / times[2]:.2f}x")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=30, help="mesh divisions (m = 2n)")
    ap.add_argument("--shards", type=int, default=16)
    ap.add_argument("--spread", action="store_true")
    ap.add_argument("--dask", action="store_true")
    ap.add_argument("--jobs", type=int, default=1, help="shards run at once by --spread")
    ap.add_argument("--skip-whole", action="store_true", help="no one run (--spread only)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        directory = Path(d)
        problem = plug(directory, a.n)
        whole = None
        if not a.skip_whole:
            whole_json = directory / "whole.json"
            seconds = run(
                ["enumerate", str(problem), "--method", "pattern-search", "--json", str(whole_json)]
            )
            whole = json.loads(whole_json.read_text())
            print(
                f"plug n = {a.n} (m = {2 * a.n}): one run of the command {seconds:.2f} s "
                f"(2 threads), {len(whole['patterns'])} pieces, "
                f"{whole['info']['nodes_visited']:,} search nodes",
                flush=True,
            )
        if a.spread:
            spread(problem, a.shards, directory, a.jobs)
        if a.dask:
            if whole is None:
                raise SystemExit("--dask compares with one run: drop --skip-whole")
            dask(problem, a.shards, whole)


if __name__ == "__main__":
    main()
