"""linkfit: kinematic synthesis of linkages from Python.

Tasks, designs and results are the task, design and result files of the ``linkfit`` command
(user guide, "Task file" and "Result file"), as Python dicts::

    import linkfit
    task = {"problem": "motion", "poses": [{"x": 0, "y": 0, "theta_deg": 0}, ...]}
    result = linkfit.solve(task)
    first = result["mechanisms"][0]                      # the recommendation
    better = linkfit.refine(task, result, mechanism=1)   # a design refined against the task
    linkfit.plot(result)                                 # with matplotlib, as the SVG

Poses and points may be numpy arrays (:func:`planar_poses`, :func:`spatial_poses`,
:func:`path_points`). Bad input raises :class:`InputError` with the command's one-line message.
``linkfit.__version__`` is the version ``linkfit --version`` prints.
"""

import json
import math

from ._linkfit import (InputError, __version__, analyze_json, export_json,
                       refine_drawn_json, solve_drawn_json, solve_many_json, summary_json)

__all__ = ["InputError", "Result", "solve", "refine", "solve_many", "analyze", "export_dxf",
           "plot", "plot_analysis", "summary",
           "planar_poses", "spatial_poses", "path_points", "__version__"]

InputError.__doc__ = """Bad input: a task, design or argument that linkfit refuses.

A ``ValueError`` whose message is the one line ``linkfit solve`` prints on stderr before it
exits with status 2 (without the ``linkfit: error:`` prefix): the item named as in the CLI
(``task: poses[3].theta_deg: expected a number, got a string``), the task named ``task`` (in
:func:`solve_many`: ``tasks[i]``) and the design ``design``.

Example:
    >>> try:
    ...     linkfit.solve({"problem": "motion", "poses": []})
    ... except linkfit.InputError as error:
    ...     print(error)
    task: poses: 0 poses given, planar motion synthesis needs at least 3
"""
InputError.__module__ = __name__  # linkfit.InputError, as documented


class Result(dict):
    """A result: the dict ``linkfit solve`` writes as JSON, with its drawing.

    Returned by :func:`solve` and :func:`refine`. It equals the CLI's result (``json.loads`` of
    its output) key for key; see the user guide's "Result file" for the fields. Beside the dict
    it carries what :func:`plot` draws.

    Attributes:
        picture_note (str): why there is no :attr:`picture` (empty otherwise); set once
            ``picture`` was asked for.
    """

    def __init__(self, drawn):
        super().__init__(json.loads(drawn.result))
        self._drawn = drawn
        self._picture = None
        self.picture_note = ""

    @property
    def picture(self):
        """The drawing's geometry (what ``linkfit solve --svg`` draws) as a dict, made when first
        asked; None for a spatial platform, which is not drawn, with ``picture_note`` saying
        why."""
        if self._drawn is not None:
            text, self.picture_note = self._drawn.picture()
            self._picture = json.loads(text) if text else None
            self._drawn = None
        return self._picture


def _plain(value):
    """JSON-ready copy of `value`: numpy arrays and scalars become lists and numbers."""
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if hasattr(value, "tolist"):  # numpy array or scalar
        return _plain(value.tolist())
    return value


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def planar_poses(array):
    """Planar poses from rows (x, y, theta_deg), as a task's ``"poses"``.

    Args:
        array: an (n, 3) array-like (numpy array, nested lists) of x, y and the angle θ in
            degrees: the moving frame's origin in the fixed frame and its turn, counter-clockwise.

    Returns:
        list of dict: ``[{"x": x, "y": y, "theta_deg": θ}, ...]``.

    Raises:
        InputError: when ``array`` is not n rows of three numbers.

    Example:
        >>> linkfit.planar_poses([[0, 0, 0], [1, 0.5, 10]])
        [{'x': 0, 'y': 0, 'theta_deg': 0}, {'x': 1, 'y': 0.5, 'theta_deg': 10}]
    """
    rows = _plain(array)
    if not isinstance(rows, list) or any(
            not isinstance(row, list) or len(row) != 3 for row in rows):
        raise InputError("poses: expected an (n, 3) array of x, y, theta_deg")
    return [{"x": x, "y": y, "theta_deg": theta} for x, y, theta in rows]


