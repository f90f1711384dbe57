"""A parameter sweep with Dask: soft boxes of several materials dropped from several heights,
each run a scene file made from its parameters and stepped by femto, hundreds of runs spread
over a Dask cluster (docs/python.md, "Sweeps on a cluster").

    .venv/bin/python python/sweep/drop_sweep.py                      # a local cluster
    .venv/bin/python python/sweep/drop_sweep.py --scheduler tcp://host:8786
    .venv/bin/python python/sweep/drop_sweep.py --csv sweep.csv --quick

The code is the same for both: dask.distributed's Client is either a LocalCluster on this
machine or the scheduler given. Each task is a pure function of its scene: it writes the scene
JSON (the same file `femto run` takes), steps it with the femto package and returns numbers;
every worker needs the femto package (the same pip line on each machine) and nothing else.
"""
import argparse
import csv
import json
import os
import sys
import tempfile
import time

import numpy as np

YOUNGS = (2e4, 5e4, 1e5, 2e5, 5e5)         # Pa
POISSON = (0.0, 0.2, 0.35, 0.45)
HEIGHTS = tuple(0.25 * k for k in range(1, 11))  # m, the box's bottom above the floor
SIZE, DENSITY, RESTITUTION = 0.4, 500.0, 0.0


def scene_for(youngs, poisson, height):
    """The scene of one run: a 0.4 m Neo-Hookean box, its bottom at height, above a floor."""
    return {
        "description": "sweep: E %g Pa, nu %g, dropped from %g m" % (youngs, poisson, height),
        "integrator": "implicit",
        "dt": 1.0 / 60.0,
        "substeps": 1,
        "seconds": 3,
        "floor": {"height": 0.0, "friction": 0.5, "restitution": RESTITUTION},
        "bodies": [{
            "mesh": "box:3,3,3",
            "box_min": [-SIZE / 2, height, -SIZE / 2],
            "box_max": [SIZE / 2, height + SIZE, SIZE / 2],
            "material": {"model": "neohookean", "youngs_modulus": youngs,
                         "poisson_ratio": poisson, "density": DENSITY},
        }],
    }


def run(params):
    """One run (on a worker): the scene written, loaded and stepped; what it measured."""
    import femto  # on the worker
    youngs, poisson, height = params
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "drop.json")
        with open(path, "w") as f:
            json.dump(scene_for(youngs, poisson, height), f)
        scene = femto.Scene.load(path)
    box = scene.bodies[0]
    landed, rebound, squash, inverted = False, 0.0, 0.0, 0
    frames = round(3.0 / scene.frame_time)
    began = time.perf_counter()
    for _ in range(frames):
        scene.step()
        y = box.positions()[:, 1]
        stats = box.stats
        inverted = max(inverted, stats["inverted_tets"])
        if not landed and y.min() < 0.02:
            landed = True
        if landed:
            rebound = max(rebound, y.min())
            squash = max(squash, SIZE - (y.max() - y.min()))
    speed = float(np.abs(box.velocities()).max())
    return {"youngs": youngs, "poisson": poisson, "height": height, "rebound": rebound,
            "max_squash": squash, "rest_height": float(y.max() - y.min()), "end_speed": speed,
            "inverted": inverted, "seconds": time.perf_counter() - began}


def grid(quick):
    if quick:
        return [(e, nu, h) for e in YOUNGS[::2] for nu in POISSON[::3] for h in HEIGHTS[::3]]
    return [(e, nu, h) for e in YOUNGS for nu in POISSON for h in HEIGHTS]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: a local "
                        "cluster on this machine)")
    parser.add_argument("--workers", type=int, default=2, help="local cluster: worker processes")
    parser.add_argument("--csv", help="write the results here")
    parser.add_argument("--quick", action="store_true", help="a 24-run subset of the 200")
    args = parser.parse_args(argv)
    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        client = Client(args.scheduler)
    else:
        client = Client(LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                     processes=True, dashboard_address=None))
    with client:
        # The workers get this file (they need only it and the femto package), wherever they are.
        client.upload_file(os.path.abspath(__file__))
        params = grid(args.quick)
        began = time.perf_counter()
        results = client.gather(client.map(run, params, pure=True))
        wall = time.perf_counter() - began
        workers = len(client.scheduler_info()["workers"])
    results.sort(key=lambda r: (r["youngs"], r["poisson"], r["height"]))
    cpu = sum(r["seconds"] for r in results)
    print("%d runs on %d workers in %.1f s (%.1f s of stepping: %.2fx)" % (
        len(results), workers, wall, cpu, cpu / wall))
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(results[0]))
            w.writeheader()
            w.writerows(results)
    print("    E (Pa)    nu  height (m)  max squash (mm)  rest height (m)  inverted")
    for r in results:
        print("%10.0f  %4.2f  %10.2f  %15.2f  %15.4f  %8d" % (
            r["youngs"], r["poisson"], r["height"], 1e3 * r["max_squash"], r["rest_height"],
            r["inverted"]))
    return results


if __name__ == "__main__":
    main()
    sys.exit(0)
