#!/usr/bin/env python3
"""The designer's picture in the README and the guide (docs/images/serve.png): `linkfit serve`
with the bundled five-pose example, its first four-bar selected and shown part way through its
cycle, in headless Chromium (Debian's chromium, chromium-driver, python3-selenium).

    /usr/bin/python3 tools/serve_screenshot.py [build/bin/linkfit] [docs/images/serve.png]
"""

import subprocess
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service


def main():
    program = sys.argv[1] if len(sys.argv) > 1 else "build/bin/linkfit"
    target = sys.argv[2] if len(sys.argv) > 2 else "docs/images/serve.png"
    server = subprocess.Popen([program, "serve", "--port", "0"], stdout=subprocess.PIPE, text=True)
    try:
        url = server.stdout.readline().split()[-1]
        options = webdriver.ChromeOptions()
        for argument in ("--headless=new", "--no-sandbox", "--disable-gpu",
                         "--window-size=1400,820", "--hide-scrollbars"):
            options.add_argument(argument)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
        try:
            driver.get(url)
            driver.execute_async_script("window.linkfit.ready.then(arguments[0]);")
            while driver.execute_script("return window.linkfit.busy"):
                time.sleep(0.05)
            driver.find_element("css selector", '[data-testid="fit-view"]').click()
            # The analysis for the animation, then a frame a third of the way round.
            driver.find_element("css selector", '[data-testid="play"]').click()
            time.sleep(1.0)
            driver.find_element("css selector", '[data-testid="play"]').click()
            time.sleep(0.2)
            driver.save_screenshot(target)
        finally:
            driver.quit()
    finally:
        server.terminate()
        server.wait()
    print(target)


if __name__ == "__main__":
    main()
