"""Drawing linkfit results with matplotlib (an optional dependency): ``linkfit.plot``.

The drawing is the content of ``linkfit solve --svg``: the task (poses as small frames, path
points as crosses, for four poses the Burmester curves) and each listed mechanism in its own panel,
at the first pose, with its coupler curve, pivots, links, sliders and its defects (a six-bar by
its joints: its links as bars, its ternary links as plates). A spherical
result's four-bars are drawn each on an orthographic view of the unit sphere about the centre, as
the SVG draws them. The geometry comes from the solver (apps/picture.h PictureToJson and
SphericalPictureToJson), attached to the results of :func:`linkfit.solve` and
:func:`linkfit.refine`.
"""

import math
import sys

# The SVG's colours (apps/picture.cc).
TASK_X = "#d62728"
TASK_Y = "#2ca02c"
COUPLER_CURVE = "#1f77b4"
PIVOT_BOX = "#2e7d32"  # the constraints' pivot boxes
CENTER_CURVE = "#9467bd"
CIRCLE_CURVE = "#ff7f0e"
PATH_POINT = "#c51b8a"
LINK = "#333333"
COUPLER_FILL = "#bcbd22"
COUPLER_STROKE = "#6b6b12"
BLOCK_FILL = "#d9d9d9"
GROUND = "#333333"
# The spherical SVG's (apps/picture.cc DrawSphericalPanel).
SPHERE_FILL = "#f3f6fa"
SPHERE_EDGE = "#9aa7b5"
SIGMA_AXES = "#9a9a9a"
SPHERICAL_GROUND = "#777777"
NO_FOUR_BAR = "task: no four-bar listed"


def _pyplot():
    try:
        import matplotlib.pyplot as pyplot
    except ImportError as error:  # pragma: no cover - depends on the machine
        raise ImportError("linkfit's drawings (plot, plot_analysis) need matplotlib in this "
                          "Python (%s): Debian's python3-matplotlib serves /usr/bin/python3"
                          % sys.executable) from error
    return pyplot


