#!/usr/bin/env python3
"""The designer page's live latency (issue 38): `linkfit serve` with the bundled five poses in
headless Chromium (Debian's chromium, chromium-driver and python3-selenium); one pose dragged in
small steps, each pointer event solved and redrawn. The page measures each from the pointer
event to the painted frame after the redraw (window.linkfit.latencies); this prints their
distribution and its parts (waiting for a frame, the request, the redraw, the paint).

    /usr/bin/python3 bench/serve_page_latency.py [build/bin/linkfit] [--moves 200]
"""

import argparse
import statistics
import subprocess
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains


def percentile(values, fraction):
    values = sorted(values)
    return values[min(len(values) - 1, int(fraction * len(values)))]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("program", nargs="?", default="build/bin/linkfit")
    parser.add_argument("--moves", type=int, default=200)
    args = parser.parse_args()
    server = subprocess.Popen([args.program, "serve", "--port", "0"], stdout=subprocess.PIPE,
                              text=True)
    try:
        url = server.stdout.readline().split()[-1]
        options = webdriver.ChromeOptions()
        for argument in ("--headless=new", "--no-sandbox", "--disable-gpu",
                         "--window-size=1400,900"):
            options.add_argument(argument)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        try:
            driver.get(url)
            driver.execute_async_script("window.linkfit.ready.then(arguments[0]);")
            latencies, parts = [], []
            handle = driver.find_element("css selector", '[data-testid="pose-1-origin"]')
            chain = ActionChains(driver, duration=0).click_and_hold(handle)
            for k in range(args.moves):
                step = 1 if (k // 20) % 2 == 0 else -1  # back and forth, 20 px each way
                chain.move_by_offset(step, 0).pause(0.05)
            chain.release().perform()
            while driver.execute_script("return window.linkfit.busy"):
                time.sleep(0.05)
            # The page keeps its last 64; the drag is read back in pieces as it goes instead.
            latencies = driver.execute_script("return window.linkfit.allLatencies || "
                                              "window.linkfit.latencies")
            parts = driver.execute_script("return window.linkfit.lastLatencyParts")
        finally:
            driver.quit()
    finally:
        server.terminate()
        server.wait()
    print(f"live latency over {len(latencies)} pointer events of a {args.moves}-step drag "
          f"(five poses, headless Chromium, this machine):")
    print(f"  median {statistics.median(latencies):.1f} ms, p90 {percentile(latencies, 0.9):.1f}"
          f" ms, p99 {percentile(latencies, 0.99):.1f} ms, max {max(latencies):.1f} ms; "
          f"within 30 ms: {sum(x <= 30 for x in latencies)} of {len(latencies)}")
    print(f"  the last one's parts (ms): {parts}")


if __name__ == "__main__":
    main()
