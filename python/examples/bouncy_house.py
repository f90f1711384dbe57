"""The seeds' bouncy house (GAMES103 HW3): explicit StVK on a sticky floor, kicked up by the
space bar's impulse at 1 s, with its energy ledger printed every half second.

    .venv/bin/python python/examples/bouncy_house.py [seconds]
"""
import sys

import femto

seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 5.0
scene = femto.Scene.house()  # what `femto run` runs: 400 vertices, 1389 tets
house = scene.bodies[0]
frames = round(seconds / scene.frame_time)
for frame in range(1, frames + 1):
    if frame == round(1.0 / scene.frame_time):
        house.apply_impulse((0.0, 10.0, 0.0))  # the space bar: up at 10 m/s
    scene.step()
    if frame % round(0.5 / scene.frame_time) == 0:
        s = house.stats
        print("t %5.2f s  centre y %+.3f m  kinetic %8.2f J  elastic %8.2f J  inverted %d" % (
            frame * scene.frame_time, s["center_of_mass"][1], s["kinetic_energy"],
            s["elastic_energy"], s["inverted_tets"]))
lowest = house.positions()[:, 1].min()
print("after %.1f s the house's lowest vertex is at y = %.4f m (the floor: -3)" % (seconds, lowest))
