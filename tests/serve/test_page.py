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
import urllib.request

import pytest

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
    chain = ActionChains(driver, duration=20).click_and_hold(handle)
    for _ in range(8):
        chain.move_by_offset(4, -3).pause(0.05)
    chain.release().perform()
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

    # A bad value typed in the table: the server's one-line message in the error bar.
    cell = driver.find_element(By.CSS_SELECTOR, '[data-testid="item-2-y"]')
    cell.clear()
    cell.send_keys("abc")
    bar = driver.find_element(By.CSS_SELECTOR, '[data-testid="error-bar"]')
    wait_for(bar.is_displayed, what="the error bar")
    assert "poses[2].y" in bar.text

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
    chain = ActionChains(driver, duration=20).click_and_hold(handle)
    for _ in range(5):
        chain.move_by_offset(4, 3).pause(0.03)
    chain.release().perform()
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
    chain = ActionChains(driver, duration=20).click_and_hold(handle)
    for _ in range(6):
        chain.move_by_offset(5, -4).pause(0.03)
    chain.release().perform()
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
