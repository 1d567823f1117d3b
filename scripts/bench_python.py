"""What the Python bindings add to a call (issue 23: at most 2 ms a call, at most 5% of a run of
1 s or more). Run it in the environment scripts/test makes (or any with `wedged` installed):

    target/venv/bin/python scripts/bench_python.py [--repeat 200]

Small calls: seeded random 2D problems with m = 9 contact nodes at mu = 1.5 (the issue-20
family). For each, the median over `--repeat` calls of `wedged.enumerate(K, 1.5)` from
Python, against the library's own time for the same run (`info.seconds`: the enumeration,
without the checks of `K` and the JSON). Their difference is what the bindings and the
problem's set-up add. A long call: the 2D plug with m = 40 at mu = 2 (`pattern-search`),
Python against the command's whole process on the same problem file, medians of 3.
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
    return a @ a.T + m * np.eye(2 * m)


def small_calls(repeat: int) -> list[str]:
    rows = []
    for seed in range(5):
        k = random_k(seed, 9)
        wedged.enumerate(k, 1.5)  # warm
        calls, inside = [], []
        for _ in range(repeat):
            start = time.perf_counter()
            result = wedged.enumerate(k, 1.5)
            calls.append(time.perf_counter() - start)
            inside.append(result.info["seconds"])
        call, lib = statistics.median(calls), statistics.median(inside)
        rows.append(
            f"| random m = 9, seed {seed} | {len(result.rays)} rays | {1e3 * call:.2f} ms "
            f"| {1e3 * lib:.2f} ms | {1e3 * (call - lib):.2f} ms |"
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
        python, command = [], []
        for _ in range(3):
            start = time.perf_counter()
            result = problem.enumerate(method="pattern-search")
            python.append(time.perf_counter() - start)
            start = time.perf_counter()
            done = subprocess.run(
                [str(wedged_bin), "enumerate", str(path), "--method", "pattern-search", "--json", "-"],
                capture_output=True,
                check=True,
            )
            command.append(time.perf_counter() - start)
            assert len(json.loads(done.stdout)["patterns"]) == len(result.patterns)
        py, cli = statistics.median(python), statistics.median(command)
        return (
            f"| plug m = 40, pattern-search (load excluded) | {len(result.patterns)} pieces "
            f"| {py:.3f} s | {cli:.3f} s (whole process) | {100 * (py / cli - 1):+.1f}% |"
        )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=200)
    parser.add_argument("--wedged", type=Path, default=ROOT / "target" / "release" / "wedged")
    args = parser.parse_args()
    print("| problem | answer | Python call (median) | library's own time | added |")
    print("|---|---|---|---|---|")
    for row in small_calls(args.repeat):
        print(row)
    print(long_call(args.wedged))


if __name__ == "__main__":
    main()
