"""The Python module against the CLI: the same results, the same one-line errors.

Run by ctest (Python.pytest) with PYTHONPATH at the build tree's python/ and LINKFIT_CLI the
built `linkfit`.
"""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import linkfit

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
CLI = os.environ.get("LINKFIT_CLI", "linkfit")
# Quick tasks of every kind: planar (exact, families, least squares), spatial, timed and untimed
# paths.
FILES = ["four_bar_5_poses.json", "four_bar_4_poses.json", "four_bar_3_poses.json",
         "slider_crank_5_poses.json", "four_bar_12_poses.json", "platform_7_poses.json",
         "path_5_points.json", "path_12_points.json", "bounded_four_bar_12_poses.json"]


def untimed(value):
    """`value` without its timing fields (they differ from run to run)."""
    if isinstance(value, dict):
        return {key: untimed(item) for key, item in value.items()
                if not (key.endswith("_ms") or key.endswith("_seconds"))}
    if isinstance(value, list):
        return [untimed(item) for item in value]
    return value


def cli_solve(path):
    completed = subprocess.run([CLI, "solve", str(path)], capture_output=True, text=True,
                               check=True)
    return json.loads(completed.stdout)


@pytest.mark.parametrize("name", FILES)
def test_solve_gives_the_cli_result(name):
    path = DATA / name
    task = json.loads(path.read_text())
    assert untimed(linkfit.solve(task)) == untimed(cli_solve(path))
    # The task as JSON text gives the same.
    assert untimed(linkfit.solve(path.read_text())) == untimed(cli_solve(path))


def test_bad_input_raises_the_cli_message(tmp_path):
    task = {"problem": "motion", "space": "planar",
            "poses": [{"x": 0, "y": 0, "theta_deg": 0}, {"x": 1, "y": "two", "theta_deg": 0},
                      {"x": 2, "y": 0, "theta_deg": 5}]}
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(task))
    completed = subprocess.run([CLI, "solve", str(path)], capture_output=True, text=True)
    assert completed.returncode == 2
    line = completed.stderr.strip()
    assert line.startswith("linkfit: error: " + str(path) + ": ")
    with pytest.raises(linkfit.InputError) as raised:
        linkfit.solve(task)
    # The same message, the source named "task" instead of the file.
    assert str(raised.value) == "task: " + line[len("linkfit: error: " + str(path) + ": "):]
    assert isinstance(raised.value, ValueError)
    with pytest.raises(linkfit.InputError):
        linkfit.solve("{not json")
    with pytest.raises(linkfit.InputError):
        linkfit.solve(42)


def test_solve_many_keeps_the_order_and_equals_solve():
    tasks = [json.loads((DATA / name).read_text()) for name in FILES] * 3
    one_by_one = [untimed(linkfit.solve(task)) for task in tasks]
    for threads in (0, 1, 2, 5):
        assert [untimed(r) for r in linkfit.solve_many(tasks, threads=threads)] == one_by_one
    assert linkfit.solve_many([]) == []


def test_solve_many_names_the_bad_task():
    good = json.loads((DATA / "four_bar_5_poses.json").read_text())
    bad = {"problem": "motion", "poses": []}
    with pytest.raises(linkfit.InputError, match=r"^tasks\[2\]: "):
        linkfit.solve_many([good, good, bad, good], threads=2)


def test_planar_poses_as_an_array():
    task = json.loads((DATA / "four_bar_5_poses.json").read_text())
    array = np.array([[p["x"], p["y"], p["theta_deg"]] for p in task["poses"]])
    from_array = linkfit.solve({"problem": "motion", "space": "planar", "poses": array})
    assert untimed(from_array) == untimed(linkfit.solve(task))
    assert linkfit.planar_poses(array)[0] == task["poses"][0]
    with pytest.raises(linkfit.InputError):
        linkfit.planar_poses(np.zeros((4, 2)))