def spatial_poses(array):
    """Spatial poses from homogeneous transforms, as a task's ``"poses"``.

    Args:
        array: an (n, 4, 4) array-like of transforms ``[[R, d], [0, 0, 0, 1]]``: a body point c
            is at R c + d in the fixed frame.

    Returns:
        list of dict: ``[{"rotation": R, "translation": d}, ...]``. The rotations are checked
        and repaired within the data's precision when the task is solved, as any task's are.

    Raises:
        InputError: when ``array`` is not n 4 × 4 matrices, or a last row is not [0, 0, 0, 1].

    Example:
        >>> linkfit.spatial_poses(numpy.eye(4)[None])[0]["translation"]
        [0.0, 0.0, 0.0]
    """
    transforms = _plain(array)
    if not isinstance(transforms, list) or any(
            not isinstance(m, list) or len(m) != 4
            or any(not isinstance(row, list) or len(row) != 4 for row in m)
            for m in transforms):
        raise InputError("poses: expected an (n, 4, 4) array of homogeneous transforms")
    poses = []
    for i, m in enumerate(transforms):
        if m[3] != [0, 0, 0, 1]:
            raise InputError("poses[%d]: expected the last row of a homogeneous transform, "
                             "[0, 0, 0, 1]" % i)
        poses.append({"rotation": [row[:3] for row in m[:3]],
                      "translation": [row[3] for row in m[:3]]})
    return poses


def path_points(points, input_deg=None):
    """A path task's ``"points"`` from coordinates and, for prescribed timing, input angles.

    Args:
        points: an (n, 2) array-like of x, y, or an (n, 3) array-like of rows x, y, input_deg.
        input_deg: the n input-crank angles in degrees (prescribed timing), or None: free
            timing (unless ``points`` has three columns).

    Returns:
        list of dict: ``[{"x": x, "y": y, "input_deg": ψ}, ...]``, or without ``input_deg``.

    Raises:
        InputError: when the shapes do not fit, or angles are given twice.

    Example:
        >>> linkfit.path_points([[0, 1], [2, 3]], input_deg=[0, 30])
        [{'x': 0, 'y': 1, 'input_deg': 0}, {'x': 2, 'y': 3, 'input_deg': 30}]
    """
    rows = _plain(points)
    if isinstance(rows, list) and rows and all(isinstance(r, list) and len(r) == 3 for r in rows):
        if input_deg is not None:
            raise InputError("points: an (n, 3) array already holds the input angles")
        input_deg = [r[2] for r in rows]
        rows = [r[:2] for r in rows]
    if not isinstance(rows, list) or any(not isinstance(r, list) or len(r) != 2 for r in rows):
        raise InputError("points: expected an (n, 2) array of x, y (or (n, 3) with input_deg)")
    angles = None if input_deg is None else _plain(input_deg)
    if angles is not None and (not isinstance(angles, list) or len(angles) != len(rows)):
        raise InputError("points: expected %d input angles, one per point" % len(rows))
    if angles is None:
        return [{"x": x, "y": y} for x, y in rows]
    return [{"x": x, "y": y, "input_deg": a} for (x, y), a in zip(rows, angles)]


def _rows(value):
    """`value` as nested lists when it is an array-like of numbers, else None."""
    rows = _plain(value)
    if isinstance(rows, list) and rows and isinstance(rows[0], list):
        return rows
    return None


# The most threads solve_many takes (as `linkfit solve --jobs`), and the largest index of a
# design's mechanism.
_MAX_THREADS = 1024
_MAX_INDEX = 2**31 - 1


def _whole_number(value, what, low, high):
    """`value` as an int from `low` to `high`, else InputError naming `what` in one line."""
    if hasattr(value, "item") and not isinstance(value, (list, tuple, dict)):
        value = value.item()  # a numpy integer
    if not isinstance(value, int) or isinstance(value, bool):
        raise InputError("%s: expected a whole number from %d to %d, got %s"
                         % (what, low, high, type(value).__name__))
    if not low <= value <= high:
        shown = str(value) if len(str(value)) <= 40 else str(value)[:40] + "..."
        raise InputError("%s: expected a whole number from %d to %d, got %s"
                         % (what, low, high, shown))
    return value


def _utf8(text, what):
    """`text` (str or bytes) as a str that is valid UTF-8, else InputError naming `what`."""
    try:
        if isinstance(text, bytes):
            return text.decode("utf-8")
        text.encode("utf-8")
        return text
    except UnicodeError as error:
        raise InputError("%s: not UTF-8 text (%s at position %d)"
                         % (what, error.reason, error.start)) from None


