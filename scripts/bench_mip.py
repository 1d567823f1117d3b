"""wedged critical against the route a user without wedged would take (issue 21): bisection on
mu, each step a big-M mixed-integer feasibility program solved by HiGHS (through SciPy).

    python3 scripts/bench_mip.py [--sizes 10,16,20] [--cap 600] [--rel 1e-6]

If SciPy is missing, the script makes target/bench-venv, installs NumPy and SciPy there (from
the package registry) and runs itself again in it. It needs the release binary
(`cargo build --release`).

Instances: the 2D plug of the scale issues (examples/plug2d.toml with nx = ny = n, triangles,
mu = 2; m = 2n contact nodes), condensed by `wedged condense --mtx`, so that both routes solve
the same K.

The mixed-integer route, at a given mu: unknowns u (2m, the contact displacements in local
frames) and z (m binaries), r = K u, and
    u_n >= 0, r_n >= 0, |r_t| <= mu r_n, sum r_n = 1,
    u_n_i <= U_i z_i, r_n_i <= 1 - z_i,
with U_i = max_j (|C_{n_i n_j}| + mu |C_{n_i t_j}|) (C = K^-1), a valid bound on u_n_i (u = C r
with sum r_n = 1 and |r_t_j| <= mu r_n_j), and r_n_i <= 1 exact: no big-M guesswork. Bisection
starts from [0, hi], hi doubled from 1 until feasible, and stops when hi - lo <= rel * hi. Its
bracket carries no certificate (HiGHS's tolerances decide each step), and it is given the
looser width (1e-6 by default against wedged's 1e-9), which favours it.

Each route is timed as a whole: wedged's process (`wedged critical FILE --json`), and the
bisection's HiGHS calls (the condensation is not counted for it). A route that passes --cap
seconds is reported as "> cap". Prints a Markdown table for BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIN = ROOT / "target" / "release" / "wedged"


def ensure_scipy() -> None:
    try:
        import scipy.optimize  # noqa: F401
    except ImportError:
        venv = ROOT / "target" / "bench-venv"
        python = venv / "bin" / "python"
        if Path(sys.executable).resolve() == python.resolve():
            sys.exit("error: SciPy could not be installed in target/bench-venv")
        if not python.exists():
            subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        subprocess.run(
            [str(python), "-m", "pip", "install", "-q", "numpy", "scipy>=1.9"], check=True
        )
        os.execv(str(python), [str(python), __file__, *sys.argv[1:]])


def plug_file(directory: Path, n: int) -> Path:
    text = (ROOT / "examples" / "plug2d.toml").read_text()
    lines = []
    for line in text.splitlines():
        key = line.split("=")[0].strip()
        if key in ("nx", "ny"):
            line = f"{key} = {n}"
        elif key == "element":
            line = 'element = "tri"'
        elif key == "mu":
            line = "mu = 2.0"
        lines.append(line)
    path = directory / f"plug_{n}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def run_wedged(problem: Path, cap: float) -> tuple[float, float | None, str]:
    out = problem.with_suffix(".json")
    start = time.perf_counter()
    proc = subprocess.run(
        [str(BIN), "critical", str(problem), "--json", str(out), "--time-limit", str(cap)],
        capture_output=True,
        text=True,
    )
    seconds = time.perf_counter() - start
    if proc.returncode not in (0, 3):
        sys.exit(f"error: wedged critical failed on {problem}: {proc.stderr.strip()}")
    report = json.loads(out.read_text())
    return seconds, report.get("mu_critical"), report["status"]


def condensed(problem: Path):
    import numpy as np
    import scipy.io

    mtx = problem.with_suffix(".mtx")
    subprocess.run(
        [str(BIN), "condense", str(problem), "--mtx", str(mtx)], check=True, capture_output=True
    )
    k = np.asarray(scipy.io.mmread(str(mtx)).todense(), dtype=float)
    k = 0.5 * (k + k.T)
    # The plug's K is in Pa (about 1e11), its displacements about 1e-11: far outside the
    # absolute tolerances of HiGHS (1e-7 and 1e-6), which then decides wrongly. mu* does not
    # change when K is scaled, so the MIP gets K with unit diagonal scale (what a careful user
    # would do).
    return k / np.max(np.abs(np.diag(k)))


class Mip:
    """The big-M feasibility program of WP at a given mu (module docs)."""

    def __init__(self, k):
        import numpy as np

        self.k = k
        self.m = k.shape[0] // 2
        self.c = np.linalg.inv(k)
        self.solves = 0

    def feasible(self, mu: float, time_left: float) -> bool | None:
        import numpy as np
        from scipy.optimize import Bounds, LinearConstraint, milp

        k, c, m = self.k, self.c, self.m
        n_idx = np.arange(m) * 2
        t_idx = n_idx + 1
        kn, kt = k[n_idx, :], k[t_idx, :]
        # U_i bounds u_n_i.
        big_u = np.max(np.abs(c[n_idx][:, n_idx]) + mu * np.abs(c[n_idx][:, t_idx]), axis=1)
        nv = 2 * m + m
        rows, lo, hi = [], [], []

        def add(row_u, row_z, lower, upper):
            rows.append(np.concatenate([row_u, row_z]))
            lo.append(lower)
            hi.append(upper)

        zero_z = np.zeros(m)
        for i in range(m):
            add(kn[i], zero_z, 0.0, np.inf)  # r_n_i >= 0
            add(kt[i] - mu * kn[i], zero_z, -np.inf, 0.0)  # r_t <= mu r_n
            add(-kt[i] - mu * kn[i], zero_z, -np.inf, 0.0)  # -r_t <= mu r_n
            e = np.zeros(m)
            e[i] = 1.0
            add(kn[i], e, -np.inf, 1.0)  # r_n_i <= 1 - z_i
            un = np.zeros(2 * m)
            un[2 * i] = 1.0
            add(un, -big_u[i] * e, -np.inf, 0.0)  # u_n_i <= U_i z_i
        add(kn.sum(axis=0), zero_z, 1.0, 1.0)  # sum r_n = 1
        a = np.array(rows)
        lower = np.full(nv, -np.inf)
        upper = np.full(nv, np.inf)
        lower[n_idx] = 0.0  # u_n >= 0
        lower[2 * m :] = 0.0
        upper[2 * m :] = 1.0
        integrality = np.concatenate([np.zeros(2 * m), np.ones(m)])
        self.solves += 1
        res = milp(
            np.zeros(nv),
            integrality=integrality,
            bounds=Bounds(lower, upper),
            constraints=LinearConstraint(a, lo, hi),
            options={"time_limit": max(time_left, 1.0), "disp": False},
        )
        if res.status == 0:
            return True
        if res.status == 2:
            return False
        return None  # the time limit, or HiGHS could not decide


def bisection(k, rel: float, cap: float) -> tuple[float, float | None, int, str]:
    mip = Mip(k)
    start = time.perf_counter()

    def left() -> float:
        return cap - (time.perf_counter() - start)

    hi = 1.0
    while True:
        verdict = mip.feasible(hi, left())
        if verdict is None or left() <= 0:
            return time.perf_counter() - start, None, mip.solves, "cap"
        if verdict:
            break
        hi *= 2.0
        if hi > 1e6:
            return time.perf_counter() - start, None, mip.solves, "never (to 1e6)"
    lo = 0.0
    while hi - lo > rel * hi:
        mid = 0.5 * (lo + hi)
        verdict = mip.feasible(mid, left())
        if verdict is None or left() <= 0:
            return time.perf_counter() - start, hi, mip.solves, "cap"
        if verdict:
            hi = mid
        else:
            lo = mid
    return time.perf_counter() - start, hi, mip.solves, "done"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="10,16,20", help="plug divisions n (m = 2n)")
    parser.add_argument("--cap", type=float, default=600.0, help="seconds per route and size")
    parser.add_argument("--rel", type=float, default=1e-6, help="the bisection's relative width")
    args = parser.parse_args()
    ensure_scipy()
    if not BIN.exists():
        sys.exit("error: build the release binary first: cargo build --release")
    import scipy

    sizes = [int(s) for s in args.sizes.split(",")]
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores; SciPy {scipy.__version__} "
        f"(HiGHS); cap {args.cap:g} s; bisection to {args.rel:g} relative, wedged to 1e-9"
    )
    print()
    print("| m | wedged critical (whole process) | mu* | bisection + HiGHS MIP | steps | its mu | ratio |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            problem = plug_file(Path(tmp), n)
            w_seconds, w_mu, w_status = run_wedged(problem, args.cap)
            k = condensed(problem)
            m_seconds, m_mu, steps, m_status = bisection(k, args.rel, args.cap)
            w_text = f"{w_seconds:.2f} s" if w_status != "incomplete" else f"> {args.cap:g} s"
            m_text = f"{m_seconds:.2f} s" if m_status == "done" else f"> {args.cap:g} s"
            ratio = (
                f"{m_seconds / w_seconds:.0f}x"
                if m_status == "done" and w_status != "incomplete"
                else (f"> {m_seconds / w_seconds:.0f}x" if w_status != "incomplete" else "")
            )
            mu_text = f"{w_mu:.9f}" if w_mu is not None else w_status
            m_mu_text = f"{m_mu:.7f}" if m_mu is not None else m_status
            print(
                f"| {2 * n} | {w_text} | {mu_text} | {m_text} | {steps} | {m_mu_text} | {ratio} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
