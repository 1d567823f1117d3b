"""Shared helpers of the Python package's tests: the repository, the command, the JSON
documents compared without their timings."""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
FIXTURES = ROOT / "crates" / "wedged-cli" / "tests" / "fixtures"
EXAMPLES = ROOT / "examples"



def wedged_bin() -> Path:
    """The command (`WEDGED_BIN`, which scripts/test sets; else the release build)."""
    path = Path(os.environ.get("WEDGED_BIN", ROOT / "target" / "release" / "wedged"))
    if not path.exists():
        pytest.fail(f"the wedged command is not built at {path}: run scripts/test, or set WEDGED_BIN")
    return path


def cli_json(*args: str) -> dict:
    """The JSON document of `wedged ARGS --json -` (exit code 0 expected)."""
    done = subprocess.run(
        [str(wedged_bin()), *args, "--json", "-"], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, f"wedged {' '.join(args)}: exit {done.returncode}: {done.stderr}"
    return json.loads(done.stdout)


def stable(doc: dict) -> dict:
    """A JSON document without what measures the run: `info` (time, memory, and the counts
    of the parallel searches, which vary from run to run) and the model's timings."""
    out = {k: v for k, v in doc.items() if k != "info"}
    if "model" in out:
        out["model"] = {k: v for k, v in out["model"].items() if "seconds" not in k}
    return out


def same_critical(python: dict, command: dict) -> None:
    """Two runs of `critical` agree: the same facts, and brackets of mu* that overlap and
    have the width asked. (The branch and bound runs in parallel, so two runs may end at
    different witnesses, mirror images on a symmetric body, and upper ends within the
    bracket's width.)"""
    for key in ["source", "dim", "nodes", "method", "status", "complete", "stopped", "tol", "certified"]:
        assert python[key] == command[key], key
    if command["status"] == "wedged":
        width = 2 * command["tol"] * command["upper"]
        assert abs(python["mu_critical"] - command["mu_critical"]) <= width
        assert python["lower"] <= command["upper"] and command["lower"] <= python["upper"]
        assert (python["witness"] is None) == (command["witness"] is None)


def two_node_k() -> np.ndarray:
    """Two contact nodes that do not interact (tests/fixtures/two_nodes.toml): each wedges
    alone once mu > 1."""
    return np.array(
        [[2.0, 1.0, 0.0, 0.0], [1.0, 1.0, 0.0, 0.0], [0.0, 0.0, 2.0, 1.0], [0.0, 0.0, 1.0, 1.0]]
    )


def random_k(seed: int, m: int, dim: int = 2) -> np.ndarray:
    """A seeded random stiffness with some frictional coupling (symmetric positive definite)."""
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(dim * m, dim * m))
    return a @ a.T + 0.5 * dim * m * np.eye(dim * m)


def plug_toml(tmp_path: Path, n: int, mu: float = 2.0, element: str = "tri") -> Path:
    """The command's plug (issue 20's) with an n x n mesh: m = 2n contact nodes."""
    text = (EXAMPLES / "plug2d.toml").read_text()
    text = text.replace("mu = 1.8", f"mu = {mu}")
    text = text.replace("nx = 8 ", f"nx = {n} ").replace("ny = 6 ", f"ny = {n} ")
    text = text.replace('element = "quad"', f'element = "{element}"')
    path = tmp_path / f"plug_{n}.toml"
    path.write_text(text)
    return path


def skfem_example():
    """examples/python/skfem_plug.py as a module (it needs scikit-fem and meshio)."""
    spec = importlib.util.spec_from_file_location("skfem_plug", EXAMPLES / "python" / "skfem_plug.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