def _text(task, what="task"):
    """JSON text of a task or design given as a dict (numpy arrays allowed) or JSON text; `what`
    names it in messages."""
    if isinstance(task, (str, bytes)):
        return _utf8(task, what)
    if not isinstance(task, dict):
        raise InputError(what + ": expected a dict or a JSON string, got " + type(task).__name__)
    try:
        return _dict_text(_plain(task), what)
    except RecursionError:
        raise InputError("%s: nested too deeply" % what) from None


def _dict_text(task, what):
    """JSON text of a task or design dict (numpy arrays already lists)."""
    poses = _rows(task.get("poses"))
    if poses is not None and all(_is_number(v) for v in poses[0]):
        if task.get("space", "planar") == "planar" and len(poses[0]) == 3:
            task["poses"] = planar_poses(poses)
    elif poses is not None and isinstance(poses[0][0], list) and len(poses[0]) == 4:
        task["poses"] = spatial_poses(poses)
    points = _rows(task.get("points"))
    if points is not None and all(_is_number(v) for v in points[0]):
        task["points"] = path_points(points)
    try:
        return json.dumps(task, allow_nan=True)
    except (TypeError, ValueError) as error:
        raise InputError("%s: cannot be written as JSON (%s)" % (what, error)) from None


def solve(task):
    """Solves one task, as ``linkfit solve`` does.

    Args:
        task: the task file's content as a dict, or its JSON text (see the user guide, "Task
            file"). Numpy arrays are taken: planar ``"poses"`` as an (n, 3) array of x, y,
            theta_deg; spatial ``"poses"`` as an (n, 4, 4) array of transforms; path
            ``"points"`` as an (n, 2) array (free timing) or (n, 3) with input_deg.

    Returns:
        Result: the result dict ``linkfit solve`` writes (its mechanisms ranked, the first the
        recommendation), which :func:`plot` draws.

    Raises:
        InputError: bad input, with the CLI's one-line message (the task named ``task``).

    Example:
        >>> result = linkfit.solve(json.load(open("data/four_bar_5_poses.json")))
        >>> result["mechanisms"][0]["type"]
        '4R'
    """
    return Result(solve_drawn_json(_text(task), "task"))


def refine(task, design, mechanism=0):
    """Refines a design against a task, as ``linkfit refine`` does.

    The task's weights, exact items and constraints hold; the refined design replaces the
    given one only when it fits better without a new kinematic defect.

    Args:
        task: a task (dict or JSON text), as for :func:`solve`: planar motion, a path (either
            timing) or spatial motion of seven poses or more.
        design: a result of :func:`solve` (or its file's JSON), or a design written by hand in
            the same form: planar ``{"dyads": [...], "mechanisms": [{"dyads": [input,
            output]}]}``; path ``{"mechanisms": [{"type": "4R", "input_pivot",
            "input_moving", "output_pivot", "output_moving", "coupler_point"}]}``; spatial
            ``{"dyads": [SS, PS or SP dyads], "mechanisms": [{"dyads": [five indices]}]}``.
        mechanism (int): which of the design's mechanisms, a list index: 0 is the first listed
            (the CLI's ``--mechanism`` and the summary's rank count from 1).

    Returns:
        Result: the result, ``"method": "refine"``; the errors before and after are in its
        first note and in the design's ``"before_refinement"``.

    Raises:
        InputError: bad task or design (named ``task`` and ``design``), or ``mechanism`` out
            of range.

    Example:
        >>> better = linkfit.refine(task, linkfit.solve(task), mechanism=2)
    """
    mechanism = _whole_number(mechanism, "mechanism", 0, _MAX_INDEX)
    return Result(refine_drawn_json(_text(task), _text(design, "design"), mechanism))


def solve_many(tasks, threads=0):
    """Solves a list of tasks on several threads, the GIL released.

    Every task is read and validated before any is solved. Ctrl-C (KeyboardInterrupt) stops the
    batch once the tasks being solved finish.

    Args:
        tasks: a list of tasks (dicts or JSON texts), as for :func:`solve`.
        threads (int): how many threads, 0 to 1024 (0: every core); a task a thread.

    Returns:
        list of dict: the results (plain dicts, without drawings), in input order.

    Raises:
        InputError: bad input in any task, naming it ``tasks[i]``, before anything is solved;
            or ``threads`` out of range.

    Example:
        >>> results = linkfit.solve_many([task] * 100, threads=2)
    """
    threads = _whole_number(threads, "threads", 0, _MAX_THREADS)
    texts = [_text(task, "tasks[%d]" % i) for i, task in enumerate(tasks)]
    sources = ["tasks[%d]" % i for i in range(len(texts))]
    return [json.loads(text) for text in solve_many_json(texts, sources, threads)]


