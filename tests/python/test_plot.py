"""linkfit.plot against `linkfit solve --svg`: the same panels, titles and mechanisms.

Run by ctest (Python.pytest); needs matplotlib (Debian's python3-matplotlib, which the README's
first command installs).
"""

import html
import json
import math
import os
import pathlib
import re
import subprocess

import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import linkfit  # noqa: E402

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"
CLI = os.environ.get("LINKFIT_CLI", "linkfit")


def svg_panel_titles(name, tmp_path):
    picture = tmp_path / "picture.svg"
    subprocess.run([CLI, "solve", str(DATA / name), "--svg", str(picture)], check=True,
                   capture_output=True)
    text = picture.read_text()
    return [html.unescape(t) for t in re.findall(r'font-weight="bold" fill="#222222">'
                                                 r'(\d+: [^<]*)</text>', text)]


def plotted_points(axis):
    """Every vertex of the lines drawn on an Axes."""
    points = []
    for line in axis.get_lines():
        xs, ys = line.get_data()
        points += list(zip(map(float, xs), map(float, ys)))
    return points


def near(point, points, tolerance):
    return any(abs(point[0] - x) <= tolerance and abs(point[1] - y) <= tolerance
               for x, y in points)


@pytest.mark.parametrize("name", ["four_bar_12_poses.json", "slider_crank_5_poses.json",
                                  "four_bar_4_poses.json", "path_12_points.json",
                                  "path_12_points_untimed.json"])
def test_plot_draws_the_svgs_panels(tmp_path, name):
    task = json.loads((DATA / name).read_text())
    result = linkfit.solve(task)
    figure = linkfit.plot(result)
    axes = [axis for axis in figure.axes if axis.get_visible()]
    titles = svg_panel_titles(name, tmp_path)
    assert titles, "the SVG lists no panel"
    assert [axis.get_title(loc="left") for axis in axes] == titles
    # Each panel draws its mechanism's fixed pivots and the task's poses or points.
    path = result["problem"] == "path"
    tolerance = 1e-9 * result["scale"]
    for axis, mechanism in zip(axes, result["mechanisms"]):
        drawn = plotted_points(axis)
        if path:
            pivots = [mechanism["input_pivot"]]
            if "output_pivot" in mechanism:
                pivots.append(mechanism["output_pivot"])
            places = [(p["x"], p["y"]) for p in task["points"]]
        else:
            pivots = [result["dyads"][k]["fixed"] for k in mechanism["dyads"]
                      if "fixed" in result["dyads"][k]]
            places = [(p["x"], p["y"]) for p in task["poses"]]
        for pivot in pivots:
            assert near(pivot, drawn, tolerance), pivot
        for place in places:
            assert near(place, drawn, tolerance), place
    figure.savefig(tmp_path / "figure.png")
    matplotlib.pyplot.close(figure)


def test_plot_draws_six_bars_by_their_joints(tmp_path):
    """A six-bar result (issue 36): the SVG's panels, each six-bar's joints where the result says
    they are at the first pose."""
    name = "six_bar_5_poses.json"
    task = json.loads((DATA / name).read_text())
    result = linkfit.solve(task)
    assert result["six_bars"]
    figure = linkfit.plot(result)
    axes = [axis for axis in figure.axes if axis.get_visible()]
    assert [axis.get_title(loc="left") for axis in axes] == svg_panel_titles(name, tmp_path)
    tolerance = 1e-9 * result["scale"]
    for axis, six_bar in zip(axes, result["six_bars"]):
        drawn = plotted_points(axis)
        joints = six_bar["joints_at_first_pose"]
        places = [joints["ground_pivot"], joints["elbow"], joints["wrist"]]
        for link in joints["links"]:
            places += [link["from_joint"], link["to_joint"]]
        for place in places:
            assert near(place, drawn, tolerance), place
        assert "Stephenson" in axis.get_title(loc="left") or "Watt" in axis.get_title(loc="left")
    figure.savefig(tmp_path / "six_bars.png")
    matplotlib.pyplot.close(figure)