def _to_fixed(pose, point):
    """A point of E at coupler pose (x, y, theta), in Sigma."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    return (x + c * point[0] - s * point[1], y + s * point[0] + c * point[1])


def _direction_to_fixed(pose, direction):
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return (c * direction[0] - s * direction[1], s * direction[0] + c * direction[1])


def _hull(points):
    """Convex hull (monotone chain), counter-clockwise."""
    points = sorted(set(points))
    if len(points) < 3:
        return points

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in points:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(points):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def _draw_task(ax, picture, length):
    arrow = 0.25 * length
    for i, (x, y, theta) in enumerate(picture["task_poses"]):
        for colour, angle in ((TASK_X, theta), (TASK_Y, theta + math.pi / 2)):
            ax.annotate("", xy=(x + arrow * math.cos(angle), y + arrow * math.sin(angle)),
                        xytext=(x, y), arrowprops=dict(arrowstyle="->", color=colour, lw=1.5))
        ax.plot([x], [y], "o", color="#222222", markersize=3)
        ax.annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(-9, -11),
                    fontsize=8, fontweight="bold", color="#222222")
    for i, (x, y) in enumerate(picture["path_points"]):
        ax.plot([x], [y], "x", color=PATH_POINT, markersize=7, mew=2)
        ax.annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(5, -11), fontsize=8,
                    fontweight="bold", color=PATH_POINT)


def _line_through(ax, point, direction, view, **style):
    """A line through `point` along `direction`, across the view."""
    x0, y0, x1, y1 = view
    span = 2.0 * math.hypot(x1 - x0, y1 - y0) + math.hypot(point[0] - 0.5 * (x0 + x1),
                                                          point[1] - 0.5 * (y0 + y1))
    ax.plot([point[0] - span * direction[0], point[0] + span * direction[0]],
            [point[1] - span * direction[1], point[1] + span * direction[1]], **style)


def _draw_jointed(ax, mechanism):
    """A linkage drawn by its joints (six-bars): each binary link a bar, each body of three or
    more joints a plate (the task body with E's origin, in the coupler's colours), the ground's
    joints as pivots."""
    joints = mechanism["joints"]
    places = joints["at_first_pose"]
    pose = mechanism["first_pose"]
    origin = (pose[0], pose[1])
    for index, body in enumerate(joints["bodies"]):
        if index == 0:
            continue
        points = [tuple(places[j]) for j in body if places[j] is not None]
        task = index == joints["task_body"]
        if task:
            points.append(origin)
        hull = _hull(points)
        if len(hull) >= 3:
            ax.fill([p[0] for p in hull], [p[1] for p in hull],
                    color=COUPLER_FILL if task else "#9aa7b4", alpha=0.35, zorder=2)
            ax.plot([p[0] for p in hull + hull[:1]], [p[1] for p in hull + hull[:1]],
                    color=COUPLER_STROKE if task else LINK, lw=1.5, zorder=2)
        elif len(hull) == 2:
            ax.plot([hull[0][0], hull[1][0]], [hull[0][1], hull[1][1]],
                    color=COUPLER_STROKE if task else LINK, lw=3 if task else 2.5,
                    solid_capstyle="round", zorder=3)
    ground = set(joints["bodies"][0]) if joints["bodies"] else set()
    for j, place in enumerate(places):
        if place is None:
            continue
        if j in ground:
            ax.plot([place[0]], [place[1]], "^", color=GROUND, markersize=9, zorder=5)
        ax.plot([place[0]], [place[1]], "o", color="white", mec=LINK, markersize=6, zorder=6)
        ax.annotate(joints["names"][j], place, textcoords="offset points", xytext=(6, 5),
                    fontsize=8, color=LINK)
    ax.plot([origin[0]], [origin[1]], "o", color=COUPLER_CURVE, markersize=3, zorder=6)


def _draw_mechanism(ax, mechanism, length):
    if "joints" in mechanism:
        _draw_jointed(ax, mechanism)
        return
    pose = mechanism["first_pose"]
    view = mechanism["view"]
    dyads = (mechanism["input"], mechanism["output"])
    origin = (pose[0], pose[1])
    moving = [_to_fixed(pose, d["moving"]) if d["type"] != "RP" and d["moving"] else None
              for d in dyads]
    # Slider lines fixed in Sigma (PR), under everything else.
    for dyad in dyads:
        if dyad["type"] == "PR":
            _line_through(ax, dyad["line_point"], dyad["line_direction"], view, color="#555555",
                          lw=1.2, ls=(0, (6, 3)), zorder=1)
    # Cranks and rockers (RR), the coupler body, and rods fixed in E (RP).
    for dyad, pin in zip(dyads, moving):
        if dyad["type"] == "RR" and pin is not None:
            ax.plot([dyad["fixed"][0], pin[0]], [dyad["fixed"][1], pin[1]], color=LINK, lw=2.5,
                    solid_capstyle="round", zorder=3)
    body = [origin] + [pin for pin in moving if pin is not None]
    rods = []
    for dyad in dyads:
        if dyad["type"] != "RP":
            continue
        direction = _direction_to_fixed(pose, dyad["line_direction"])
        point = _to_fixed(pose, dyad["line_point"])
        # Measured from the foot of E's origin on the rod.
        t_origin = (origin[0] - point[0]) * direction[0] + (origin[1] - point[1]) * direction[1]
        point = (point[0] + t_origin * direction[0], point[1] + t_origin * direction[1])
        ts = [0.0]
        for p in list(body) + ([tuple(dyad["fixed"])] if dyad["fixed"] else []):
            t = (p[0] - point[0]) * direction[0] + (p[1] - point[1]) * direction[1]
            ts.append(t)
            body.append((point[0] + t * direction[0], point[1] + t * direction[1]))
        lo, hi = min(ts) - 0.6 * length, max(ts) + 0.6 * length
        rods.append((dyad, point, direction, lo, hi))
    hull = _hull([tuple(p) for p in body])
    if len(hull) >= 3:
        ax.fill([p[0] for p in hull], [p[1] for p in hull], color=COUPLER_FILL, alpha=0.35,
                zorder=2)
        ax.plot([p[0] for p in hull + hull[:1]], [p[1] for p in hull + hull[:1]],
                color=COUPLER_STROKE, lw=1.5, zorder=2)
    elif len(hull) == 2:
        ax.plot([hull[0][0], hull[1][0]], [hull[0][1], hull[1][1]], color=COUPLER_STROKE, lw=3,
                zorder=2)
    for _, point, direction, lo, hi in rods:
        ax.plot([point[0] + lo * direction[0], point[0] + hi * direction[0]],
                [point[1] + lo * direction[1], point[1] + hi * direction[1]],
                color=COUPLER_STROKE, lw=2.5, solid_capstyle="round", zorder=3)
    # Slider blocks: PR at its moving pivot, RP at its fixed pivot.
    for dyad, pin in zip(dyads, moving):
        if dyad["type"] == "PR" and pin is not None:
            ax.plot([pin[0]], [pin[1]], "s", color=BLOCK_FILL, mec=LINK, markersize=11,
                    zorder=4)
        if dyad["type"] == "RP" and dyad["fixed"]:
            ax.plot([dyad["fixed"][0]], [dyad["fixed"][1]], "s", color=BLOCK_FILL, mec=LINK,
                    markersize=11, zorder=4)
    names = ("A", "B")
    for name, dyad, pin in zip(names, dyads, moving):
        if pin is not None:
            ax.plot([pin[0]], [pin[1]], "o", color="white", mec=LINK, markersize=7, zorder=5)
            ax.annotate(name, pin, textcoords="offset points", xytext=(6, 5), fontsize=8,
                        color=LINK)
        if dyad["type"] != "PR" and dyad["fixed"]:
            ax.plot([dyad["fixed"][0]], [dyad["fixed"][1]], "^", color=GROUND, markersize=9,
                    zorder=5)
            ax.annotate(name + "0", dyad["fixed"], textcoords="offset points", xytext=(7, -4),
                        fontsize=8, color=LINK)
    ax.plot([origin[0]], [origin[1]], "o", color=COUPLER_CURVE, markersize=3, zorder=5)


def _box_corners(box, pose=None):
    """A pivot box [x0, y0, x1, y1] as its four corners, mapped by pose [x, y, theta]."""
    corners = [(box[0], box[1]), (box[2], box[1]), (box[2], box[3]), (box[0], box[3])]
    if pose is None:
        return corners
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return [(pose[0] + c * x - s * y, pose[1] + s * x + c * y) for x, y in corners]


def _draw_pivot_boxes(ax, picture, mechanism):
    """The constraints' pivot boxes: the fixed pivots' in Sigma, the moving pivots' where E is."""
    import matplotlib.patches as patches
    boxes = []
    if picture.get("fixed_pivots_box"):
        boxes.append((_box_corners(picture["fixed_pivots_box"]), (0, (8, 4))))
    if picture.get("moving_pivots_box") and mechanism is not None:
        boxes.append((_box_corners(picture["moving_pivots_box"], mechanism["first_pose"]),
                      (0, (3, 3))))
    for corners, dashes in boxes:
        ax.add_patch(patches.Polygon(corners, closed=True, facecolor=PIVOT_BOX, alpha=0.06,
                                     zorder=0))
        ax.add_patch(patches.Polygon(corners, closed=True, fill=False, edgecolor=PIVOT_BOX,
                                     lw=1.2, ls=dashes, zorder=1))


