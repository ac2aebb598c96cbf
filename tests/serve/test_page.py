"""The `linkfit serve` page in headless Chromium against the real server.

Run by ctest (Serve.page) with LINKFIT_CLI the built `linkfit`, which serves the source tree's
web/ (the page of this checkout). Needs Debian's python3-selenium, chromium and chromium-driver
(scripts/setup.sh installs them).
"""

import json
import math
import os
import pathlib
import queue
import shutil
import subprocess
import tempfile
import threading
import time
import urllib.parse
import urllib.request

import pytest

from conftest import running_server

ROOT = pathlib.Path(__file__).resolve().parents[2]
WEB = ROOT / "web"
CLI = os.environ.get("LINKFIT_CLI", "linkfit")
CHROMEDRIVER = "/usr/bin/chromedriver"

from selenium import webdriver  # Debian's python3-selenium, installed by scripts/setup.sh
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def browser():
    # scripts/setup.sh installs them: missing, the page is untested, which is a failure.
    assert _chromium() and os.path.exists(CHROMEDRIVER), (
        "chromium and chromium-driver are missing: run scripts/setup.sh")
    options = webdriver.ChromeOptions()
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,900"):
        options.add_argument(argument)
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_script_timeout(20)
    try:
        yield driver
    finally:
        driver.quit()


def api_solve(url, task_text):
    request = urllib.request.Request(url + "api/solve", data=task_text.encode(), method="POST",
                                     headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=30) as reply:
        return json.loads(reply.read())


def wait_for(predicate, timeout=10, what="condition"):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    pytest.fail(f"timed out waiting for {what}")


def drag(driver, handle, steps, dx, dy, pause, release=True):
    """Presses on `handle` and moves by (dx, dy) pixels `steps` times, `pause` seconds apart,
    as a hand drags (each move an event the page solves); then lets go unless told not to."""
    chain = ActionChains(driver, duration=20).click_and_hold(handle)
    for _ in range(steps):
        chain.move_by_offset(dx, dy).pause(pause)
    (chain.release() if release else chain).perform()


def settle(driver):
    """Waits until no solve is queued or in flight."""
    wait_for(lambda: not driver.execute_script("return window.linkfit.busy"), what="the solves to settle")


def drawn_fixed_pivots(driver):
    """{dyad index: (x, y)} of the fixed pivots drawn, read in one script (the picture is
    redrawn between two calls)."""
    pairs = driver.execute_script("""
        return [...document.querySelectorAll('[data-testid^="fixed-pivot-"]')].map(
            (e) => [e.dataset.testid, e.dataset.x, e.dataset.y]);""")
    return {int(testid.rsplit("-", 1)[1]): (float(x), float(y)) for testid, x, y in pairs}


def assert_page_shows(driver, result):
    """The fixed pivots drawn and the mechanism list are those of `result`."""
    expected = {i: tuple(d["fixed"]) for i, d in enumerate(result["dyads"]) if "fixed" in d}
    drawn = drawn_fixed_pivots(driver)
    assert drawn.keys() == expected.keys()
    for i, (x, y) in expected.items():
        assert math.isclose(drawn[i][0], x, rel_tol=1e-9, abs_tol=1e-9), (i, drawn[i], (x, y))
        assert math.isclose(drawn[i][1], y, rel_tol=1e-9, abs_tol=1e-9), (i, drawn[i], (x, y))
    # ... and drawn there: each pivot's glyph centred where the view puts the result's point
    # (measured in one script: the picture is redrawn between two calls).
    placed = driver.execute_script("""
        const canvas = document.querySelector('[data-testid="canvas"]').getBoundingClientRect();
        return [...document.querySelectorAll('[data-testid^="fixed-pivot-"]')].map((e) => {
          const box = e.getBoundingClientRect();
          return [e.dataset.testid, box.x + box.width / 2 - canvas.x,
                  box.y + box.height / 2 - canvas.y, canvas.width, canvas.height];
        });""")
    assert len(placed) == len(expected)
    for testid, cx, cy, width, height in placed:
        index = int(testid.rsplit("-", 1)[1])
        sx, sy = driver.execute_script("return window.linkfit.toScreen(...arguments)",
                                       *expected[index])
        if 0 <= sx <= width and 0 <= sy <= height:
            assert abs(cx - sx) < 1.5 and abs(cy - sy) < 1.5, (index, (cx, cy), (sx, sy))
    rows = driver.execute_script(
        """return document.querySelectorAll('[data-testid^="mechanism-row-"]').length""")
    assert rows == len(result["mechanisms"])
    page = driver.execute_script("return window.linkfit.state.result")
    assert [m["dyads"] for m in page["mechanisms"]] == [m["dyads"] for m in result["mechanisms"]]


