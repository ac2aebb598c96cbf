"""The Python module as a careless user calls it (issue 33): every kind of task with an item marked
exact at every effort, invalid UTF-8, out-of-range arguments, a bad task in a batch, Ctrl-C during
a batch. Never a crash, never a traceback of the module's own, and InputError in one line that
names the item.
"""

import json
import os
import pathlib
import signal
import subprocess
import sys
import time

import pytest

import linkfit

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
# The bundled examples of every kind, with their list of items.
KINDS = [("four_bar_3_poses.json", "poses"), ("four_bar_4_poses.json", "poses"),
         ("four_bar_5_poses.json", "poses"), ("four_bar_12_poses.json", "poses"),
         ("platform_7_poses.json", "poses"), ("spherical_four_bar_5_poses.json", "poses"),
         ("path_5_points.json", "points"), ("path_12_points.json", "points"),
         ("path_12_points_untimed.json", "points"), ("function_3_pairs.json", "pairs")]


def exact_variants():
    """Every kind with its first, an interior and its last item marked exact, at every effort."""
    tasks = []
    for name, items in KINDS:
        base = json.loads((DATA / name).read_text())
        count = len(base[items])
        for position in sorted({0, count // 2, count - 1}):
            for effort in ("fast", "balanced", "thorough"):
                task = json.loads(json.dumps(base))
                task[items][position]["exact"] = True
                task["options"] = {"effort": effort}
                tasks.append(task)
    return tasks


def test_exact_items_in_every_kind_at_every_effort():
    # An untimed path with an exact interior point killed the interpreter at balanced (a Ceres
    # CHECK failure in the native module).
    crash = json.loads((DATA / "path_12_points_untimed.json").read_text())
    crash["points"][6]["exact"] = True
    crash["options"] = {"effort": "balanced"}
    assert linkfit.solve(crash)["mechanisms"]
    tasks = exact_variants()
    results = linkfit.solve_many(tasks, threads=2)
    assert len(results) == len(tasks)
    for task, result in zip(tasks, results):
        assert result["problem"] == task["problem"]


def test_invalid_utf8_is_an_input_error():
    with pytest.raises(linkfit.InputError) as raised:
        linkfit.solve(b'{"problem": "motion", "poses": [\xff\xfe]}')
    assert str(raised.value).startswith("task: not UTF-8 text (invalid start byte at position 32)")
    with pytest.raises(linkfit.InputError, match=r"^task: not UTF-8 text"):
        linkfit.solve('{"problem": "\udcff"}')
    with pytest.raises(linkfit.InputError, match=r"^tasks\[1\]: not UTF-8 text"):
        linkfit.solve_many([(DATA / "four_bar_5_poses.json").read_text(), b"\xc3\x28"])


@pytest.mark.parametrize("threads", [-1, 10**30, 1.5, "2", True])
def test_threads_out_of_range(threads):
    with pytest.raises(linkfit.InputError) as raised:
        linkfit.solve_many([], threads=threads)
    message = str(raised.value)
    assert message.startswith("threads: expected a whole number from 0 to 1024, got ")
    assert "\n" not in message and len(message) < 120


@pytest.mark.parametrize("mechanism", [-1, 2**31, 10**30, 2.0])
def test_mechanism_out_of_range(mechanism):
    task = json.loads((DATA / "four_bar_12_poses.json").read_text())
    design = {"dyads": [{"type": "RR", "fixed": [0, 0], "moving": [1, 0], "radius": 1},
                        {"type": "RR", "fixed": [3, 0], "moving": [2, 1], "radius": 2}],
              "mechanisms": [{"dyads": [0, 1]}]}
    with pytest.raises(linkfit.InputError) as raised:
        linkfit.refine(task, design, mechanism=mechanism)
    message = str(raised.value)
    assert message.startswith("mechanism: expected a whole number from 0 to 2147483647, got ")
    assert "\n" not in message and len(message) < 120


def test_solve_many_names_every_bad_task_by_its_index():
    good = json.loads((DATA / "four_bar_5_poses.json").read_text())
    with pytest.raises(linkfit.InputError, match=r"^tasks\[3\]: expected a dict or a JSON "
                                                 r"string, got int$"):
        linkfit.solve_many([good, good, good, 42])
    with pytest.raises(linkfit.InputError, match=r"^tasks\[2\]: cannot be written as JSON"):
        linkfit.solve_many([good, good, {"problem": {1, 2}}])
    deep = {"poses": []}
    for _ in range(5000):
        deep = {"poses": [deep]}
    with pytest.raises(linkfit.InputError, match=r"^tasks\[0\]: nested too deeply$"):
        linkfit.solve_many([deep])


def test_a_bad_last_task_is_reported_before_any_is_solved():
    slow = json.loads((DATA / "path_12_points_untimed.json").read_text())
    slow["options"] = {"effort": "thorough"}
    bad = json.loads((DATA / "four_bar_5_poses.json").read_text())
    del bad["poses"][3]["y"]
    start = time.monotonic()
    with pytest.raises(linkfit.InputError, match=r"^tasks\[20\]: poses\[3\]\.y: missing field$"):
        linkfit.solve_many([slow] * 20 + [bad], threads=1)
    # Twenty thorough untimed paths take a minute; reading them takes milliseconds.
    assert time.monotonic() - start < 2.0


def test_ctrl_c_stops_a_batch():
    script = (
        "import json, sys, linkfit\n"
        "task = json.loads(open(sys.argv[1]).read())\n"
        "task['options'] = {'effort': 'thorough'}\n"
        "print('started', flush=True)\n"
        "linkfit.solve_many([task] * 40, threads=1)\n"
        "print('finished', flush=True)\n")
    env = dict(os.environ)
    process = subprocess.Popen([sys.executable, "-c", script,
                                str(DATA / "path_12_points_untimed.json")],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    assert process.stdout.readline().strip() == "started"
    time.sleep(1.0)
    start = time.monotonic()
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=60)
    stopped = time.monotonic() - start
    assert "finished" not in out
    assert "KeyboardInterrupt" in err
    # The task being solved finishes (a few seconds at most); the other 39 are not started.
    assert stopped < 15.0
