"""The Dask sweep on a cluster of its own: a dask-scheduler and two dask-worker processes
talking TCP over the loopback, as on several machines; the results are the physics' and the
same bits as a run in this process (each run is a pure function of its scene)."""
import json
import os
import subprocess
import sys
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "sweep"))
import drop_sweep  # noqa: E402


@pytest.fixture
def cluster(tmp_path):
    """A scheduler on 127.0.0.1 (a free port, written to a scheduler file) and two workers of
    one thread each, all separate processes of this Python (which has femto)."""
    pytest.importorskip("distributed")
    address_file = tmp_path / "scheduler.json"
    common = ["--no-dashboard"]
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler",
                               "--host", "127.0.0.1", "--port", "0",
                               "--scheduler-file", str(address_file)] + common,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)]
    try:
        for _ in range(300):
            if address_file.exists() and address_file.stat().st_size > 0:
                break
            time.sleep(0.1)
        address = json.loads(address_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        for k in range(2):
            procs.append(subprocess.Popen(
                [sys.executable, "-m", "distributed.cli.dask_worker", address,
                 "--nworkers", "1", "--nthreads", "1", "--name", "worker-%d" % k,
                 "--local-directory", str(tmp_path / ("w%d" % k))] + common,
                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE))
        from dask.distributed import Client
        with Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=60)
        yield address
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()


def test_the_sweep_runs_on_a_scheduler_and_two_workers(cluster, tmp_path):
    table = tmp_path / "sweep.csv"
    results = drop_sweep.main(["--scheduler", cluster, "--quick", "--csv", str(table)])
    assert len(results) == 24 and table.read_text().count("\n") == 25
    by = {(r["youngs"], r["poisson"], r["height"]): r for r in results}
    for (e, nu, h), r in by.items():
        assert r["inverted"] == 0 and r["end_speed"] < 0.05
        # Dropped from higher, it squashes more; stiffer, less.
        higher = [k for k in by if k[:2] == (e, nu) and k[2] > h]
        assert all(by[k]["max_squash"] > r["max_squash"] for k in higher)
        stiffer = [k for k in by if k[0] > e and k[1:] == (nu, h)]
        assert all(by[k]["max_squash"] < r["max_squash"] for k in stiffer)
    # At rest, nu = 0: the column's self-weight shortening rho g L^2 / (2 E), within 25% on
    # this 3 x 3 x 3 mesh.
    for (e, nu, h), r in by.items():
        if nu == 0.0:
            expected = drop_sweep.DENSITY * 9.8 * drop_sweep.SIZE ** 2 / (2 * e)
            assert abs((drop_sweep.SIZE - r["rest_height"]) - expected) < 0.25 * expected
    # The cluster's numbers are this process's: the same scene, the same bits.
    for params in [(2e4, 0.0, 0.25), (5e5, 0.45, 2.5)]:
        here = drop_sweep.run(params)
        there = by[params]
        assert all(here[k] == there[k] for k in here if k != "seconds")