def test_plot_on_given_axes_and_refined_results():
    import matplotlib.pyplot as pyplot
    task = json.loads((DATA / "path_12_points.json").read_text())
    result = linkfit.solve(task)
    figure, axis = pyplot.subplots()
    assert linkfit.plot(result, ax=axis, mechanism=1) is axis
    assert axis.get_title(loc="left").startswith("2: ")
    refined = linkfit.refine(task, result, mechanism=1)
    single = linkfit.plot(refined)
    assert [a.get_title(loc="left") for a in single.axes] == ["1: 4R, crank-rocker"]
    with pytest.raises(ValueError, match="mechanism 40"):
        linkfit.plot(result, mechanism=40)
    pyplot.close("all")


SPHERICAL = "spherical_four_bar_5_poses.json"


def spherical_view(result, mechanism):
    """The view a spherical four-bar is drawn on, from the result alone (user guide, "Spherical
    motion"): along the mean of its fixed axes and its moving axes at the first pose (the bundled
    task's first orientation is the identity), Sigma's z-axis up; returns (right, up)."""
    def unit(v):
        n = math.sqrt(sum(x * x for x in v))
        return [x / n for x in v]

    dyads = [result["dyads"][k] for k in mechanism["dyads"]]
    toward = unit([sum(d[key][i] for d in dyads for key in ("fixed_axis", "moving_axis"))
                   for i in range(3)])
    up = unit([(1.0 if i == 2 else 0.0) - toward[2] * toward[i] for i in range(3)])
    right = [up[1] * toward[2] - up[2] * toward[1], up[2] * toward[0] - up[0] * toward[2],
             up[0] * toward[1] - up[1] * toward[0]]
    return right, up


def drawn_ground_pivots(axis):
    """Where the ground pivots (triangle marks) are drawn on an Axes."""
    return [(float(x), float(y)) for line in axis.get_lines() if line.get_marker() == "^"
            for x, y in zip(*line.get_data())]


def test_plot_draws_spherical_four_bars_on_their_views(tmp_path):
    task = json.loads((DATA / SPHERICAL).read_text())
    assert task["poses"][0]["angle_deg"] == 0  # the first orientation: the identity
    result = linkfit.solve(task)
    assert result["model"] == "spherical"
    figure = linkfit.plot(result)
    axes = [axis for axis in figure.axes if axis.get_visible()]
    listed = result["mechanisms"][:12]
    assert len(listed) >= 2
    assert [axis.get_title(loc="left") for axis in axes] == svg_panel_titles(SPHERICAL, tmp_path)
    assert len(axes) == len(listed)
    assert any("orthographic view of the unit sphere" in text.get_text() for text in figure.texts)
    for axis, mechanism in zip(axes, listed):
        right, up = spherical_view(result, mechanism)
        fixed = [result["dyads"][k]["fixed_axis"] for k in mechanism["dyads"]]
        expected = [tuple(sum(a * b for a, b in zip(u, direction)) for direction in (right, up))
                    for u in fixed]
        drawn = drawn_ground_pivots(axis)
        assert len(drawn) == 2
        for pivot, place in zip(drawn, expected):  # input, then output
            assert pivot == pytest.approx(place, abs=1e-9)
        # Everything drawn is on the view of the unit sphere.
        assert all(x * x + y * y <= 1.0 + 1e-9 for x, y in plotted_points(axis))
    figure.savefig(tmp_path / "sphere.png")
    matplotlib.pyplot.close(figure)


def test_plot_draws_one_spherical_four_bar_on_given_axes():
    import matplotlib.pyplot as pyplot
    result = linkfit.solve(json.loads((DATA / SPHERICAL).read_text()))
    figure, axis = pyplot.subplots()
    assert linkfit.plot(result, ax=axis, mechanism=1) is axis
    assert axis.get_title(loc="left").startswith("2: spherical 4R, ")
    right, up = spherical_view(result, result["mechanisms"][1])
    fixed = [result["dyads"][k]["fixed_axis"] for k in result["mechanisms"][1]["dyads"]]
    expected = [sum(a * b for a, b in zip(u, direction))
                for u in fixed for direction in (right, up)]
    assert [c for pivot in drawn_ground_pivots(axis) for c in pivot] == pytest.approx(expected,
                                                                                   abs=1e-9)
    single = linkfit.plot(result, mechanism=1)
    assert [a.get_title(loc="left") for a in single.axes] == [axis.get_title(loc="left")]
    with pytest.raises(ValueError, match="mechanism 40"):
        linkfit.plot(result, mechanism=40)
    pyplot.close("all")


