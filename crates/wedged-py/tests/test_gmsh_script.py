"""A Gmsh script as the problem's mesh (examples/plug2d.geo, `[mesh.parameters]`), meshed by the
real Gmsh (the `gmsh` package that scripts/test installs): the mesh it gives is the one Gmsh's
own Python API makes of the script with the same parameters, in the command and in Python; the
parameters reach the script; a study varies them."""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

import wedged
from conftest import EXAMPLES, cli_json, wedged_bin

gmsh = pytest.importorskip("gmsh")

SCRIPT = EXAMPLES / "plug2d.geo"


@pytest.fixture(autouse=True)
def gmsh_on_the_path(monkeypatch):
    """The package's `gmsh` command (a Python script run by `python`) on the PATH, for the
    command and for the package, which both run it."""
    bin_dir = Path(sys.executable).parent
    assert (bin_dir / "gmsh").exists(), "the gmsh package's command is missing"
    monkeypatch.setenv("PATH", f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}")
    monkeypatch.delenv("WEDGED_GMSH", raising=False)


def problem(tmp_path: Path, mesh: str, name: str) -> Path:
    """examples/plug2d_geo.toml with its [mesh] table (and parameters) replaced by `mesh`."""
    text = (EXAMPLES / "plug2d_geo.toml").read_text()
    path = tmp_path / name
    path.write_text(text[: text.index("[mesh]")] + mesh + "\n" + text[text.index("[material]"):])
    return path


def by_the_api(tmp_path: Path, half_angle: float, lc: float) -> Path:
    """The script meshed by Gmsh's Python API with the parameters set as ONELAB numbers."""
    out = tmp_path / f"api_{half_angle}.msh"
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.onelab.setNumber("half_angle", [half_angle])
        gmsh.onelab.setNumber("lc", [lc])
        gmsh.open(str(SCRIPT))
        gmsh.model.mesh.generate(2)
        gmsh.write(str(out))
    finally:
        gmsh.finalize()
    return out


@pytest.mark.parametrize("half_angle", [15.0, 30.0])
def test_the_script_is_meshed_as_gmsh_meshes_it(tmp_path, half_angle):
    toml = problem(
        tmp_path,
        f'[mesh]\ngmsh = "{SCRIPT}"\n[mesh.parameters]\nhalf_angle = {half_angle}\nlc = 0.2\n',
        "plug.toml",
    )
    reference = problem(tmp_path, f'[mesh]\ngmsh = "{by_the_api(tmp_path, half_angle, 0.2)}"', "ref.toml")
    from_script, from_api = cli_json("critical", str(toml)), cli_json("critical", str(reference))
    # The same mesh, so the same mu*: within the bracket's width, the parallel search's
    # upper ends (conftest.same_critical).
    assert from_script["status"] == from_api["status"] == "wedged"
    width = 2 * from_script["tol"] * from_script["upper"]
    assert abs(from_script["mu_critical"] - from_api["mu_critical"]) <= width
    assert abs(wedged.load(toml).critical().mu - from_script["mu_critical"]) <= width
    assert from_script["nodes"] == from_api["nodes"] > 0
    # The parameter reached the script: the top corner is at 0.5 + tan(half_angle).
    points = wedged.load(toml).mesh()["points"]
    assert max(points[:, 0]) == pytest.approx(0.5 + math.tan(math.radians(half_angle)), rel=1e-12)


def test_a_parameter_the_script_overwrites_is_refused(tmp_path):
    # `lc` set by a plain assignment after the DefineConstant: it overwrites the value given.
    script = tmp_path / "plain.geo"
    script.write_text(
        SCRIPT.read_text()
        .replace('lc = {0.125, Name "lc"}', "dummy = {0}")
        .replace("t = Tan(", "lc = 0.125;\nt = Tan(")
    )
    text = (EXAMPLES / "plug2d_geo.toml").read_text().replace('gmsh = "plug2d.geo"', f'gmsh = "{script}"')
    toml = tmp_path / "plain.toml"
    toml.write_text(text.replace("lc = 0.125 ", "lc = 0.3 "))
    with pytest.raises(wedged.InputError, match=r"lc = 0.3, but .*plain.geo set it to 0.125"):
        wedged.load(toml)
    done = subprocess.run([str(wedged_bin()), "critical", str(toml)], capture_output=True, text=True)
    assert done.returncode == 2
    assert "DefineConstant[ lc = {0.125} ]" in done.stderr
    # The value the script sets itself, given: nothing to refuse.
    toml.write_text(text)
    assert wedged.load(toml).K.shape[0] > 0


