"""Steps per second of the browser twin (WebAssembly in headless Chromium, through
window.kaneSim.run) against `simulate` on the same machine, same config, same torque, in one run.

Usage: /usr/bin/python3 bench/browser_speed.py [DURATION_S]   (after scripts/build.sh, with the
devel space sourced; prints the machine, then median-of-5 wall times and steps/s of each)
"""
import os
import re
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from machine import machine  # noqa: E402
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

DURATION = float(sys.argv[1]) if len(sys.argv) > 1 else 3600.0
TORQUE = ("--torque-sine", "1,0.5")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run"]


def main():
    print("machine:", machine())
    steps = int(round(DURATION * 1000))
    server = subprocess.Popen(["rosrun", "kane_sim", "web", "--port", "0"], stdout=subprocess.PIPE,
                              text=True)
    url = re.search(r"http://\S+/", server.stdout.readline()).group(0)
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for flag in FLAGS:
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    try:
        driver.set_script_timeout(600)
        driver.get(url)
        driver.execute_async_script("window.kaneSim.ready.then(arguments[0])")
        driver.execute_script("document.getElementById('play').click()")  # pause the live twin
        web, native, loop = [], [], []
        simulate = subprocess.run(["catkin_find", "--first-only", "kane_sim", "simulate"],
                                  capture_output=True, text=True, check=True).stdout.strip()
        for _ in range(5):
            out = driver.execute_async_script(
                "const done = arguments[1]; window.kaneSim.run({duration: arguments[0], "
                "torque: {sine: '1,0.5'}, outputRate: 1}).then(done, (e) => done(String(e)))",
                DURATION)
            web.append(out["wallSeconds"])
            start = time.perf_counter()
            r = subprocess.run([simulate, "--duration", str(DURATION), "--output-rate", "1",
                                *TORQUE], check=True, capture_output=True, text=True)
            native.append(time.perf_counter() - start)
            loop.append(float(re.search(r"wall time ([0-9.e+-]+) s", r.stderr).group(1)))
        w, n = statistics.median(web), statistics.median(native)
        print("%d physics steps (rk4, 1 kHz, %g s of sim time), median of 5:" % (steps, DURATION))
        print("  Chromium %s, WebAssembly: %.3f s, %.2f M steps/s"
              % (driver.capabilities.get("browserVersion"), w, steps / w / 1e6))
        l = statistics.median(loop)
        print("  simulate (native), whole process: %.3f s, %.2f M steps/s; its loop alone "
              "(simulate's own wall time): %.3f s, %.2f M steps/s" % (n, steps / n / 1e6, l,
                                                                   steps / l / 1e6))
        print("  browser / native: %.2f (whole process), %.2f (loop)" % (w / n, w / l))
    finally:
        driver.quit()
        server.terminate()


if __name__ == "__main__":
    main()
