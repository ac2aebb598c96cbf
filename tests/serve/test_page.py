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
    latency = driver.execute_script("return window.linkfit.lastLatencyMs")
    parts = driver.execute_script("return window.linkfit.lastLatencyParts")
    print("live latency", latency, parts)
    assert latency is not None
    assert latency <= 30, f"live latency {latency:.1f} ms (wait, request, redraw: {parts})"
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