def summary(result, title=""):
    """The table ``linkfit show`` prints for a result.

    Per listed mechanism: its rank (from 1), type, Grashof class, link lengths, fit, worst
    transmission angle, defects and violations.

    Args:
        result: a result dict (from :func:`solve`, :func:`refine` or a file) or its JSON text.
        title (str): the name shown in the table's first line (``linkfit show`` shows the file).

    Returns:
        str: the table, to ``print``.

    Raises:
        InputError: when ``result`` is not a result.

    Example:
        >>> print(linkfit.summary(linkfit.solve(task), "my task"))
        my task: motion (planar), exact: 6 listed, 6 without a kinematic defect; L = 17.65
        #  type  grashof ...
    """
    return summary_json(result if isinstance(result, str) else json.dumps(_plain(dict(result))),
                        title)


def analyze(result, mechanism=0, input_speed=1.0, steps=360, load=None, input_range_deg=None,
            masses=None, length_unit=None, gravity=False, task=None):
    """The kinematics of a listed four-bar or six-bar over its input's range, as ``linkfit analyze``.

    Closed form from the loop equations and their derivatives: per step the input angle, every
    link's angle, angular velocity and angular acceleration, the coupler point's position,
    velocity and acceleration, the transmission angle and the mechanical advantage; the dead
    points where a rocker's range ends; with a load, the input torque that holds it (virtual
    work) and its peak. Planar 4Rs and slider-cranks driven by a crank (motion, path and
    function results), six-bars driven by their input (``mechanism`` indexes the result's
    ``six_bars``; the coupler point is the tool frame's origin, the output the task body) and
    spherical four-bars (the coupler's angular velocity and acceleration as [x, y, z] vectors,
    the load a torque on the output).

    Args:
        result: a result (dict from :func:`solve` or :func:`refine`, or read from a file) or its
            JSON text.
        mechanism (int): a list index (0, the first listed; the CLI's ``--mechanism`` counts
            from 1).
        input_speed (float): the input crank's constant angular velocity, rad/s (not 0).
        steps (int): samples over the input's range (a whole turn for a crank, between the dead
            points for a rocker).
        load (dict or None): ``{"coupler_force": [fx, fy], "output_torque": t,
            "slider_force": f}``, each optional.
        input_range_deg (tuple, str or None): the part of the input's range sampled: (from,
            to), the input's angles in degrees (both ends sampled); ``"task"``, its angles from
            the first to the last task pose (a six-bar's result gives them); ``"whole"``, a
            rocking input between its dead points (its rates grow without bound toward them).
            None: a crank's whole turn, a rocking input's task range where known, else whole.
        masses (dict or None): the links' masses in kg, ``{"input": m, "coupler": m,
            "output": m}`` (each optional; ``output`` is the rocker or the slider), for the
            torque that drives them at the constant input speed: the crank and the rocker as
            uniform bars, the coupler as a plate on its pins and the coupler point, the slider
            as a block; a six-bar's ``upper_link``, ``forearm``, ``task_body``, ``first_link``
            and ``second_link``, each uniform over its joints; a spherical four-bar's links as
            thin arcs of its sphere. Needs ``length_unit``.
        length_unit (str or None): the result's length unit, ``"m"``, ``"cm"``, ``"mm"``,
            ``"in"`` or ``"ft"``: torques are then in newtons times it.
        gravity (bool): with masses, their weight too (gravity along -y of the result's
            frame).
        task: the result's task (dict or JSON text), for a four-bar's task range where the
            result alone does not give it (motion and timed path tasks); checked against the
            result.

    Returns:
        dict: the analysis (the JSON ``linkfit analyze`` writes): ``input_deg``, ``links``
        (``input``, ``coupler``, ``output`` or ``slider``: ``angle_deg``, ``angular_velocity``,
        ``angular_acceleration``), ``coupler_point``, ``coupler_point_velocity``,
        ``coupler_point_acceleration``, ``transmission_angle_deg``, ``mechanical_advantage``
        (None where the output stands still), ``dead_points``, with a load or masses
        ``input_torque`` and ``peak_input_torque``, with masses ``inertial_torque`` (and, with
        gravity, ``weight_torque``), the parts of ``input_torque`` they make.

    Raises:
        InputError: for a result without such a mechanism, one not analyzed (yet), or a bad
            argument.

    Example:
        >>> kin = linkfit.analyze(linkfit.solve(task), steps=72, load={"coupler_force": [0, -10]})
        >>> round(max(kin["transmission_angle_deg"]), 1), round(kin["peak_input_torque"])
        (115.4, 375)
    """
    load = dict(load or {})
    unknown = set(load) - {"coupler_force", "output_torque", "slider_force"}
    if unknown:
        raise InputError("load: unknown field " + sorted(unknown)[0] +
                         " (coupler_force, output_torque, slider_force)")
    def number(value, what):
        value = _plain(value)
        if not _is_number(value) or not math.isfinite(value):
            raise InputError("%s: expected a finite number, got %r" % (what, value))
        return float(value)

    force = _plain(load.get("coupler_force", [0.0, 0.0]))
    if not isinstance(force, (list, tuple)) or len(force) != 2:
        raise InputError("load.coupler_force: expected [fx, fy]")
    force = [number(v, "load.coupler_force") for v in force]
    speed = number(input_speed, "input_speed")
    if speed == 0.0:
        raise InputError("input_speed: expected a number other than 0 (rad/s)")
    steps = _whole_number(steps, "steps", 1, 1000000)
    mechanism = _whole_number(mechanism, "mechanism", 0, 10**9)
    range_kind = ""
    if isinstance(input_range_deg, str):
        if input_range_deg not in ("task", "whole"):
            raise InputError("input_range_deg: expected (from, to) in degrees, 'task' or "
                             "'whole', got %r" % (input_range_deg,))
        range_kind, input_range_deg = input_range_deg, None
    if input_range_deg is not None:
        bounds = _plain(input_range_deg)
        if not isinstance(bounds, (list, tuple)) or len(bounds) != 2:
            raise InputError("input_range_deg: expected (from, to) in degrees, 'task' or "
                             "'whole'")
        input_range_deg = tuple(number(v, "input_range_deg") for v in bounds)
    masses = dict(_plain(masses) or {})
    four_bar = ("input", "coupler", "output")
    six_bar = ("upper_link", "forearm", "task_body", "first_link", "second_link")
    links = six_bar if set(masses) & set(six_bar) else four_bar
    unknown = set(masses) - set(links)
    if unknown:
        raise InputError("masses: unknown link " + sorted(unknown)[0] + " (a four-bar's input, "
                         "coupler, output; a six-bar's " + ", ".join(six_bar) + ")")
    link_masses = [number(masses.get(link, 0.0), "masses." + link)
                   for link in links] if masses else []
    if length_unit is not None and not isinstance(length_unit, str):
        raise InputError("length_unit: expected m, cm, mm, in or ft, got %r" % (length_unit,))
    text = result if isinstance(result, str) else json.dumps(_plain(dict(result)))
    task_text = "" if task is None else (task if isinstance(task, str)
                                         else json.dumps(_plain(dict(task))))
    return json.loads(analyze_json(text, mechanism, speed, steps, force[0], force[1],
                                   number(load.get("output_torque", 0.0), "load.output_torque"),
                                   number(load.get("slider_force", 0.0), "load.slider_force"),
                                   input_range_deg, link_masses, length_unit or "",
                                   bool(gravity), range_kind, task_text))