def _draw_panel(ax, picture, mechanism):
    length = picture["length"]
    view = mechanism["view"] if mechanism is not None else picture["view"]
    _draw_pivot_boxes(ax, picture, mechanism)
    for curve in picture["center_point_curves"]:
        if curve:
            ax.plot([p[0] for p in curve], [p[1] for p in curve], color=CENTER_CURVE, lw=1.2)
    for curve in picture["circle_point_curves"]:
        if curve:
            ax.plot([p[0] for p in curve], [p[1] for p in curve], color=CIRCLE_CURVE, lw=1.2,
                    ls=(0, (6, 3)))
    if mechanism is not None and mechanism["coupler_curve"]:
        curve = mechanism["coupler_curve"]
        ax.plot([p[0] for p in curve], [p[1] for p in curve], color=COUPLER_CURVE, lw=1.6,
                zorder=2)
    _draw_task(ax, picture, length)
    if mechanism is not None:
        _draw_mechanism(ax, mechanism, length)
        ax.set_title(mechanism["title"], fontsize=9, loc="left")
        ax.text(0.01, 0.01, "\n".join(mechanism["labels"]), transform=ax.transAxes, fontsize=7,
                va="bottom", ha="left", color="#444444",
                bbox=dict(facecolor="white", edgecolor="none", alpha=0.8, pad=1.5))
    ax.set_xlim(view[0], view[2])
    ax.set_ylim(view[1], view[3])
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, color="#ececec", lw=0.8)
    ax.set_axisbelow(True)
    ax.tick_params(labelsize=7)


