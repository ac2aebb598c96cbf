"""linkfit.dask on a LocalCluster of two worker processes: 1,000 tasks, the results equal
solve_many's (timing fields aside)."""

import json
import pathlib
import random
import time

import pytest

distributed = pytest.importorskip("distributed")

import linkfit
import linkfit.dask

from test_linkfit import untimed

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"


def five_pose_tasks(count, seed=7):
    """`count` five-pose tasks: the bundled four-bar's poses moved and turned at random."""
    base = json.loads((DATA / "four_bar_5_poses.json").read_text())
    rng = random.Random(seed)
    tasks = []
    for _ in range(count):
        dx, dy, turn = rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-10, 10)
        task = dict(base)
        task["poses"] = [{"x": p["x"] + dx, "y": p["y"] + dy, "theta_deg": p["theta_deg"] + turn}
                         for p in base["poses"]]
        tasks.append(task)
    return tasks


def test_solve_bag_on_a_local_cluster_equals_solve_many():
    tasks = five_pose_tasks(1000)
    expected = [untimed(result) for result in linkfit.solve_many(tasks)]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        start = time.perf_counter()
        results = linkfit.dask.solve_bag(tasks, npartitions=20, threads=1).compute()
        seconds = time.perf_counter() - start
        assert len(client.scheduler_info()["workers"]) == 2
    assert [untimed(result) for result in results] == expected
    print("1000 five-pose tasks on 2 worker processes: %.2f s, %.0f tasks/s"
          % (seconds, len(tasks) / seconds))
