"""The browser twin's tests: `rosrun kane_sim web` serving the built page, and Debian's Chromium,
headless, driven by Selenium (python3-selenium, chromium-driver). One server and one browser for
the session; each test loads the page afresh. Any console error fails the test that caused it."""
import os
import re
import subprocess

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

HERE = os.path.dirname(os.path.abspath(__file__))

# As the machine's own browser check runs it: no first-run, sync or background traffic (this
# machine's network is closed; Chromium would retry its hosts many times a second otherwise).
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--window-size=1600,1000"]
RESULTS = os.path.join(os.environ.get("KANE_SIM_BUILD_DIR", "/tmp"), "test_results", "browser")


@pytest.fixture(scope="session")
def page_url():
    server = subprocess.Popen(["rosrun", "kane_sim", "web", "--port", "0"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    line = server.stdout.readline()
    match = re.search(r"http://127\.0\.0\.1:\d+/", line)
    if not match:
        server.kill()
        pytest.fail("rosrun kane_sim web did not print its URL: %r %s" % (line, server.stderr.read()))
    yield match.group(0)
    server.terminate()
    server.wait(timeout=10)


@pytest.fixture(scope="session")
def browser(page_url):
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    options.add_argument("--user-data-dir=%s" % os.path.join(RESULTS, "profile-%d" % os.getpid()))
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    os.makedirs(RESULTS, exist_ok=True)
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    # Bounds, not expectations: one core beside a CPU hog once took more than 120 s for a run's
    # script and 300 s (chromedriver's default) for the renderer to answer.
    driver.set_script_timeout(1200)
    driver.set_page_load_timeout(1200)
    yield driver
    driver.quit()


class Page:
    """The page loaded afresh, its hooks called as a script would."""

    def __init__(self, driver, url):
        self.driver = driver
        self.url = url
        self.load(url)

    def load(self, url):
        self.driver.get("about:blank")  # a new document even when only the #fragment differs
        self.driver.get(url)
        ready = self.call("return window.kaneSim.ready.then(() => 'ok')")
        assert ready == "ok", ready

    def call(self, body, *args):
        """An async script: `body` is a function body returning a promise or a value; its result,
        or {'rejected': message} when the promise rejects."""
        script = ("const done = arguments[arguments.length - 1];"
                  "const args = Array.from(arguments).slice(0, -1);"
                  "Promise.resolve().then(() => (function () {%s}).apply(null, args))"
                  ".then(done, (e) => done({rejected: String(e && e.message || e)}));" % body)
        return self.driver.execute_async_script(script, *args)

    def console_errors(self):
        return [e["message"] for e in self.driver.get_log("browser") if e["level"] == "SEVERE"]


@pytest.fixture
def page(browser, page_url):
    browser.get_log("browser")  # what earlier tests left
    p = Page(browser, page_url)
    yield p
    errors = p.console_errors()
    assert not errors, "console errors: %s" % errors


@pytest.fixture(scope="module")
def shared_page(browser, page_url):
    """One page for a module's many runs (the one-truth matrix): kaneSim.run starts a fresh
    worker each call, so the runs share nothing but the page."""
    browser.get_log("browser")
    p = Page(browser, page_url)
    yield p
    errors = p.console_errors()
    assert not errors, "console errors: %s" % errors