def _draw_runs(ax, runs, colour, width, zorder):
    """A polyline of the sphere as projected: solid on the near hemisphere, dashed on the far."""
    for run in runs:
        xs, ys = [p[0] for p in run["points"]], [p[1] for p in run["points"]]
        if run["front"]:
            ax.plot(xs, ys, color=colour, lw=0.8 * width, solid_capstyle="round", zorder=zorder)
        else:
            ax.plot(xs, ys, color=colour, lw=0.48 * width, ls=(0, (3, 3)), alpha=0.6,
                    zorder=zorder)


def _draw_spherical_panel(ax, picture, mechanism):
    """One spherical four-bar on its view of the unit sphere (coordinates x . right, x . up)."""
    import matplotlib.patches as patches
    ax.add_patch(patches.Circle((0.0, 0.0), 1.0, facecolor=SPHERE_FILL, edgecolor=SPHERE_EDGE,
                                lw=1, zorder=0))
    if mechanism is None:
        ax.set_title(NO_FOUR_BAR, fontsize=9, loc="left")
    else:
        for name, (x, y) in zip("xyz", mechanism["sigma_axes"]):
            ax.plot([0.0, 0.25 * x], [0.0, 0.25 * y], color=SIGMA_AXES, lw=1, zorder=1)
            ax.text(0.3 * x, 0.3 * y, name, fontsize=8, color=SIGMA_AXES, zorder=1)
        for arc in mechanism["task_couplers"]:
            _draw_runs(ax, arc, TASK_X, 1.2, 2)
        _draw_runs(ax, mechanism["input_pin_path"], COUPLER_CURVE, 1.0, 2)
        _draw_runs(ax, mechanism["output_pin_path"], CENTER_CURVE, 1.0, 2)
        _draw_runs(ax, mechanism["ground"], SPHERICAL_GROUND, 2.0, 3)
        _draw_runs(ax, mechanism["input_link"], LINK, 3.0, 3)
        _draw_runs(ax, mechanism["output_link"], LINK, 3.0, 3)
        _draw_runs(ax, mechanism["coupler"], COUPLER_STROKE, 4.0, 3)
        for pin in mechanism["pins"]:
            ax.plot([pin["at"][0]], [pin["at"][1]], "o", color="white", mec=LINK, markersize=7,
                    alpha=1.0 if pin["front"] else 0.5, zorder=5)
        for name, pivot in zip(("input", "output"), mechanism["fixed_pivots"]):
            ax.plot([pivot["at"][0]], [pivot["at"][1]], "^", color=GROUND, markersize=9,
                    alpha=1.0 if pivot["front"] else 0.5, zorder=5)
            ax.annotate(name, pivot["at"], textcoords="offset points", xytext=(7, 4),
                        fontsize=8, color=LINK)
        ax.set_title(mechanism["title"], fontsize=9, loc="left")
        ax.text(0.01, 0.01, "\n".join(mechanism["labels"]), transform=ax.transAxes, fontsize=7,
                va="bottom", ha="left", color="#444444",
                bbox=dict(facecolor="white", edgecolor="none", alpha=0.8, pad=1.5))
    ax.set_xlim(-1.1, 1.1)
    ax.set_ylim(-1.1, 1.1)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_axis_off()