def export_dxf(result, path, mechanism=0, input_deg=None, task=None):
    """Writes a listed four-bar as a DXF drawing, as ``linkfit export --dxf``.

    Each link on its own layer (``GROUND``, ``INPUT``, ``COUPLER``, ``OUTPUT``) with its pivots
    as circles, the coupler body, the coupler curve (``CURVE``), the task's poses or points
    (``TASK``, when ``task`` is given) and aligned dimensions of the link lengths
    (``DIMENSIONS``), in the result's coordinates. 4Rs and slider-cranks driven by a crank.

    Args:
        result: a result (dict or JSON text).
        path: the DXF file to write (str or path-like).
        mechanism (int): a list index (0, the first listed).
        input_deg (float or None): draw the crank at this angle (degrees, fixed frame); None:
            at the first pose.
        task: the result's task (dict or JSON text), to draw its poses or points.

    Returns:
        None: the drawing is in ``path`` (AutoCAD 2000 DXF, readable by CAD programs and
        ezdxf).

    Raises:
        InputError: for a result without such a mechanism, one not drawn (yet), or an angle
            where the four-bar does not assemble.

    Example:
        >>> linkfit.export_dxf(linkfit.solve(task), "four_bar.dxf", task=task)
    """
    _export(result, path, mechanism, input_deg, task, svg=False)