def test_plot_says_what_it_cannot_draw():
    spatial = linkfit.solve(json.loads((DATA / "platform_7_poses.json").read_text()))
    with pytest.raises(ValueError, match="spatial platform"):
        linkfit.plot(spatial)
    with pytest.raises(ValueError, match="no planar mechanism"):
        linkfit.plot(json.loads(json.dumps(spatial)))


def test_plot_draws_a_result_read_back_from_a_file():
    """Issue 35: a result written to a file and read back is drawn from each mechanism's
    "linkage", its ground pivots where the file says, the task's points overlaid."""
    import matplotlib.pyplot as pyplot
    task = json.loads((DATA / "path_12_points_untimed.json").read_text())
    back = json.loads(json.dumps(linkfit.solve(task)))
    figure = linkfit.plot(back, task=task)
    panels = [axis for axis in figure.axes if axis.get_visible()]
    assert len(panels) == min(12, len(back["mechanisms"]))
    assert panels[0].get_title(loc="left").startswith("1. " + back["mechanisms"][0]["type"])
    joints = back["mechanisms"][0]["linkage"]["joints"]
    expected = joints["input_pivot"] + joints["output_pivot"]
    assert [c for pivot in drawn_ground_pivots(panels[0]) for c in pivot] == pytest.approx(
        expected, abs=1e-9)
    one = linkfit.plot(back, mechanism=2)
    assert [a.get_title(loc="left")[:3] for a in one.axes] == ["3. "]
    with pytest.raises(ValueError, match="mechanism 40"):
        linkfit.plot(back, mechanism=40)
    table = linkfit.summary(back)
    assert table.splitlines()[1].split()[:3] == ["#", "type", "grashof"]
    assert table.splitlines()[2].split()[:2] == ["1", back["mechanisms"][0]["type"]]
    pyplot.close("all")


def test_plot_draws_the_tasks_pivot_box():
    """A task's fixed_pivots_box is drawn in each panel where the task puts it (as the SVG)."""
    task = json.loads((DATA / "bounded_four_bar_5_poses.json").read_text())
    (x0, y0), (x1, y1) = task["constraints"]["fixed_pivots_box"]
    result = linkfit.solve(task)
    figure = linkfit.plot(result)
    axes = [axis for axis in figure.axes if axis.get_visible()]
    assert axes
    corners = {(x0, y0), (x1, y0), (x1, y1), (x0, y1)}
    for axis in axes:
        outlines = [{(round(float(x), 9), round(float(y), 9)) for x, y in patch.get_xy()}
                    for patch in axis.patches if hasattr(patch, "get_xy")]
        assert any(corners <= outline for outline in outlines), axis.get_title(loc="left")
    matplotlib.pyplot.close(figure)


def test_plot_analysis_draws_four_panels_with_the_dead_points():
    """linkfit.plot_analysis (issue 37): four panels against the input angle, a line per link in
    the first three and the torque in the last, a rocker's dead points marked on each."""
    result = linkfit.solve(json.loads((DATA / "function_log10.json").read_text()))
    analysis = linkfit.analyze(result, steps=60, load={"output_torque": 1.0},
                               input_range_deg="whole")
    figure = linkfit.plot_analysis(analysis)
    axes = figure.get_axes()
    assert len(axes) == 4
    dead = [point["input_deg"] for point in analysis["dead_points"]]
    assert len(dead) == 2
    for k, ax in enumerate(axes):
        lines = ax.get_lines()
        series = [line for line in lines if line.get_linestyle() == "-"]
        marks = [line for line in lines if line.get_linestyle() == "--"]
        assert len(series) == (3 if k < 3 else 1)
        assert sorted(mark.get_xdata()[0] for mark in marks) == sorted(dead)
        for line in series:
            assert list(line.get_xdata()) == analysis["input_deg"]
    assert list(axes[3].get_lines()[0].get_ydata()) == analysis["input_torque"]
    with pytest.raises(ValueError):
        linkfit.plot_analysis({"mechanisms": []})