def _draw_linkage_panel(ax, number, mechanism, task_points):
    """One panel of a result read back from a file: the mechanism's "linkage" (its joints in
    Sigma at the first task pose, pose, point or pair), the task's points or pose origins when
    given, in the result's own coordinates."""
    joints = mechanism.get("linkage", {}).get("joints", {})
    if task_points:
        ax.plot([p[0] for p in task_points], [p[1] for p in task_points], "x", color=PATH_POINT,
                markersize=6, zorder=3)
    pins = [joints.get("input_pin"), joints.get("output_pin")]
    body = [p for p in pins + [joints.get("coupler_point")] if p is not None]
    if len(body) >= 2:
        ax.fill([p[0] for p in body], [p[1] for p in body], color=COUPLER_FILL, alpha=0.5,
                edgecolor=COUPLER_STROKE, zorder=2)
    for side in ("input", "output"):
        pivot, pin = joints.get(side + "_pivot"), joints.get(side + "_pin")
        if pivot is not None and pin is not None:
            ax.plot([pivot[0], pin[0]], [pivot[1], pin[1]], "-", color=LINK, linewidth=2.5,
                    zorder=4)
        if pivot is not None:
            ax.plot([pivot[0]], [pivot[1]], "^", color=GROUND, markersize=9, zorder=5)
            ax.annotate(side, pivot, textcoords="offset points", xytext=(7, 4), fontsize=8,
                        color=LINK)
        if pin is not None:
            ax.plot([pin[0]], [pin[1]], "o", color=LINK, markersize=5, zorder=5)
        line = joints.get(side + "_slider_line")
        if line is not None:
            angle = math.radians(line["angle_deg"])
            anchor = pin if line.get("on") == "ground" and pin is not None else pivot
            anchor = anchor if anchor is not None else line["point"]
            reach = max(1e-9, max(abs(v) for p in body + [anchor] for v in p)) * 0.3
            dx, dy = reach * math.cos(angle), reach * math.sin(angle)
            ax.plot([anchor[0] - dx, anchor[0] + dx], [anchor[1] - dy, anchor[1] + dy], "--",
                    color=GROUND, linewidth=1, zorder=3)
    point = joints.get("coupler_point")
    if point is not None:
        ax.plot([point[0]], [point[1]], "s", color=COUPLER_CURVE, markersize=5, zorder=6)
    labels = [mechanism.get("type", "")]
    if mechanism.get("grashof"):
        labels.append(mechanism["grashof"])
    labels.append(", ".join(mechanism.get("defects") or []) or "no defects")
    ax.set_title("%d. %s" % (number, " · ".join(labels)), fontsize=9, loc="left")
    ax.set_aspect("equal", adjustable="datalim")


def _task_points(task):
    """The points (path) or pose origins (planar motion) of a task dict, for the overlay."""
    if not task:
        return []
    if isinstance(task, str):
        import json
        task = json.loads(task)
    items = task.get("points") or task.get("poses") or []
    return [(item["x"], item["y"]) for item in items
            if isinstance(item, dict) and "x" in item and "y" in item]