def test_designer_page(server, browser):
    driver = browser
    driver.get(server)
    # The bundled five-pose example, solved and drawn on load.
    assert driver.execute_async_script(
        "const done = arguments[0]; window.linkfit.ready.then(() => done(true));")
    settle(driver)
    task_text = driver.execute_script("return window.linkfit.taskText()")
    example = json.loads((ROOT / "data" / "four_bar_5_poses.json").read_text())
    assert json.loads(task_text) == example
    # The digits as written: the task text carries the file's numbers, not re-printed floats.
    assert "32.4759526419165" in task_text
    assert_page_shows(driver, api_solve(server, task_text))
    version = driver.find_element(By.CSS_SELECTOR, '[data-testid="status-version"]').text
    assert version.startswith("linkfit ")

    # Drag the second pose's origin: every move solves live; the last picture is the API's answer.
    before = json.loads(task_text)["poses"][1]
    samples_before = driver.execute_script("return window.linkfit.latencies.length")
    handle = driver.find_element(By.CSS_SELECTOR, '[data-testid="pose-1-origin"]')
    drag(driver, handle, 8, 4, -3, 0.05)
    settle(driver)
    moved_text = driver.execute_script("return window.linkfit.taskText()")
    moved = json.loads(moved_text)
    assert (moved["poses"][1]["x"], moved["poses"][1]["y"]) != (before["x"], before["y"])
    assert moved["poses"][1]["theta_deg"] == before["theta_deg"]
    assert moved["poses"][0] == example["poses"][0]
    assert_page_shows(driver, api_solve(server, moved_text))
    # The latency of each move: pointer event to the frame that paints its solve's picture. Their
    # median (one sample catches any hiccup of a loaded machine's scheduler, and includes up to a
    # frame of waiting for the display's next frame).
    latency, parts, samples = driver.execute_script(
        "const l = window.linkfit; return [l.lastLatencyMs, l.lastLatencyParts, l.latencies];")
    samples = samples[samples_before - len(samples):] if samples_before < len(samples) else []
    print("live latency", latency, parts, "drag:", [round(ms, 1) for ms in samples])
    assert latency is not None and len(samples) >= 4, samples
    median = sorted(samples)[len(samples) // 2]
    assert median <= 30, (f"live latency median {median:.1f} ms of {samples} "
                          f"(last: wait, request, redraw, paint {parts})")
    assert "live:" in driver.find_element(By.CSS_SELECTOR, '[data-testid="latency"]').text

    # Select the second mechanism and play it: the animation steps through linkfit's analysis.
    driver.find_element(By.CSS_SELECTOR, '[data-testid="mechanism-row-1"]').click()
    assert driver.execute_script("return window.linkfit.state.selected") == 1
    driver.find_element(By.CSS_SELECTOR, '[data-testid="play"]').click()
    wait_for(lambda: driver.execute_script("return window.linkfit.playing"), what="play")
    first = driver.execute_script("return window.linkfit.frame")
    wait_for(lambda: driver.execute_script("return window.linkfit.frame") != first, what="the animation")
    analysis = driver.execute_script("return window.linkfit.state.analysis")
    assert analysis["mechanism"] == 2 and len(analysis["input_deg"]) > 10
    assert driver.find_elements(By.CSS_SELECTOR, '[data-testid="coupler-curve"]')
    driver.find_element(By.CSS_SELECTOR, '[data-testid="play"]').click()

    # Save the task: the file is the task's text, digits and all.
    driver.find_element(By.CSS_SELECTOR, '[data-testid="export-task"]').click()
    exported = driver.execute_script("return window.linkfit.lastExport")
    assert exported["name"] == "task.json"
    assert exported["text"] == moved_text
    assert json.loads(exported["text"]) == moved

    # A value typed in the table that is not a number: not sent; the cell marked, the error bar says so.
    count = driver.execute_script("return window.linkfit.solveCount")
    cell = driver.find_element(By.CSS_SELECTOR, '[data-testid="item-2-y"]')
    cell.clear()
    cell.send_keys("abc")
    bar = driver.find_element(By.CSS_SELECTOR, '[data-testid="error-bar"]')
    wait_for(bar.is_displayed, what="the error bar")
    assert "pose 3, y: 'abc' is not a number" in bar.text, bar.text
    assert "invalid" in cell.get_attribute("class")
    settle(driver)
    assert driver.execute_script("return window.linkfit.solveCount") == count
    assert json.loads(driver.execute_script("return window.linkfit.taskText()")) == moved

    target = os.environ.get("LINKFIT_SCREENSHOT") or os.path.join(tempfile.mkdtemp(), "serve_page.png")
    # The picture with the error fixed again, for a human to look at.
    cell.clear()
    cell.send_keys(str(example["poses"][2]["y"]))
    settle(driver)
    wait_for(lambda: not bar.is_displayed(), what="the error bar to clear")
    driver.save_screenshot(target)
    assert os.path.getsize(target) > 0


# ---------- picked pivots, constraint boxes, refinement, cancel ----------

DATA = ROOT / "data"


def api_refine(url, task_text, design_text, mechanism):
    """POST /api/refine?mechanism=N (counted from 1) with the parts task and design."""
    boundary = "linkfit-test-boundary"
    body = b""
    for name, text in (("task", task_text), ("design", design_text)):
        body += (f"--{boundary}\r\nContent-Disposition: form-data; name=\"{name}\"; "
                 f"filename=\"{name}.json\"\r\nContent-Type: application/json\r\n\r\n").encode()
        body += text.encode() + b"\r\n"
    body += f"--{boundary}--\r\n".encode()
    request = urllib.request.Request(
        url + f"api/refine?mechanism={mechanism}", data=body, method="POST",
        headers={"Content-Type": f"multipart/form-data; boundary={boundary}"})
    with urllib.request.urlopen(request, timeout=60) as reply:
        return json.loads(reply.read())


def without_times(value):
    """A result without its timings (`solve_time_ms`, each stage's `time_ms`): the rest is
    deterministic."""
    if isinstance(value, dict):
        return {k: without_times(v) for k, v in value.items() if not k.endswith("time_ms")}
    if isinstance(value, list):
        return [without_times(v) for v in value]
    return value


def load_page(driver, url):
    """The page freshly loaded, its bundled example solved."""
    driver.get(url)
    assert driver.execute_async_script(
        "const done = arguments[0]; window.linkfit.ready.then(() => done(true));")
    settle(driver)


def open_task(driver, path):
    """Opens a task file's text as "Open task…" does and waits for its solve; the text."""
    text = path.read_text()
    driver.execute_script("window.linkfit.openTask(arguments[0])", text)
    settle(driver)
    return text


def page_task(driver):
    return json.loads(driver.execute_script("return window.linkfit.taskText()"))


def distance_to_polylines(polylines, p):
    best = math.inf
    for line in polylines:
        for a, b in zip(line, line[1:]):
            ab = (b[0] - a[0], b[1] - a[1])
            length2 = ab[0] ** 2 + ab[1] ** 2
            t = 0 if length2 == 0 else max(0, min(1, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / length2))
            best = min(best, math.hypot(a[0] + t * ab[0] - p[0], a[1] + t * ab[1] - p[1]))
    return best


# Free places to click: canvas pixels (x, y) whose topmost element is the canvas's own drawing
# without a drag handle (a click there picks), away from the edges and from each other; at most
# `count`, from `candidates` (world points) or, without them, from a grid over the canvas.
FREE_SPOTS = """
  const [candidates, count, apart] = arguments;
  const svg = document.querySelector('[data-testid="canvas"]');
  const r = svg.getBoundingClientRect();
  const free = (sx, sy) => {
    if (sx < 60 || sy < 90 || sx > r.width - 60 || sy > r.height - 80) return false;
    for (const [dx, dy] of [[0, 0], [-8, 0], [8, 0], [0, -8], [0, 8]]) {
      const e = document.elementFromPoint(r.x + sx + dx, r.y + sy + dy);
      if (!e || !svg.contains(e) || e.closest('[data-drag]')) return false;
    }
    return true;
  };
  const points = candidates
    ? candidates.map(([x, y]) => [x, y, ...window.linkfit.toScreen(x, y)])
    : [...Array(15).keys()].flatMap((i) => [...Array(10).keys()].map((j) => {
        const sx = r.width * (i + 1) / 16, sy = r.height * (j + 1) / 11;
        return [null, null, sx, sy];
      }));
  const chosen = [];
  for (const p of points) {
    if (chosen.length >= count) break;
    if (!free(p[2], p[3])) continue;
    if (chosen.some((q) => Math.hypot(q[2] - p[2], q[3] - p[3]) < apart)) continue;
    chosen.push(p);
  }
  return { chosen, width: r.width, height: r.height };
"""


def click_canvas(driver, sx, sy, width, height):
    """A click at canvas pixel (sx, sy) (Selenium's offsets are from the element's centre)."""
    canvas = driver.find_element(By.CSS_SELECTOR, '[data-testid="canvas"]')
    ActionChains(driver).move_to_element_with_offset(
        canvas, round(sx - width / 2), round(sy - height / 2)).click().perform()
    settle(driver)


def world_per_pixel(driver):
    (x0, _), (x1, _) = driver.execute_script(
        "return [window.linkfit.toScreen(0, 0), window.linkfit.toScreen(1, 0)]")
    return 1 / (x1 - x0)


def test_picked_pivots(server, browser):
    driver = browser
    load_page(driver, server)

    # Four poses: the center-point curve is drawn; two clicks near it pick two fixed pivots on it.
    open_task(driver, DATA / "four_bar_4_poses.json")
    curves = driver.execute_script("return window.linkfit.state.result.burmester_curves.center_points")
    drawn = driver.execute_script(
        """return [...document.querySelectorAll('[data-testid="center-point-curve"]')]
             .map((e) => e.points.numberOfItems)""")
    assert len(drawn) == sum(1 for line in curves if len(line) >= 2) and min(drawn) >= 2
    driver.find_element(By.CSS_SELECTOR, '[data-testid="tool-pivot"]').click()
    candidates = [p for line in curves for p in line[::7]]
    spots = driver.execute_script(FREE_SPOTS, candidates, 2, 120)
    assert len(spots["chosen"]) == 2, "two free points of the center-point curve on screen"
    unit = world_per_pixel(driver)
    for x, y, sx, sy in spots["chosen"]:
        # A few pixels off the curve: the pivot goes to the curve's nearest point.
        click_canvas(driver, sx + 3, sy - 2, spots["width"], spots["height"])
    task_text = driver.execute_script("return window.linkfit.taskText()")
    pivots = json.loads(task_text)["fixed_pivots"]
    assert len(pivots) == 2
    for (x, y, _, _), p in zip(spots["chosen"], pivots):
        assert distance_to_polylines(curves, p) < 2e-3, (p, "off the center-point curve")
        assert math.hypot(p[0] - x, p[1] - y) < 10 * unit, (p, (x, y), "far from the click")
    assert_page_shows(driver, api_solve(server, task_text))
    result = driver.execute_script("return window.linkfit.state.result")
    picked = [i for i, d in enumerate(result["dyads"])
              if any(math.hypot(d["fixed"][0] - p[0], d["fixed"][1] - p[1]) < 1e-2 for p in pivots)]
    assert len(picked) == 2, "a dyad at each picked pivot"
    assert any(sorted(m["dyads"]) == sorted(picked) for m in result["mechanisms"]), (
        "the four-bar of the two picked pivots is listed")

    # A picked pivot dragged slides along the curve.
    handle = driver.find_element(By.CSS_SELECTOR, '[data-testid="picked-pivot-0"]')
    drag(driver, handle, 5, 4, 3, 0.03)
    settle(driver)
    task_text = driver.execute_script("return window.linkfit.taskText()")
    moved = json.loads(task_text)["fixed_pivots"]
    assert moved[1] == pivots[1] and moved[0] != pivots[0]
    assert distance_to_polylines(curves, moved[0]) < 2e-3, (moved[0], "dragged off the curve")
    assert_page_shows(driver, api_solve(server, task_text))

    # Cleared: the task has no pivots, and is solved so.
    driver.find_element(By.CSS_SELECTOR, '[data-testid="clear-pivots"]').click()
    settle(driver)
    task_text = driver.execute_script("return window.linkfit.taskText()")
    assert "fixed_pivots" not in json.loads(task_text)
    assert_page_shows(driver, api_solve(server, task_text))

    # Three poses: any two clicks give two pivots there and their four-bar.
    open_task(driver, DATA / "four_bar_3_poses.json")
    assert driver.execute_script(
        "return document.querySelector('[data-testid=\"tool-pivot\"]').classList.contains('active')")
    spots = driver.execute_script(FREE_SPOTS, None, 2, 150)
    assert len(spots["chosen"]) == 2
    unit = world_per_pixel(driver)
    clicked = []
    for _, _, sx, sy in spots["chosen"]:
        clicked.append(driver.execute_script(
            """const s = window.linkfit.toScreen(0, 0), t = window.linkfit.toScreen(1, 1);
               return [(arguments[0] - s[0]) / (t[0] - s[0]), (arguments[1] - s[1]) / (t[1] - s[1])];""",
            round(sx), round(sy)))
        click_canvas(driver, sx, sy, spots["width"], spots["height"])
    task_text = driver.execute_script("return window.linkfit.taskText()")
    pivots = json.loads(task_text)["fixed_pivots"]
    assert len(pivots) == 2
    for p, q in zip(pivots, clicked):
        assert math.hypot(p[0] - q[0], p[1] - q[1]) < 2 * unit, (p, q)
    result = api_solve(server, task_text)
    assert_page_shows(driver, result)
    assert len(result["dyads"]) == 2 and [sorted(m["dyads"]) for m in result["mechanisms"]] == [[0, 1]]
    driver.find_element(By.CSS_SELECTOR, '[data-testid="tool-select"]').click()


def test_constraint_box(server, browser):
    driver = browser
    load_page(driver, server)
    count = driver.execute_script("return window.linkfit.solveCount")
    driver.find_element(By.CSS_SELECTOR, '[data-testid="c-fixed-box"]').click()
    settle(driver)
    box = page_task(driver)["constraints"]["fixed_pivots_box"]
    assert driver.execute_script("return window.linkfit.state.result.constraints.fixed_pivots_box") == box
    assert driver.execute_script("return window.linkfit.solveCount") > count

    # Drag the box's corner 2 (x max, y max: top right on screen) right and up.
    handle = driver.find_element(By.CSS_SELECTOR, '[data-testid="fixed_pivots_box-corner-2"]')
    assert driver.execute_script(
        """const e = arguments[0], b = e.getBoundingClientRect();
           return document.elementFromPoint(b.x + b.width / 2, b.y + b.height / 2) === e;""", handle)
    unit = world_per_pixel(driver)
    count = driver.execute_script("return window.linkfit.solveCount")
    drag(driver, handle, 6, 5, -4, 0.03)
    settle(driver)
    task_text = driver.execute_script("return window.linkfit.taskText()")
    moved = json.loads(task_text)["constraints"]["fixed_pivots_box"]
    assert moved[0] == box[0], "the opposite corner stays"
    assert abs(moved[1][0] - (box[1][0] + 30 * unit)) < 2 * unit, (moved, box, unit)
    assert abs(moved[1][1] - (box[1][1] + 24 * unit)) < 2 * unit, (moved, box, unit)
    # Re-solved with it: the result echoes the box, and is the API's answer for the task.
    assert driver.execute_script("return window.linkfit.solveCount") > count
    assert driver.execute_script("return window.linkfit.state.result.constraints.fixed_pivots_box") == moved
    assert_page_shows(driver, api_solve(server, task_text))


def test_refine(server, browser):
    driver = browser
    load_page(driver, server)
    task_text = open_task(driver, DATA / "four_bar_12_poses.json")
    assert driver.execute_script("return window.linkfit.state.result.method") == "least-squares"
    assert driver.execute_script("return window.linkfit.taskText()") == task_text
    # Refine the second mechanism of the fast stage's list.
    driver.find_element(By.CSS_SELECTOR, '[data-testid="mechanism-row-1"]').click()
    design_text, before = driver.execute_script(
        "return [window.linkfit.state.resultText, window.linkfit.state.result.mechanisms[1]]")
    button = driver.find_element(By.CSS_SELECTOR, '[data-testid="refine"]')
    assert button.is_enabled()
    button.click()
    wait_for(lambda: driver.execute_script(
        "return window.linkfit.state.result.method === 'refine' && !window.linkfit.busy"),
        timeout=30, what="the refinement")
    page = driver.execute_script("return window.linkfit.state.result")
    expected = api_refine(server, task_text, design_text, 2)
    assert without_times(page) == without_times(expected)
    assert len(page["mechanisms"]) == 1
    after = page["mechanisms"][0]
    status = driver.find_element(By.CSS_SELECTOR, '[data-testid="status-refine"]').text
    assert "refined mechanism 2" in status and "→" in status, status
    assert f"{before['max_pose_error']:.4g}" in status and f"{after['max_pose_error']:.4g}" in status, status
    assert after["max_pose_error"] <= before["max_pose_error"]
    assert driver.execute_script(
        "return document.querySelectorAll('[data-testid^=\"mechanism-row-\"]').length") == 1


def test_cancel_staged_solve(server, browser):
    driver = browser
    load_page(driver, server)
    open_task(driver, DATA / "classic_path_ellipse_10_points.json")
    from selenium.webdriver.support.ui import Select
    Select(driver.find_element(By.CSS_SELECTOR, '[data-testid="effort"]')).select_by_visible_text("thorough")
    driver.find_element(By.CSS_SELECTOR, '[data-testid="solve"]').click()
    # Fast is done in a moment; balanced then runs for seconds.
    wait_for(lambda: driver.execute_script(
        """const li = document.querySelector('[data-testid="stage-balanced"]');
           return li && li.className === 'running';"""), timeout=10, what="the balanced stage")
    time.sleep(0.3)
    assert driver.execute_script("return window.linkfit.busy")
    driver.find_element(By.CSS_SELECTOR, '[data-testid="cancel"]').click()
    settle(driver)
    stages, elapsed, solve_enabled, cancel_enabled = driver.execute_script(
        """const $ = (id) => document.querySelector(`[data-testid="${id}"]`);
           return [[...$('stages').children].map((li) => [li.dataset.testid, li.className, li.textContent]),
                   $('elapsed').textContent, !$('solve').disabled, !$('cancel').disabled];""")
    assert [s[:2] for s in stages] == [["stage-fast", "done"], ["stage-balanced", "cancelled"],
                                       ["stage-thorough", "cancelled"]], stages
    assert "cancelled" in stages[1][2] and "not run" in stages[2][2], stages
    assert elapsed.startswith("cancelled"), elapsed
    assert solve_enabled and not cancel_enabled
    # Still usable: a five-pose task solves (live) as the API does.
    task_text = open_task(driver, DATA / "four_bar_5_poses.json")
    assert_page_shows(driver, api_solve(server, task_text))
    assert driver.execute_script("return window.linkfit.state.result.mechanisms.length") > 0


# ---------- every dyad and four-bar type drawn; bad input refused; box fields; layout ----------

# Four poses whose Burmester curves give slider dyads (PR): slider-cranks driven by the slider and
# by the crank, and a 4R. The same motion inverted (the frames swapped) gives RP dyads: inverted
# slider-cranks.
SLIDER_TASK = json.dumps({"problem": "motion", "space": "planar", "poses": [
    {"x": 0, "y": 0, "theta_deg": 0}, {"x": 40, "y": 25, "theta_deg": 15},
    {"x": 85, "y": 35, "theta_deg": 30}, {"x": 170, "y": 0, "theta_deg": 60}]})
INVERTED_TASK = json.dumps({"problem": "motion", "space": "planar", "poses": [
    {"x": 0, "y": 0, "theta_deg": 0}, {"x": -45.1075, "y": -13.7954, "theta_deg": -15},
    {"x": -91.1122, "y": 12.1891, "theta_deg": -30}, {"x": -85, "y": 147.2243, "theta_deg": -60}]})

# The picture's state in one script: the error bar, what the status says was not drawn, the
# selected mechanism's parts (their world coordinates) and the dyads' glyphs.
PICTURE = """
  const $ = (id) => document.querySelector(`[data-testid="${id}"]`);
  const parts = [...document.querySelectorAll('#layer-mechanism [data-testid]')].map((e) => ({
    id: e.dataset.testid, x: Number(e.dataset.x), y: Number(e.dataset.y), angle: Number(e.dataset.angle),
    from: e.dataset.from, to: e.dataset.to,
    nan: [...e.attributes].some((a) => /NaN|undefined/.test(a.value)) }));
  const dyads = [...document.querySelectorAll('[data-testid^="dyad-"]')].map((e) => e.dataset.testid);
  return { error: $('error-bar').hidden ? null : $('error-text').textContent, notDrawn: $('status-draw').textContent,
           parts, dyads, analysis: window.linkfit.state.analysis, selected: window.linkfit.state.selected,
           busy: window.linkfit.busy, frame: window.linkfit.frame };
"""


def off_line(x, y, line):
    """The distance from (x, y) to the line through (line.x, line.y) at line.angle (radians)."""
    return abs(-(x - line["x"]) * math.sin(line["angle"]) + (y - line["y"]) * math.cos(line["angle"]))


def check_frame(picture, mechanism, scale):
    """The selected mechanism's parts are those of its joints' types, and assembled: each slider
    block on its line, each RP's fixed pivot on the line the coupler carries."""
    joints = mechanism["linkage"]["joints"]
    parts = {p["id"]: p for p in picture["parts"]}
    assert not any(p["nan"] for p in picture["parts"]), picture["parts"]
    for side in ("input", "output"):
        line = joints.get(side + "_slider_line")
        if line is None:  # RR: a crank from its fixed pivot
            assert {f"mech-crank-{side}", f"mech-pivot-{side}"} <= parts.keys(), (side, parts.keys())
            assert f"mech-slider-{side}" not in parts
            continue
        block, drawn_line = parts[f"mech-slider-{side}"], parts[f"mech-line-{side}"]
        assert off_line(block["x"], block["y"], drawn_line) < 1e-6 * scale, (side, block, drawn_line)
        if line["on"] == "ground":  # PR: the block slides on the ground line
            assert math.isclose(drawn_line["angle"], math.radians(line["angle_deg"]), abs_tol=1e-9)
            assert f"mech-pivot-{side}" not in parts
        else:  # RP: the block turns on its fixed pivot, on the coupler's line
            assert f"mech-pivot-{side}" in parts
            assert math.hypot(block["x"] - joints[side + "_pivot"][0],
                              block["y"] - joints[side + "_pivot"][1]) < 1e-9 * scale
    return parts


def check_every_mechanism(driver, types):
    """Selects each listed mechanism: drawn without an error, as its type, at two steps of its
    analysis; returns the mechanism types seen."""
    result = driver.execute_script("return window.linkfit.state.result")
    scale = result["scale"]
    seen = set()
    assert {d["type"] for d in result["dyads"]} >= types, result["dyads"]
    for i, mechanism in enumerate(result["mechanisms"]):
        driver.find_element(By.CSS_SELECTOR, f'[data-testid="mechanism-row-{i}"]').click()
        picture = wait_for(lambda: (lambda p: p if p["analysis"] and p["analysis"]["mechanism"] == i + 1
                                    and not p["busy"] else None)(driver.execute_script(PICTURE)),
                           what=f"mechanism {i + 1} analysed")
        assert picture["error"] is None and picture["notDrawn"] == "", picture
        assert "coupler-curve" in {p["id"] for p in picture["parts"]}
        first = check_frame(picture, mechanism, scale)
        # Another step of its cycle: still assembled, the crank's length kept.
        steps = len(picture["analysis"]["input_deg"])
        driver.execute_script("""const s = document.querySelector('[data-testid="scrub"]');
            s.value = arguments[0]; s.dispatchEvent(new Event('input'));""", steps // 3)
        picture = driver.execute_script(PICTURE)
        assert picture["frame"] == steps // 3 and picture["error"] is None and picture["notDrawn"] == ""
        later = check_frame(picture, mechanism, scale)
        for side in ("input", "output"):
            if f"mech-crank-{side}" in first:
                length = [math.dist(*[[float(v) for v in p[k].split(",")] for k in ("from", "to")])
                          for p in (first[f"mech-crank-{side}"], later[f"mech-crank-{side}"])]
                assert math.isclose(*length, rel_tol=1e-9), (side, length)
        seen.add(mechanism["type"])
    # Every dyad drawn, a slider's and an RP's with its block.
    picture = driver.execute_script(PICTURE)
    for i, d in enumerate(result["dyads"]):
        assert f"dyad-{i}" in picture["dyads"]
        assert (f"dyad-block-{i}" in picture["dyads"]) == (d["type"] != "RR"), (i, d["type"])
    return seen


def test_every_dyad_type_drawn(server, browser):
    driver = browser
    load_page(driver, server)
    driver.execute_script("window.linkfit.openTask(arguments[0])", SLIDER_TASK)
    settle(driver)
    assert check_every_mechanism(driver, {"RR", "PR"}) >= {"slider-crank", "4R"}
    result = driver.execute_script("return window.linkfit.state.result")
    assert_page_shows(driver, result)
    # Played: a slider-driven slider-crank moves.
    driven = [i for i, m in enumerate(result["mechanisms"]) if "input_slider_line" in m["linkage"]["joints"]]
    assert driven, "a slider-crank driven by its slider"
    driver.find_element(By.CSS_SELECTOR, f'[data-testid="mechanism-row-{driven[0]}"]').click()
    driver.find_element(By.CSS_SELECTOR, '[data-testid="play"]').click()
    wait_for(lambda: driver.execute_script("return window.linkfit.playing"), what="play")
    first = driver.execute_script("return window.linkfit.frame")
    wait_for(lambda: driver.execute_script("return window.linkfit.frame") != first, what="the animation")
    driver.find_element(By.CSS_SELECTOR, '[data-testid="play"]').click()
    picture = driver.execute_script(PICTURE)
    assert picture["error"] is None and picture["notDrawn"] == ""
    check_frame(picture, result["mechanisms"][driven[0]], result["scale"])
    assert "slider at" in driver.find_element(By.CSS_SELECTOR, '[data-testid="anim-angle"]').text
    # The canvas still follows the zoom: pose 1 is drawn where the view now puts it.
    before = driver.execute_script("return window.linkfit.toScreen(0, 0)")
    driver.execute_script("""document.querySelector('[data-testid="canvas"]').dispatchEvent(
        new WheelEvent('wheel', {deltaY: -300, clientX: 200, clientY: 200, bubbles: true, cancelable: true}));""")
    after, drawn = driver.execute_script("""const o = document.querySelector('[data-testid="pose-0-origin"]');
        return [window.linkfit.toScreen(0, 0), [Number(o.getAttribute('cx')), Number(o.getAttribute('cy'))]];""")
    assert after != before and math.dist(after, drawn) < 0.5, (before, after, drawn)

    # RP dyads: inverted slider-cranks.
    driver.execute_script("window.linkfit.openTask(arguments[0])", INVERTED_TASK)
    settle(driver)
    assert "inverted slider-crank" in check_every_mechanism(driver, {"RR", "RP"})
    assert_page_shows(driver, driver.execute_script("return window.linkfit.state.result"))

    # Five poses with a slider: the bundled slider-crank example.
    open_task(driver, DATA / "slider_crank_5_poses.json")
    assert check_every_mechanism(driver, {"RR", "PR"}) >= {"slider-crank", "4R"}

    # A mechanism of a shape the page does not know: drawn as far as it goes, said in the status.
    text = driver.execute_script("return window.linkfit.state.resultText")
    odd = json.loads(text)
    odd["dyads"][0] = {"type": "XY", "fixed": "here"}
    del odd["mechanisms"][0]["linkage"]["joints"]["input_pin"]
    driver.execute_script("window.linkfit.openResultText(arguments[0])", json.dumps(odd))
    time.sleep(0.3)  # its analysis: the server may refuse the broken linkage, which the bar then says
    picture = driver.execute_script(PICTURE)
    assert picture["error"] is None or picture["error"].startswith("analysis:"), picture["error"]
    assert "dyad 1" in picture["notDrawn"] and "input joints" in picture["notDrawn"], picture["notDrawn"]
    assert "dyad-1" in picture["dyads"]


def error_text(driver):
    return driver.execute_script("""const b = document.querySelector('[data-testid="error-bar"]');
        return b.hidden ? null : document.querySelector('[data-testid="error-text"]').textContent;""")


def test_bad_numbers_refused(server, browser):
    driver = browser
    load_page(driver, server)
    # A decimal comma typed in a cell: not sent, the cell marked, the error bar says why.
    cell = driver.find_element(By.CSS_SELECTOR, '[data-testid="item-1-x"]')
    cell.clear()
    cell.send_keys("40")
    settle(driver)
    task = driver.execute_script("return window.linkfit.taskText()")
    count = driver.execute_script("return window.linkfit.solveCount")
    cell.send_keys(",5")
    settle(driver)
    assert error_text(driver) == "pose 2, x: '40,5' is not a number (use a decimal point)"
    assert "invalid" in cell.get_attribute("class")
    assert driver.execute_script("return window.linkfit.solveCount") == count
    assert driver.execute_script("return window.linkfit.taskText()") == task
    cell.clear()
    cell.send_keys("40.50")
    settle(driver)
    assert error_text(driver) is None and "invalid" not in cell.get_attribute("class")
    assert '"x": 40.50' in driver.execute_script("return window.linkfit.taskText()")

    # A pasted table with decimal commas: refused with the same hint, the task kept.
    task = driver.execute_script("return window.linkfit.taskText()")
    driver.find_element(By.CSS_SELECTOR, '.paste > summary').click()
    area = driver.find_element(By.CSS_SELECTOR, '[data-testid="table-text"]')
    for table, message in (
            ("x;y;theta_deg\n0;0;0\n40,5;25;15\n85;35;30\n170;0;60\n", "table line 3, x: '40,5'"),
            ("0\t0\t0\n40\t25,5\t15\n85\t35\t30\n", "table line 2, y: '25,5'"),
            ("0 0 0\n40,5 25 15\n85 35 30\n", "table line 2: '40,5'")):
        driver.execute_script("arguments[0].value = arguments[1]", area, table)
        driver.find_element(By.CSS_SELECTOR, '[data-testid="table-apply"]').click()
        assert error_text(driver) == message + " is not a number (use a decimal point)", error_text(driver)
        assert driver.execute_script("return window.linkfit.taskText()") == task
    driver.find_element(By.CSS_SELECTOR, '.paste > summary').click()

    # The server's message naming poses[2]: the table's row 3 named and marked; the result kept
    # but greyed as out of date until the next solve succeeds.
    cell = driver.find_element(By.CSS_SELECTOR, '[data-testid="item-2-y"]')
    good = cell.get_attribute("value")
    # Pasted into the cell at once (typed, "1e9" and "1e99" would be solved on the way).
    driver.execute_script("arguments[0].value = '1e999'; arguments[0].dispatchEvent(new Event('input'))", cell)
    settle(driver)
    message = error_text(driver)
    assert message and "poses[2].y (row 3)" in message, message
    state = driver.execute_script("""const $ = (id) => document.querySelector(`[data-testid="${id}"]`);
        return [window.linkfit.state.stale, $('item-row-2').classList.contains('error-row'),
                $('mechanism-list').classList.contains('stale'), !$('mechanism-stale').hidden,
                document.getElementById('layer-mechanism').classList.contains('stale'),
                document.querySelectorAll('#layer-mechanism > *').length,
                document.querySelectorAll('.error-row').length]""")
    assert state == [True, True, True, True, True, state[5], 1] and state[5] > 0, state
    cell.clear()
    cell.send_keys(good)
    settle(driver)
    state = driver.execute_script("""return [window.linkfit.state.stale, document.querySelectorAll('.error-row').length,
        document.querySelector('[data-testid="mechanism-list"]').classList.contains('stale'),
        document.getElementById('layer-mechanism').classList.contains('stale')]""")
    assert state == [False, 0, False, False] and error_text(driver) is None, state


def test_box_corner_fields(server, browser):
    driver = browser
    load_page(driver, server)
    driver.find_element(By.CSS_SELECTOR, '[data-testid="c-fixed-box"]').click()
    settle(driver)
    key = "fixed_pivots_box"
    fields = lambda: driver.execute_script(
        "return ['xmin', 'ymin', 'xmax', 'ymax'].map((n) => document.querySelector(`[data-testid=\"c-%s-${n}\"]`).value)" % key)
    box = page_task(driver)["constraints"][key]
    assert [float(v) for v in fields()] == [box[0][0], box[0][1], box[1][0], box[1][1]]
    # Typed: the task keeps the digits; the box is drawn there and solved with.
    xmax = f"{math.floor(box[1][0]) + 5}.50"
    field = driver.find_element(By.CSS_SELECTOR, f'[data-testid="c-{key}-xmax"]')
    field.clear()
    field.send_keys(xmax)
    settle(driver)
    text = driver.execute_script("return window.linkfit.taskText()")
    assert f"[{xmax}, " in text, text
    assert driver.execute_script("return window.linkfit.state.result.constraints.fixed_pivots_box")[1][0] == float(xmax)
    corner = driver.execute_script("""const e = document.querySelector('[data-testid="fixed_pivots_box-corner-2"]');
        return [Number(e.getAttribute('x')) + 5, Number(e.getAttribute('y')) + 5];""")
    expected = driver.execute_script("return window.linkfit.toScreen(...arguments)", float(xmax), box[1][1])
    assert math.dist(corner, expected) < 0.5, (corner, expected)
    # Not a number: refused, said.
    field = driver.find_element(By.CSS_SELECTOR, f'[data-testid="c-{key}-ymin"]')
    field.clear()
    field.send_keys("3,5")
    settle(driver)
    assert error_text(driver) == "fixed pivots box, ymin: '3,5' is not a number (use a decimal point)"
    assert "invalid" in field.get_attribute("class")
    assert page_task(driver)["constraints"][key][0][1] == 3  # the last number typed, "3"
    # Dragged on the canvas: the fields follow (the dragged values rounded to the view).
    handle = driver.find_element(By.CSS_SELECTOR, f'[data-testid="{key}-corner-2"]')
    assert driver.execute_script(
        """const e = arguments[0], b = e.getBoundingClientRect();
           return document.elementFromPoint(b.x + b.width / 2, b.y + b.height / 2) === e;""", handle)
    ActionChains(driver, duration=20).click_and_hold(handle).move_by_offset(12, -9).pause(0.05) \
        .move_by_offset(12, -9).release().perform()
    settle(driver)
    moved = json.loads(driver.execute_script("return window.linkfit.taskText()"))["constraints"][key]
    assert moved[1][0] > float(xmax) and moved[1][1] > box[1][1], (moved, xmax, box)
    raw = driver.execute_script("return window.linkfit.taskText()")
    assert fields() == [str(v) for v in driver.execute_script(
        "const b = window.linkfit.taskTree().constraints.fixed_pivots_box; return [b[0][0].text, b[0][1].text, b[1][0].text, b[1][1].text]")], raw
    assert error_text(driver) is None


def test_layout_readable(server, browser):
    driver = browser
    load_page(driver, server)
    layout = """
      const rect = (e) => e.getBoundingClientRect();
      const $ = (id) => document.querySelector(`[data-testid="${id}"]`);
      const hint = rect($('hint')), legend = rect($('legend'));
      const notes = $('status-notes'), panel = $('notes-panel');
      const wrap = document.querySelector('.mechs-wrap'), head = rect(document.querySelector('.mechs th.violates'));
      return { overlap: hint.width > 0 && hint.right > legend.left && hint.left < legend.right &&
                        hint.bottom > legend.top && hint.top < legend.bottom,
               hintText: $('hint').textContent,
               notes: panel.hidden ? null : [...notes.children].map((li) => li.textContent),
               // Each note whole: wrapped, not cut; the panel on screen, above the status bar.
               notesClipped: [...notes.children].some((li) => li.scrollWidth > li.clientWidth + 1 ||
                   getComputedStyle(li).textOverflow === 'ellipsis' || rect(li).height < 10) ||
                   panel.scrollWidth > panel.clientWidth + 1 || rect(panel).top < 0 ||
                   rect(panel).bottom > rect($('status-bar')).top + 1,
               canvasHeight: rect($('canvas')).height,
               violatesVisible: head.width > 0 && head.right <= rect(wrap).right + 1 && wrap.scrollWidth <= wrap.clientWidth + 1,
               rows: document.querySelectorAll('[data-testid^="mechanism-row-"]').length };
    """
    height = driver.execute_script(layout)["canvasHeight"]
    for task in (SLIDER_TASK, (DATA / "four_bar_12_poses.json").read_text()):
        driver.execute_script("window.linkfit.openTask(arguments[0])", task)
        settle(driver)
        page = driver.execute_script(layout)
        notes = driver.execute_script("return window.linkfit.state.result.notes")
        assert notes and not page["overlap"] and page["notes"] is None, page
        # The canvas keeps its size with the notes; their button opens every note, whole.
        assert page["canvasHeight"] == height, page
        toggle = driver.find_element(By.CSS_SELECTOR, '[data-testid="notes-toggle"]')
        toggle.click()
        page = driver.execute_script(layout)
        assert page["notes"] == notes and not page["notesClipped"], page
        toggle.click()
        assert driver.execute_script(layout)["notes"] is None
    # Many mechanisms, each violating constraints: the "violates" column in view.
    task = json.loads((DATA / "four_bar_12_poses.json").read_text())
    task["constraints"] = {"max_link_length": 5, "min_transmission_angle_deg": 80,
                           "fixed_pivots_box": [[0, 0], [1, 1]]}
    driver.execute_script("window.linkfit.openTask(arguments[0])", json.dumps(task))
    settle(driver)
    page = driver.execute_script(layout)
    assert page["rows"] >= 8 and page["violatesVisible"] and not page["overlap"], page


def test_constrained_drag_is_fast_then_refined(server, browser):
    """Five poses with a box: while a pose is dragged the page solves at the fast level (it keeps
    up with the pointer), and on release at the task's own effort; the picture is then the API's
    answer for the moved task, its bounded least-squares fits of all five among it."""
    driver = browser
    load_page(driver, server)
    open_task(driver, ROOT / "data" / "bounded_four_bar_5_poses.json")
    handle = driver.find_element(By.CSS_SELECTOR, '[data-testid="pose-1-origin"]')
    driver.execute_script("window.linkfit.allLatencies.length = 0")
    drag(driver, handle, 10, 2, -2, 0.06, release=False)
    settle(driver)
    # Held, not yet released: the last solve was the fast level's.
    held = driver.execute_script("return window.linkfit.taskText()")
    request = urllib.request.Request(server + "api/solve?effort=fast", data=held.encode(),
                                     method="POST", headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=30) as reply:
        fast = json.loads(reply.read())
    assert_page_shows(driver, fast)
    latencies = driver.execute_script("return window.linkfit.allLatencies")
    assert latencies, "no live solve while dragging"
    ActionChains(driver).release().perform()
    settle(driver)
    released = driver.execute_script("return window.linkfit.taskText()")
    assert released == held
    full = api_solve(server, released)
    assert_page_shows(driver, full)
    assert any("least-squares fit(s) of all five" in note for note in full["notes"])
    print("constrained drag latencies (ms):", sorted(latencies))


# ---------- replies to a replaced task, a reload, the Play loop, long numbers, Delete in a drag ----------

# Every /api/solve reply held `arguments[0]` ms before the page sees it (a slow reply: a request is
# in flight when the test acts), the page's uncaught errors recorded in window.pageErrors.
HOLD_SOLVES = """
  window.pageErrors = [];
  window.addEventListener('error', (e) => window.pageErrors.push(String(e.message)));
  window.addEventListener('unhandledrejection', (e) => window.pageErrors.push(String(e.reason)));
  const hold = arguments[0];
  const fetch0 = window.fetch;
  window.fetch = async (url, options) => {
    const response = await fetch0(url, options);
    if (String(url).includes('/api/solve')) await new Promise((resolve) => setTimeout(resolve, hold));
    return response;
  };
"""


def test_delete_while_dragging_drops_the_old_reply(server, browser):
    """Three poses, one dragged (its live solve in flight), Delete: two poses, no result. The
    reply for three poses that then arrives is dropped (not drawn as current), and the pointer
    moves after the Delete throw nothing: the drag has ended."""
    from selenium.webdriver.common.keys import Keys
    driver = browser
    load_page(driver, server)
    open_task(driver, DATA / "four_bar_3_poses.json")
    assert driver.execute_script("return window.linkfit.state.result.mechanisms.length") > 0
    before = page_task(driver)["poses"]
    driver.execute_script(HOLD_SOLVES, 500)
    # The last pose: after the Delete, its index names no pose.
    handle = driver.find_element(By.CSS_SELECTOR, '[data-testid="pose-2-origin"]')
    ActionChains(driver, duration=20).click_and_hold(handle).move_by_offset(6, -4).pause(0.03) \
        .move_by_offset(6, -4).perform()
    # A solve sent, its reply held; Delete while the pose is still held.
    assert driver.execute_script("return window.linkfit.busy")
    count = driver.execute_script("return window.linkfit.solveCount")
    ActionChains(driver).send_keys(Keys.DELETE).perform()
    assert len(page_task(driver)["poses"]) == 2
    ActionChains(driver, duration=20).move_by_offset(5, 5).pause(0.03).move_by_offset(5, 5) \
        .pause(0.03).release().perform()
    settle(driver)  # the held reply has come (a solve in flight is waited for)
    state = driver.execute_script("""
        const $ = (id) => document.querySelector(`[data-testid="${id}"]`);
        return {result: window.linkfit.state.result, count: window.linkfit.solveCount,
                rows: document.querySelectorAll('[data-testid^="mechanism-row-"]').length,
                drawn: document.querySelectorAll('#layer-mechanism *, #layer-dyads *').length,
                errors: window.pageErrors, error: $('error-bar').hidden ? null : $('error-text').textContent};""")
    assert state == {"result": None, "count": count, "rows": 0, "drawn": 0, "errors": [], "error": None}, state
    assert page_task(driver)["poses"] == before[:2]  # the drag ended: no other pose moved
    # Still usable: a pose added back solves and is drawn.
    driver.execute_script("window.linkfit.openTask(arguments[0])", (DATA / "four_bar_3_poses.json").read_text())
    wait_for(lambda: driver.execute_script("return window.linkfit.state.result"), what="the solve")
    settle(driver)
    assert driver.execute_script("return window.pageErrors") == []


# Counts, from now on, the animation frames, the Play loop's tick callbacks, and the steps the
# animation advances (a full turn wraps: the shorter way round).
COUNT_TICKS = """
  const l = window.linkfit;
  const c = window.playCount = {frames: 0, ticks: 0, steps: 0, start: performance.now(), last: l.frame};
  if (!window.rafWrapped) {
    window.rafWrapped = true;
    const raf = window.requestAnimationFrame.bind(window);
    window.requestAnimationFrame = (cb) => raf((t) => { if (cb.name === 'tick') window.playCount.ticks++; cb(t); });
  }
  const n = l.state.analysis ? l.state.analysis.input_deg.length : 1;
  const frame = () => {
    if (window.playCount !== c) return;
    c.frames++;
    const d = Math.abs(l.frame - c.last);
    c.steps += Math.min(d, n - d);
    c.last = l.frame;
    requestAnimationFrame(frame);
  };
  requestAnimationFrame(frame);
"""


def test_play_runs_one_loop(server, browser):
    """Mechanisms selected quickly one after another while playing: the last one plays, in one
    loop (one tick a frame, about 60 steps a second); Pause and Play pressed within one frame
    leave one loop too, and Play / Pause still toggles."""
    driver = browser
    load_page(driver, server)
    assert driver.execute_script("return window.linkfit.state.result.mechanisms.length") >= 4
    play = driver.find_element(By.CSS_SELECTOR, '[data-testid="play"]')
    play.click()
    wait_for(lambda: driver.execute_script("return window.linkfit.playing"), what="play")

    def one_loop(what):
        driver.execute_script(COUNT_TICKS)
        time.sleep(0.5)
        count = driver.execute_script(
            "const c = window.playCount; return {...c, elapsed: performance.now() - c.start};")
        assert count["frames"] >= 10, (what, count)
        assert count["ticks"] <= count["frames"] + 1, (what, count)  # one loop
        assert 0 < count["steps"] <= count["elapsed"] * 60 / 1000 + 3, (what, count)

    driver.execute_script("""for (const i of [1, 2, 3]) {
        document.querySelector(`[data-testid="mechanism-row-${i}"]`).click(); }""")
    wait_for(lambda: driver.execute_script(
        "return window.linkfit.playing && window.linkfit.state.analysis?.mechanism === 4"),
        what="the fourth mechanism playing")
    one_loop("after selecting")
    driver.execute_script("const b = arguments[0]; b.click(); b.click();", play)  # Pause, Play
    assert driver.execute_script("return window.linkfit.playing")
    one_loop("after Pause and Play")
    play.click()
    assert not driver.execute_script("return window.linkfit.playing")
    frame = driver.execute_script("return window.linkfit.frame")
    driver.execute_script(COUNT_TICKS)
    time.sleep(0.15)
    assert driver.execute_script("return [window.linkfit.frame, window.playCount.ticks]") == [frame, 0]
    play.click()
    wait_for(lambda: driver.execute_script("return window.linkfit.frame") != frame, what="the animation again")
    play.click()
    assert not driver.execute_script("return window.linkfit.playing")


def test_long_number_saved_and_reopened(server, browser):
    """A number of 70 digits typed in the table: saved as typed, and the saved task reopens."""
    driver = browser
    load_page(driver, server)
    long = "12." + "3" * 67
    assert len(long) == 70
    cell = driver.find_element(By.CSS_SELECTOR, '[data-testid="item-0-x"]')
    driver.execute_script("arguments[0].value = arguments[1]; arguments[0].dispatchEvent(new Event('input'))",
                          cell, long)
    settle(driver)
    driver.find_element(By.CSS_SELECTOR, '[data-testid="export-task"]').click()
    saved = driver.execute_script("return window.linkfit.lastExport.text")
    assert f'"x": {long}' in saved
    driver.execute_script("window.linkfit.openTask(arguments[0])", saved)
    settle(driver)
    assert driver.execute_script("return window.linkfit.taskText()") == saved
    assert driver.execute_script("return window.linkfit.taskTree().poses[0].x.text") == long


def test_reload_cancels_long_solves(browser):
    """A page reloaded while its balanced stage runs: the server is told to stop that solve (its
    request_id is then unknown to /api/cancel), so it does not hold the one place."""
    from selenium.webdriver.support.ui import Select
    driver = browser
    with running_server("--long-solves", "1") as (url, _):
        load_page(driver, url)
        open_task(driver, DATA / "classic_path_ellipse_10_points.json")
        driver.execute_script("""
            window.sentUrls = [];
            const fetch0 = window.fetch;
            window.fetch = (u, o) => { window.sentUrls.push(String(u)); return fetch0(u, o); };""")
        Select(driver.find_element(By.CSS_SELECTOR, '[data-testid="effort"]')).select_by_visible_text("balanced")
        driver.find_element(By.CSS_SELECTOR, '[data-testid="solve"]').click()
        wait_for(lambda: driver.execute_script(
            """const li = document.querySelector('[data-testid="stage-balanced"]');
               return li && li.className === 'running';"""), timeout=10, what="the balanced stage")
        time.sleep(0.3)
        sent = [u for u in driver.execute_script("return window.sentUrls") if "effort=balanced" in u]
        assert len(sent) == 1, sent
        request_id = urllib.parse.parse_qs(urllib.parse.urlsplit(sent[0]).query)["request_id"][0]
        driver.get(url)  # balanced runs for seconds: still running unless the page had it stopped
        time.sleep(0.3)
        request = urllib.request.Request(url + f"api/cancel?request_id={request_id}", data=b"", method="POST")
        with urllib.request.urlopen(request, timeout=10) as reply:
            assert json.loads(reply.read()) == {"cancelled": False}
        assert driver.execute_async_script(
            "const done = arguments[0]; window.linkfit.ready.then(() => done(true));")
