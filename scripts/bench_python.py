"""What the Python bindings add to a call (issue 23: at most 2 ms a call, at most 5% of a run of
1 s or more). Run it in the environment scripts/test makes (or any with `wedged` installed):

    target/venv/bin/python scripts/bench_python.py [--repeat 200]

Small calls: seeded random 2D problems with m = 9 contact nodes at mu = 1.5 (K = A A^T + 0.9 I,
A normal: from 8 to 439 rays). For each, over `--repeat` calls of `wedged.enumerate(K, 1.5)`:
the median call, the median of the library's own run (`library_seconds`, the wall time of the
library's run on the bindings' worker thread), and the median per call of their difference,
which is what the bindings add: `K` copied and checked (`Problem::new`), the worker thread,
the arrays and the result objects. The records (rays, cones, pieces) are made when first read,
so the table gives what the call adds and what it adds with every record read. A long call: the 2D plug with m = 40 at mu = 2
(`pattern-search`), the same with medians of 3, and the command's whole process on the same
problem file for comparison.
Prints a Markdown table for BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import wedged

ROOT = Path(__file__).resolve().parents[1]


def random_k(seed: int, m: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(2 * m, 2 * m))
    return a @ a.T + 0.1 * m * np.eye(2 * m)


def small_calls(repeat: int) -> list[str]:
    rows = []
    for seed in range(5):
        k = random_k(seed, 9)
        result = wedged.enumerate(k, 1.5)  # warm
        calls, inside, added, records = [], [], [], []
        for _ in range(repeat):
            result = None  # the previous result freed outside the timing
            start = time.perf_counter()
            result = wedged.enumerate(k, 1.5)
            call = time.perf_counter() - start
            # The records, made when first read (every ray's arrays and statuses, every cone
            # and piece).
            start = time.perf_counter()
            count = len(result.rays) + len(result.cones) + len(result.patterns)
            records.append(time.perf_counter() - start)
            calls.append(call)
            inside.append(result.library_seconds)
            added.append(call - result.library_seconds)
        both = [a + r for a, r in zip(added, records)]
        rows.append(
            f"| random m = 9, seed {seed} | {len(result.rays)} rays, {count - len(result.rays)} "
            f"cones and pieces | {1e3 * statistics.median(calls):.2f} ms "
            f"| {1e3 * statistics.median(inside):.2f} ms "
            f"| {1e3 * statistics.median(added):.2f} ms "
            f"| {1e3 * statistics.median(both):.2f} ms |"
        )
    return rows


def long_call(wedged_bin: Path) -> str:
    text = (ROOT / "examples" / "plug2d.toml").read_text()
    text = text.replace("mu = 1.8", "mu = 2.0").replace("nx = 8 ", "nx = 20 ")
    text = text.replace("ny = 6 ", "ny = 20 ").replace('element = "quad"', 'element = "tri"')
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "plug40.toml"
        path.write_text(text)
        problem = wedged.load(path)
        python, command, added = [], [], []
        for _ in range(3):
            result = None
            start = time.perf_counter()
            result = problem.enumerate(method="pattern-search")
            python.append(time.perf_counter() - start)
            added.append(python[-1] - result.library_seconds)
            start = time.perf_counter()
            len(result.patterns)
            added[-1] += time.perf_counter() - start
            start = time.perf_counter()
            done = subprocess.run(
                [str(wedged_bin), "enumerate", str(path), "--method", "pattern-search", "--json", "-"],
                capture_output=True,
                check=True,
            )
            command.append(time.perf_counter() - start)
            assert len(json.loads(done.stdout)["patterns"]) == len(result.patterns)
        py, cli, extra = (statistics.median(x) for x in (python, command, added))
        return (
            f"| plug m = 40, pattern-search | {len(result.patterns)} pieces | {py:.3f} s "
            f"(the command's whole process: {cli:.3f} s) | {py - extra:.3f} s "
            f"| | {1e3 * extra:.2f} ms ({100 * extra / (py - extra):.2f}%) |"
        )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=200)
    parser.add_argument("--wedged", type=Path, default=ROOT / "target" / "release" / "wedged")
    args = parser.parse_args()
    print(
        "| problem | answer | Python call (median) | the library's run | added to the call "
        "| added, with every record read |"
    )
    print("|---|---|---|---|---|---|")
    for row in small_calls(args.repeat):
        print(row)
    print(long_call(args.wedged))


if __name__ == "__main__":
    main()