def plot(result, ax=None, mechanism=None, task=None):
    """Draws a result of :func:`linkfit.solve` or :func:`linkfit.refine` with matplotlib.

    With ``ax`` (a matplotlib Axes), draws one panel on it: the task and mechanism number
    ``mechanism`` of the result (0, the first and best ranked, by default); returns ``ax``.
    Without, makes a figure with one panel per listed mechanism (at most 12, as the SVG), or
    ``mechanism`` alone when given; returns the figure.

    A spherical result's four-bars are drawn as the SVG draws them, each on an orthographic view
    of the unit sphere about the centre (a panel's coordinates are those of the sphere's points
    projected on its view, the picture's "right" and "up"). Spatial platforms are not drawn (as
    ``linkfit solve --svg``): ValueError says so.

    A result read back from a file (a plain dict, e.g. ``json.load``) is drawn from each planar
    mechanism's ``"linkage"``: its joints at the first task pose, point or pair, without the
    coupler curve; ``task`` (the task dict) adds its points or pose origins.
    """
    picture = getattr(result, "picture", None)  # made here, on first use
    if picture is None and not isinstance(result, dict):
        raise ValueError("linkfit.plot: expected a result (a dict), got %s" % type(result).__name__)
    if picture is None:
        reason = getattr(result, "picture_note", "")
        listed = result.get("mechanisms", [])
        drawable = [(k, m) for k, m in enumerate(listed) if isinstance(m, dict) and "linkage" in m]
        if reason or not drawable:
            raise ValueError("linkfit.plot: " + (reason or "this result has no planar mechanism "
                                                 "with a \"linkage\" to draw"))
        if mechanism is not None and not 0 <= mechanism < len(listed):
            raise ValueError("linkfit.plot: mechanism %d: the result lists %d mechanisms"
                             % (mechanism, len(listed)))
        if mechanism is not None:
            drawable = [(k, m) for k, m in drawable if k == mechanism]
            if not drawable:
                raise ValueError("linkfit.plot: mechanism %d has no \"linkage\" to draw"
                                 % mechanism)
        points = _task_points(task)
        if ax is not None:
            _draw_linkage_panel(ax, drawable[0][0] + 1, drawable[0][1], points)
            return ax
        pyplot = _pyplot()
        drawable = drawable[:12]
        columns = min(3, len(drawable))
        rows = (len(drawable) + columns - 1) // columns
        figure, axes = pyplot.subplots(rows, columns, figsize=(4.3 * columns, 4.3 * rows),
                                       squeeze=False)
        for k, axis in enumerate(axes.flat):
            if k < len(drawable):
                _draw_linkage_panel(axis, drawable[k][0] + 1, drawable[k][1], points)
            else:
                axis.set_visible(False)
        figure.tight_layout()
        return figure
    spherical = picture.get("kind") == "spherical"
    draw_panel = _draw_spherical_panel if spherical else _draw_panel
    mechanisms = picture["mechanisms"]
    if mechanism is not None and not 0 <= mechanism < len(mechanisms):
        raise ValueError("linkfit.plot: mechanism %d: the drawing lists %d mechanisms"
                         % (mechanism, len(mechanisms)))
    if ax is not None:
        index = 0 if mechanism is None else mechanism
        draw_panel(ax, picture, mechanisms[index] if mechanisms else None)
        return ax
    pyplot = _pyplot()
    chosen = mechanisms if mechanism is None else [mechanisms[mechanism]]
    panels = max(1, len(chosen))
    columns = min(3, panels)
    rows = (panels + columns - 1) // columns
    figure, axes = pyplot.subplots(rows, columns, figsize=(4.3 * columns, 4.3 * rows),
                                   squeeze=False)
    for k, axis in enumerate(axes.flat):
        if k < panels:
            draw_panel(axis, picture, chosen[k] if chosen else None)
        else:
            axis.set_visible(False)
    heading = picture["title"]
    if spherical:
        heading = (heading + ": " if heading else "") + picture["heading"]
    if heading:
        figure.suptitle(heading)
    figure.tight_layout()
    return figure


