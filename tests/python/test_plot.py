"""linkfit.plot against `linkfit solve --svg`: the same panels, titles and mechanisms.

Run by ctest (Python.pytest); needs matplotlib (Debian's python3-matplotlib, which the README's
first command installs).
"""

import html
import json
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


def test_plot_says_what_it_cannot_draw():
    spatial = linkfit.solve(json.loads((DATA / "platform_7_poses.json").read_text()))
    with pytest.raises(ValueError, match="spatial platform"):
        linkfit.plot(spatial)
    with pytest.raises(ValueError, match="carries no drawing"):
        linkfit.plot(json.loads(json.dumps(spatial)))
