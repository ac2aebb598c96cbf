"""linkfit: kinematic synthesis of linkages from Python.

Tasks and results are the task and result files of the ``linkfit`` command (README, "Task
file" and "Result file"), as Python dicts::

    import linkfit
    result = linkfit.solve({"problem": "motion", "space": "planar",
                            "poses": [{"x": 0, "y": 0, "theta_deg": 0}, ...]})
    first = result["mechanisms"][0]

Bad input raises :class:`InputError` with the command's one-line message.
"""

import json

from ._linkfit import InputError, solve_json, solve_many_json

__all__ = ["InputError", "solve", "solve_many", "planar_poses"]


def _plain(value):
    """JSON-ready copy of `value`: numpy arrays and scalars become lists and numbers."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if hasattr(value, "tolist"):  # numpy array or scalar
        return _plain(value.tolist())
    return value


def planar_poses(array):
    """Planar poses from an (n, 3) array-like of rows (x, y, theta_deg), as a task's "poses"."""
    rows = _plain(array)
    if not isinstance(rows, list) or any(
            not isinstance(row, list) or len(row) != 3 for row in rows):
        raise InputError("poses: expected an (n, 3) array of x, y, theta_deg")
    return [{"x": x, "y": y, "theta_deg": theta} for x, y, theta in rows]


def _text(task):
    if isinstance(task, (str, bytes)):
        return task.decode() if isinstance(task, bytes) else task
    if not isinstance(task, dict):
        raise InputError("task: expected a dict or a JSON string, got " + type(task).__name__)
    task = _plain(task)
    poses = task.get("poses")
    if (isinstance(poses, list) and poses and isinstance(poses[0], list)
            and len(poses[0]) == 3 and task.get("space", "planar") == "planar"):
        task["poses"] = planar_poses(poses)
    return json.dumps(task)


def solve(task):
    """Solves one task (a dict, or its JSON text); returns the result dict `linkfit solve`
    writes. Planar "poses" may be given as an (n, 3) array of x, y, theta_deg."""
    return json.loads(solve_json(_text(task), "task"))


def solve_many(tasks, threads=0):
    """Solves a list of tasks on `threads` threads (0: every core), the GIL released; results
    in input order. Bad input in any task raises InputError naming it (tasks[i])."""
    texts = [_text(task) for task in tasks]
    sources = ["tasks[%d]" % i for i in range(len(texts))]
    return [json.loads(text) for text in solve_many_json(texts, sources, threads)]