# The analysis plot's series: (panel title, unit, key of a link's arrays or None for a top-level
# array), one panel each.
_ANALYSIS_PANELS = [("link angles", "deg", "angle_deg"),
                    ("angular velocities", "rad/s", "angular_velocity"),
                    ("angular accelerations", "rad/s²", "angular_acceleration")]
_LINK_COLOURS = {"input": "#d62728", "coupler": "#1f77b4", "output": "#2ca02c",
                 "slider": "#2ca02c", "upper_link": "#d62728", "forearm": "#1f77b4",
                 "task_body": "#2ca02c", "first_link": "#ff7f0e", "second_link": "#9467bd"}
DEAD_POINT = "#7f7f7f"


def plot_analysis(analysis, fig=None):
    """Plots an analysis of :func:`linkfit.analyze` with matplotlib, as ``linkfit analyze --svg``.

    Four panels against the input angle: each link's angle (a slider's position), angular
    velocity (its velocity) and angular acceleration (its acceleration), and the input torque
    that holds the load (with a load; else the transmission angle). The input's dead points (a
    rocker's range ends) are marked by dashed vertical lines on every panel. Returns the figure.
    """
    pyplot = _pyplot()
    if not isinstance(analysis, dict) or "input_deg" not in analysis or "links" not in analysis:
        raise ValueError("linkfit.plot_analysis: expected an analysis of linkfit.analyze")
    if fig is None:
        fig = pyplot.figure(figsize=(8, 9))
    axes = fig.subplots(4, 1, sharex=True)
    x = analysis["input_deg"]
    for ax, (title, unit, key) in zip(axes, _ANALYSIS_PANELS):
        for name, link in analysis["links"].items():
            values = link.get(key)
            label = name
            if values is None:  # a slider: its position, velocity, acceleration
                values = link[{"angle_deg": "position", "angular_velocity": "velocity",
                               "angular_acceleration": "acceleration"}[key]]
                label = name + " (length units)"
            if values and isinstance(values[0], list):  # a spherical coupler's vectors
                values = [math.sqrt(sum(c * c for c in v)) for v in values]
                label = name + " (magnitude)"
            ax.plot(x, values, color=_LINK_COLOURS.get(name, LINK), label=label, linewidth=1.2)
        ax.set_title(title, fontsize=9, loc="left")
        ax.set_ylabel(unit)
        ax.legend(fontsize=7, loc="upper right")
    last = axes[3]
    force = "input_force" in analysis  # a slider drives it
    if "input_torque" in analysis or force:
        key = "input_force" if force else "input_torque"
        last.plot(x, analysis[key], color=LINK, linewidth=1.2)
        last.set_title("input %s holding the load (peak %.4g)"
                       % ("force" if force else "torque", analysis["peak_" + key]),
                       fontsize=9, loc="left")
        last.set_ylabel("force" if force else
                        analysis.get("units", {}).get("torque", "force × length"))
    else:
        last.plot(x, analysis["transmission_angle_deg"], color=LINK, linewidth=1.2)
        last.set_title("transmission angle", fontsize=9, loc="left")
        last.set_ylabel("deg")
    last.set_xlabel("input position" if "input_position" in analysis else "input angle, deg")
    # The dead points next to the samples (within a tenth of their span), as the SVG draws them.
    reach = 0.1 * (max(x) - min(x)) if x else 0.0
    for dead in analysis.get("dead_points", []):
        at = dead.get("input_deg", dead.get("input_position"))
        if at is None or at < min(x) - reach or at > max(x) + reach:
            continue
        for ax in axes:
            ax.axvline(at, color=DEAD_POINT, linestyle="--", linewidth=0.8)
    fig.tight_layout()
    return fig
