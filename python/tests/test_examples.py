"""The examples run as a user runs them, and say what they should."""
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "examples")


def run(name, *args):
    done = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_bouncy_house_jumps_and_never_inverts():
    out = run("bouncy_house.py", "2")
    heights = [float(y) for y in re.findall(r"centre y ([-+0-9.]+)", out)]
    assert len(heights) == 3 and max(heights) > 3.0  # the kick at 1 s throws it up
    assert all(n == "0" for n in re.findall(r"inverted (\d+)", out))


def test_the_sweep_squashes_soft_boxes_more():
    rows = [line.split() for line in run("material_sweep.py").splitlines()[1:]]
    squash = {(float(r[0]), float(r[1])): float(r[3]) for r in rows}
    assert len(squash) == 9
    for nu in (0.0, 0.3, 0.45):
        assert squash[(2e4, nu)] > squash[(5e4, nu)] > squash[(2e5, nu)] > 0
    # Stiff and unconstrained (nu = 0): within 15% of the column's rho g h^2 / (2 E).
    estimate = float(rows[6][4])
    assert abs(squash[(2e5, 0.0)] - estimate) < 0.15 * estimate


def test_the_gmsh_cube_loses_energy_and_never_gains_it(tmp_path):
    plot = tmp_path / "energy.png"
    out = run("gmsh_energy.py", os.path.join(HERE, "..", "..", "tests", "data", "mesh",
                                              "cube_gmsh41.msh"), str(plot))
    assert plot.stat().st_size > 10000
    rise = float(re.search(r"largest rise in a frame ([-+0-9.e]+) J", out).group(1))
    assert rise < 1e-6