def export_svg(result, path, mechanism=0, input_deg=None, task=None):
    """Writes a listed four-bar as an SVG drawing, as ``linkfit export --svg``.

    The drawing :func:`export_dxf` writes, as SVG: a group per layer (its ``id`` the layer's
    name: ``GROUND``, ``INPUT``, ``COUPLER``, ``OUTPUT``, ``CURVE``, ``TASK``, ``DIMENSIONS``),
    strokes in the layer's colour, in the result's coordinates and units (y up, through a
    flipping group); each dimension as extension lines, a dimension line and the length as text.

    Args:
        result: a result (dict or JSON text).
        path: the SVG file to write (str or path-like).
        mechanism (int): a list index (0, the first listed).
        input_deg (float or None): draw the crank at this angle (degrees, fixed frame); None:
            at the first pose.
        task: the result's task (dict or JSON text), to draw its poses or points.

    Returns:
        None: the drawing is in ``path``.

    Raises:
        InputError: for a result without such a mechanism, one not drawn (yet), or an angle
            where the four-bar does not assemble.

    Example:
        >>> linkfit.export_svg(linkfit.solve(task), "four_bar.svg", task=task)
    """
    _export(result, path, mechanism, input_deg, task, svg=True)


def _export(result, path, mechanism, input_deg, task, svg):
    """Writes the drawing of export_dxf or export_svg."""
    mechanism = _whole_number(mechanism, "mechanism", 0, 10**9)
    if input_deg is not None:
        input_deg = _plain(input_deg)
        if not _is_number(input_deg) or not math.isfinite(input_deg):
            raise InputError("input_deg: expected a finite number, got %r" % (input_deg,))
        input_deg = float(input_deg)
    text = result if isinstance(result, str) else json.dumps(_plain(dict(result)))
    task_text = "" if task is None else (task if isinstance(task, str)
                                         else json.dumps(_plain(dict(task))))
    drawing = export_json(text, mechanism, input_deg, task_text, svg)
    with open(path, "wb") as out:
        out.write(drawing)


def plot_analysis(analysis, fig=None):
    """Plots an analysis of :func:`analyze` with matplotlib, as ``linkfit analyze --svg``.

    Four panels against the input angle: every link's angle, angular velocity and angular
    acceleration (a slider's position, velocity, acceleration), and the input torque holding
    the load (without a load: the transmission angle); the dead points of a rocker marked on
    each by dashed lines.

    Args:
        analysis (dict): from :func:`analyze`.
        fig: a matplotlib Figure to draw on, or None for a new one.

    Returns:
        the matplotlib Figure.

    Raises:
        ValueError: ``analysis`` is not one.
        ImportError: matplotlib is missing.

    Example:
        >>> kin = linkfit.analyze(result, steps=90, load={"coupler_force": [0, -10]})
        >>> linkfit.plot_analysis(kin).savefig("kinematics.png")
    """
    from .drawing import plot_analysis as draw
    return draw(analysis, fig=fig)


def plot(result, ax=None, mechanism=None, task=None):
    """Draws a result with matplotlib, as ``linkfit solve --svg`` draws it.

    Args:
        result: a result of :func:`solve` or :func:`refine`, or one read back from a file
            (drawn from each planar mechanism's ``"linkage"``).
        ax: a matplotlib Axes to draw one panel on, or None for a new figure with a panel per
            listed mechanism (at most 12).
        mechanism (int or None): a list index (0, the first listed; the CLI's ``--mechanism``
            counts from 1): draw that mechanism alone.
        task: for a result read from a file, its task (dict or JSON text): adds its points or
            pose origins.

    Returns:
        ``ax`` when given, else the new matplotlib Figure.

    Raises:
        ValueError: nothing to draw (a spatial platform, a mechanism out of range).
        ImportError: matplotlib is missing.

    Example:
        >>> linkfit.plot(result, mechanism=0).savefig("first.png")

    See :func:`linkfit.drawing.plot` for what is drawn.
    """
    from .drawing import plot as draw
    return draw(result, ax=ax, mechanism=mechanism, task=task)
