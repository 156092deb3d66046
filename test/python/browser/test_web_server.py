"""`rosrun kane_sim web` as a user meets it: the URL, the MIME types a browser needs, hostile
flags, a taken port, a missing build, Ctrl-C and SIGTERM."""
import os
import re
import signal
import socket
import subprocess
import time
import urllib.error
import urllib.request

import pytest


def start(*args):
    return subprocess.Popen(["rosrun", "kane_sim", "web", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def url_of(server):
    line = server.stdout.readline()
    match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    assert match, line
    return match.group(0), int(match.group(1))


def test_serves_the_page_with_the_types_a_browser_needs():
    server = start("--port", "0")
    try:
        url, _ = url_of(server)
        for name, kind in (("", "text/html"), ("kane_sim.wasm", "application/wasm"),
                           ("kane_sim.js", "text/javascript"), ("page.js", "text/javascript"),
                           ("mechanism.yaml", "text/yaml"), ("vendor/rosbag.js", "text/javascript")):
            with urllib.request.urlopen(url + name, timeout=10) as r:
                assert r.headers["Content-Type"].startswith(kind), (name, r.headers["Content-Type"])
                assert r.headers["Cache-Control"] == "no-store"
        with pytest.raises(urllib.error.HTTPError):  # nothing outside the folder
            urllib.request.urlopen(url + "../../etc/passwd", timeout=10)
    finally:
        server.send_signal(signal.SIGINT)
        assert server.wait(timeout=10) == 0  # Ctrl-C is how a user stops it


def test_sigterm_stops_it():
    server = start("--port", "0")
    url_of(server)
    server.send_signal(signal.SIGTERM)
    assert server.wait(timeout=10) == 0


@pytest.mark.parametrize("port", ["-1", "65536", "99999999999", "abc", "", "1e3", "nan"])
def test_a_bad_port_is_refused(port):
    r = subprocess.run(["rosrun", "kane_sim", "web", "--port", port], capture_output=True,
                       text=True, timeout=30)
    assert r.returncode == 2 and "--port" in r.stderr, r.stderr


def test_a_taken_port_says_so():
    taken = socket.socket()
    taken.bind(("127.0.0.1", 0))
    taken.listen(1)
    try:
        r = subprocess.run(["rosrun", "kane_sim", "web", "--port", str(taken.getsockname()[1])],
                           capture_output=True, text=True, timeout=30)
        assert r.returncode == 3 and "--port 0" in r.stderr, r.stderr
    finally:
        taken.close()


@pytest.mark.parametrize("folder", ["/nonexistent", "/dev/zero", "/tmp", ""])
def test_a_folder_that_is_not_a_built_page_is_named(folder):
    r = subprocess.run(["rosrun", "kane_sim", "web", "--dir", folder], capture_output=True,
                       text=True, timeout=30)
    assert r.returncode == 1 and "is not a built page" in r.stderr, r.stderr


def test_without_a_build_it_says_how_to_make_one(tmp_path):
    # A checkout with no build folder beside it, and no other place named.
    (tmp_path / "kane_sim" / "scripts").mkdir(parents=True)
    script = tmp_path / "kane_sim" / "scripts" / "web"
    script.write_text(open(os.path.join(os.path.dirname(__file__), "..", "..", "..", "scripts",
                                        "web")).read())
    env = {k: v for k, v in os.environ.items()
           if k not in ("KANE_SIM_WEB_DIR", "KANE_SIM_BUILD_DIR", "CMAKE_PREFIX_PATH")}
    r = subprocess.run(["/usr/bin/python3", str(script)], capture_output=True, text=True,
                       timeout=30, env=env)
    assert r.returncode == 1 and "no built page found" in r.stderr, r.stderr
    assert "bash scripts/install_deps.sh --web" in r.stderr and "bash scripts/build_web.sh" in r.stderr
