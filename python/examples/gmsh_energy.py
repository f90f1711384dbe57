"""Read a Gmsh mesh, drop it on the floor, and plot its energy ledger with matplotlib:
kinetic, elastic and gravity energy and their sum, which the floor's stick and the damping
only take from (femto's health check holds every body to its ledger).

    .venv/bin/python python/examples/gmsh_energy.py [mesh.msh] [plot.png]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import femto  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    here, "..", "..", "tests", "data", "mesh", "cube_gmsh41.msh")
out = sys.argv[2] if len(sys.argv) > 2 else "energy.png"

mesh = femto.TetMesh.load(path)
lo, hi = np.min(mesh.vertices, axis=0), np.max(mesh.vertices, axis=0)
mesh.transform(scale=0.5 / np.max(hi - lo), center=True)
world = femto.World(integrator="implicit", floor={"height": -1.0})
body = world.add_body(mesh, femto.Material("neohookean", youngs_modulus=5e4,
                                           poisson_ratio=0.35),
                      mass_mode="density", density=800.0)
times, ledger = [], {"kinetic": [], "elastic": [], "gravity": []}
for frame in range(120):
    world.step(1 / 60)
    s = body.stats
    times.append((frame + 1) / 60)
    ledger["kinetic"].append(s["kinetic_energy"])
    ledger["elastic"].append(s["elastic_energy"])
    ledger["gravity"].append(s["gravity_energy"])
total = np.sum([ledger[k] for k in ledger], axis=0)
for name, values in ledger.items():
    plt.plot(times, values, label=name)
plt.plot(times, total, "k--", label="total")
plt.xlabel("time (s)")
plt.ylabel("energy (J)")
plt.title("%s: %d tets dropped on the floor" % (os.path.basename(path), mesh.tet_count))
plt.legend()
plt.savefig(out, dpi=100)
rise = np.max(np.diff(total))
print("%s: %d vertices, %d tets; the total energy went from %.3f J to %.3f J (largest rise in a "
      "frame %.2e J); plot in %s" % (os.path.basename(path), mesh.vertex_count, mesh.tet_count,
                                     total[0], total[-1], rise, out))