def study(out: Path, *options: str) -> tuple:
    """`wedged study examples/plug2d_geo.toml OPTIONS --out OUT`, which must succeed: its
    output and the rows of its CSV."""
    done = subprocess.run(
        [str(wedged_bin()), "study", str(EXAMPLES / "plug2d_geo.toml"), *options, "--out", str(out)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    return done, list(csv.DictReader((out / "study.csv").open()))


def test_a_study_varies_the_scripts_parameters(tmp_path):
    _, rows = study(tmp_path / "study", "--vary", "mesh.parameters.half_angle=15,35")
    assert [r["mesh.parameters.half_angle"] for r in rows] == ["15", "35"]
    mus = [float(r["mu_star"]) for r in rows]
    assert all(r["complete"] == "true" for r in rows)
    assert mus[0] != mus[1]


def test_a_mesh_size_study_of_a_script_extrapolates(tmp_path):
    """The script's mesh size varied first, against h: one line, extrapolated to h = 0."""
    done, rows = study(tmp_path / "sizes", "--vary", "mesh.parameters.lc=0.2,0.1,0.07,0.05", "--x", "h")
    hs = [float(r["h"]) for r in rows]
    assert hs == sorted(hs, reverse=True) and len(set(hs)) == 4
    assert "extrapolated to h = 0: mu* = " in done.stdout, done.stdout


def test_size_factor_scales_every_mesh_size(tmp_path):
    """`size_factor = 2` with `lc = 0.1` is the mesh of `lc = 0.2`: the same K."""
    def load(lc: float, factor: str) -> wedged.Problem:
        return wedged.load(problem(
            tmp_path,
            f'[mesh]\ngmsh = "{SCRIPT}"\n{factor}[mesh.parameters]\nlc = {lc}\n',
            f"plug_{lc}_{len(factor)}.toml",
        ))
    scaled, plain, fine = load(0.1, "size_factor = 2.0\n"), load(0.2, ""), load(0.1, "")
    assert scaled.K.shape == plain.K.shape
    assert scaled.K.shape[0] < fine.K.shape[0]
    assert abs(scaled.K - plain.K).max() <= 1e-12 * abs(plain.K).max()


def test_refine_studies_any_script(tmp_path):
    """`--vary refine=...` on a script divides its size factor: h falls with the factor, and
    each finer point starts from the coarser answer."""
    done, rows = study(tmp_path / "refine", "--vary", "refine=1,1.5,2")
    hs = [float(r["h"]) for r in rows]
    ms = [int(r["m"]) for r in rows]
    assert hs == sorted(hs, reverse=True) and ms == sorted(ms) and len(set(ms)) == 3
    assert hs[0] / hs[2] == pytest.approx(2.0, rel=0.2)
    assert done.stdout.count("started from the coarser answer") == 2, done.stdout


def test_a_fine_script_starts_from_its_condensed_problem(tmp_path):
    """From 80 contact nodes on, `critical` on the script's unstructured mesh first solves
    its problem condensed onto about half its nodes and starts from that wedge; the bracket is
    that of `--no-chain`, and Python's."""
    toml = problem(tmp_path, f'[mesh]\ngmsh = "{SCRIPT}"\n[mesh.parameters]\nlc = 0.0267\n', "fine.toml")
    done = subprocess.run([str(wedged_bin()), "critical", str(toml)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "the problem condensed onto" in " ".join(done.stdout.split()), done.stdout
    chained = cli_json("critical", str(toml))
    assert 28 <= chained["info"]["condensed_nodes"] <= 43
    scratch = cli_json("critical", str(toml), "--no-chain")
    assert chained["nodes"] == scratch["nodes"] == 84
    width = 2 * scratch["tol"] * scratch["upper"]
    assert abs(chained["mu_critical"] - scratch["mu_critical"]) <= width
    assert abs(wedged.load(toml).critical().mu - scratch["mu_critical"]) <= width
