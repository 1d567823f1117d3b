"""An experiment for issues 20 and 21 (not part of the tests): does the doubly nonnegative (DNN)
relaxation of WP's complementarity decide WP at mu, or one node's contact decision?

WP at mu has a nontrivial solution exactly when the quadratic form r_n . u_n (u = K^-1 r)
vanishes somewhere on the polyhedral cone C of reactions with u_n >= 0 and the friction cones
(no complementarity). Writing r = E z with z >= 0 the friction-edge coefficients (r_n_i =
z+_i + z-_i, r_t_i = mu (z+_i - z-_i)) and B z = u_n, the relaxation asks for a matrix Z (in
place of z z^T) with

    Z positive semidefinite, Z >= 0, Z B^T >= 0, B Z B^T >= 0, <Q, Z> = 0, a^T Z a = 1

(Q the form r_n . u_n in z, a^T z = sum r_n). Infeasible means no wedged configuration at mu.
`--drop` removes one family of constraints to see which ones the bound needs.

`--decide PIECES.json` (the JSON of `wedged enumerate --json` at the first mu) asks, for every
node i and both of its decisions, whether the relaxation with that decision added is feasible
(contact: u_n_i = 0, so Z B_i^T = 0; separated: r_i = 0, so the rows of z+_i and z-_i vanish),
and prints how many of the pieces take the decision: a decision no piece takes is the root of a
dead subtree of the contact-set search, which the relaxation should refute. `--nodes 0,1,8`
restricts it to some nodes.

    python3 -m venv /tmp/cvx && /tmp/cvx/bin/pip install cvxpy scipy
    wedged condense plug.toml --mtx K.mtx
    /tmp/cvx/bin/python scripts/dnn_bound.py K.mtx 1.6,1.65,1.7 [--drop psd|Z|ZB|BZB]
    wedged enumerate plug.toml --json pieces.json
    /tmp/cvx/bin/python scripts/dnn_bound.py K.mtx 2.0 --decide pieces.json [--nodes 0,1]

Prints, per mu (or per decision), the solver's status and time. Results: BENCHMARKS.md, "A
doubly nonnegative relaxation of mu* (tried, not kept)" and "Dead subtrees refuted by the
doubly nonnegative relaxation".
"""

from __future__ import annotations

import argparse
import json
import time

import cvxpy as cp
import numpy as np
import scipy.io


def relaxation(c: np.ndarray, mu: float, drop: str | None, fixes: list[tuple[int, bool]]):
    """The DNN relaxation for compliance `c` at `mu`, with the decisions `fixes`
    ((node, contact?)) added; a cvxpy problem whose status says feasible or not."""
    m = c.shape[0] // 2
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
    if drop != "psd":
        cons.append(z >> 0)
    if drop != "Z":
        cons.append(z >= 0)
    if drop != "ZB":
        cons.append(z @ b.T >= 0)
    if drop != "BZB":
        cons.append(b @ z @ b.T >= 0)
    for node, contact in fixes:
        if contact:
            cons.append(z @ b[node, :] == 0)
        else:
            cons += [z[2 * node, :] == 0, z[2 * node + 1, :] == 0]
    return cp.Problem(cp.Minimize(0), cons)


def status_of(problem) -> tuple[str, float]:
    start = time.time()
    try:
        problem.solve(solver=cp.CLARABEL)
        status = problem.status
    except cp.error.SolverError:
        status = "solver failed"
    return status, time.time() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mtx", help="the condensed stiffness (wedged condense --mtx)")
    parser.add_argument("mus", help="friction coefficients, comma-separated")
    parser.add_argument("--drop", choices=["psd", "Z", "ZB", "BZB"], default=None)
    parser.add_argument("--decide", help="pieces (wedged enumerate --json) to decide nodes by")
    parser.add_argument("--nodes", help="with --decide: only these nodes, comma-separated")
    args = parser.parse_args()
    k = scipy.io.mmread(args.mtx)
    k = k.toarray() if hasattr(k, "toarray") else np.asarray(k)
    c = np.linalg.inv(k)
    m = k.shape[0] // 2
    mus = [float(x) for x in args.mus.split(",")]
    if args.decide is None:
        for mu in mus:
            status, seconds = status_of(relaxation(c, mu, args.drop, []))
            print(f"m = {m}, mu = {mu}: {status} in {seconds:.1f} s", flush=True)
        return
    pieces = json.load(open(args.decide))["patterns"]
    contact = [[s == "contact" for s in p["pattern"]] for p in pieces]
    nodes = range(m) if args.nodes is None else [int(x) for x in args.nodes.split(",")]
    for node in nodes:
        pressed = sum(p[node] for p in contact)
        for decision, taken in ((True, pressed), (False, len(contact) - pressed)):
            problem = relaxation(c, mus[0], args.drop, [(node, decision)])
            status, seconds = status_of(problem)
            name = "contact" if decision else "separated"
            print(
                f"node {node} {name}: taken by {taken} of {len(contact)} pieces, "
                f"relaxation {status} in {seconds:.1f} s",
                flush=True,
            )


if __name__ == "__main__":
    main()
