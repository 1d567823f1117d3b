"""An experiment for issue 21 (not part of the tests): is WP infeasible at mu by the doubly
nonnegative (DNN) relaxation of its complementarity?

WP at mu has a nontrivial solution exactly when the quadratic form r_n . u_n (u = K^-1 r)
vanishes somewhere on the polyhedral cone C of reactions with u_n >= 0 and the friction cones
(no complementarity). Writing r = E z with z >= 0 the friction-edge coefficients (r_n_i =
z+_i + z-_i, r_t_i = mu (z+_i - z-_i)) and B z = u_n, the relaxation asks for a matrix Z (in
place of z z^T) with

    Z positive semidefinite, Z >= 0, Z B^T >= 0, B Z B^T >= 0, <Q, Z> = 0, a^T Z a = 1

(Q the form r_n . u_n in z, a^T z = sum r_n). Infeasible means no wedged configuration at mu.
`--drop` removes one family of constraints to see which ones the bound needs.

    python3 -m venv /tmp/cvx && /tmp/cvx/bin/pip install cvxpy scipy
    wedged condense plug.toml --mtx K.mtx
    /tmp/cvx/bin/python scripts/dnn_bound.py K.mtx 1.6,1.65,1.7 [--drop psd|Z|ZB|BZB]

Prints, per mu, the solver's status and time. Results: BENCHMARKS.md, "A doubly nonnegative
relaxation of mu* (tried)".
"""

from __future__ import annotations

import argparse
import time

import cvxpy as cp
import numpy as np
import scipy.io


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mtx", help="the condensed stiffness (wedged condense --mtx)")
    parser.add_argument("mus", help="friction coefficients, comma-separated")
    parser.add_argument("--drop", choices=["psd", "Z", "ZB", "BZB"], default=None)
    args = parser.parse_args()
    k = scipy.io.mmread(args.mtx)
    k = k.toarray() if hasattr(k, "toarray") else np.asarray(k)
    c = np.linalg.inv(k)
    m = k.shape[0] // 2
    for mu in (float(x) for x in args.mus.split(",")):
        e = np.zeros((2 * m, 2 * m))
        for i in range(m):
            e[2 * i, 2 * i] = e[2 * i, 2 * i + 1] = 1.0
            e[2 * i + 1, 2 * i], e[2 * i + 1, 2 * i + 1] = mu, -mu
        b = (c @ e)[0::2, :]
        b = b / np.abs(b).max()
        en = e[0::2, :]
        q = en.T @ b
        q = (q + q.T) / 2
        a = en.T @ np.ones(m)
        z = cp.Variable((2 * m, 2 * m), symmetric=True)
        cons = [cp.trace(q @ z) == 0, a @ z @ a == 1]
        if args.drop != "psd":
            cons.append(z >> 0)
        if args.drop != "Z":
            cons.append(z >= 0)
        if args.drop != "ZB":
            cons.append(z @ b.T >= 0)
        if args.drop != "BZB":
            cons.append(b @ z @ b.T >= 0)
        problem = cp.Problem(cp.Minimize(0), cons)
        start = time.time()
        try:
            problem.solve(solver=cp.CLARABEL)
            status = problem.status
        except cp.error.SolverError:
            status = "solver failed"
        print(f"m = {m}, mu = {mu}: {status} in {time.time() - start:.1f} s", flush=True)


if __name__ == "__main__":
    main()
