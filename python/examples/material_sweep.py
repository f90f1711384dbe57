"""A material sweep: a soft box dropped on the floor for each Young's modulus and Poisson
ratio, implicit Neo-Hookean, on a frictionless floor; prints how far each squashes at rest
against the 1-D small-strain estimate rho g h^2 / (2 E) of a column under its own weight
(Poisson's ratio and the large strain of the softest make the difference).

    .venv/bin/python python/examples/material_sweep.py
"""
import numpy as np

import femto

SIZE, DENSITY, G = 0.2, 1000.0, 9.8
print("    E (Pa)    nu   rest height (m)   squash (mm)   1-D estimate (mm)")
for youngs in (2e4, 5e4, 2e5):
    for poisson in (0.0, 0.3, 0.45):
        world = femto.World(integrator="implicit",
                            floor={"height": 0.0, "friction": "coulomb",
                                   "friction_coefficient": 0.0})
        mesh = femto.TetMesh.box((4, 4, 4), (-SIZE / 2, 0.0, -SIZE / 2),
                                 (SIZE / 2, SIZE, SIZE / 2))
        box = world.add_body(mesh, femto.Material("neohookean", youngs_modulus=youngs,
                                                  poisson_ratio=poisson),
                             mass_mode="density", density=DENSITY)
        for _ in range(240):
            world.step(1 / 60)
        y = box.positions()[:, 1]
        height = y.max() - y.min()
        estimate = DENSITY * G * SIZE * SIZE / (2 * youngs)
        print("%10.0f  %4.2f   %15.5f   %11.3f   %17.3f" % (
            youngs, poisson, height, 1e3 * (SIZE - height), 1e3 * estimate))
        world.close()
