"""The browser twin in headless Chromium: the page loads and draws, its runs are simulate's runs,
it refuses what simulate refuses with the same words, opens bags, shares runs, and keeps running
while a run is stopped."""
import copy
import io
import itertools
import os
import subprocess
import sys

import numpy as np
import pytest
import rosbag
import yaml
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from conftest import config_path, run_tool, tool  # noqa: E402 (the Python tests' helpers)
from page_fixtures import (RESULTS, Page, browser, page, page_url,  # noqa: E402,F401
                           shared_page)
from test_one_truth import MODES, SINE, case_config  # noqa: E402 (the one-truth matrix)

MUSL = "/usr/share/emscripten/system/lib/libc/musl"
# The math the equations call beyond the written-out forms (sin, cos, sincos beyond 1e14), as
# emscripten's musl computes it; tanh (with its expm1) for the library's vector calls.
MUSL_MATH = ("sin", "cos", "sincos", "__sin", "__cos", "__rem_pio2", "__rem_pio2_large", "tanh",
             "expm1")


@pytest.fixture(scope="session")
def musl_math(tmp_path_factory):
    """musl's sin/cos/tanh from emscripten's own copy, built natively as a library that
    LD_PRELOAD puts in place of the native build's math functions (SLEEF's, answered by
    musl_for_sleef.c): `simulate` then computes with the page's libm."""
    folder = tmp_path_factory.mktemp("musl")
    out = str(folder / "libmusl_math.so")
    sources = [os.path.join(MUSL, "src", "math", name + ".c") for name in MUSL_MATH]
    include = subprocess.run(["gcc", "-print-file-name=include"], capture_output=True, text=True,
                             check=True).stdout.strip()
    objects = []
    for source in sources:
        objects.append(str(folder / (os.path.basename(source) + ".o")))
        subprocess.run(["gcc", "-O2", "-fPIC", "-c", "-w", "-ffp-contract=off", "-fno-builtin",
                        "-D_GNU_SOURCE", "-nostdinc", "-isystem", include,
                        "-I" + MUSL + "/src/internal", "-I" + MUSL + "/src/include",
                        "-I" + MUSL + "/include", "-I" + MUSL + "/arch/generic",
                        "-I" + MUSL + "/arch/emscripten", source, "-o", objects[-1]], check=True)
    shim = os.path.join(os.path.dirname(os.path.abspath(__file__)), "musl_for_sleef.c")
    subprocess.run(["gcc", "-O2", "-fPIC", "-shared", "-Wall", "-Werror", "-fno-builtin", shim,
                    *objects, "-o", out], check=True)
    return out


def simulate_rows(cfg, duration, flags, preload=None):
    env = dict(os.environ)
    if preload:
        env["LD_PRELOAD"] = preload
    r = subprocess.run([tool("simulate"), "--config", cfg, "--duration", str(duration),
                        "--output-rate", "100", *flags], capture_output=True, text=True, env=env,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    return lines[0].split(","), np.array([[float(v) for v in l.split(",")] for l in lines[1:]])


def page_rows(page, cfg_text, duration, torque):
    out = page.call("return window.kaneSim.run({config: args[0], duration: args[1], "
                    "torque: args[2], outputRate: 100})", cfg_text, duration, torque)
    assert "rejected" not in out, out
    return out["columns"], np.array(out["rows"], dtype=float)


CASES = list(itertools.product(MODES, (False, True), (False, True), (False, True)))


@pytest.mark.parametrize("mode,profile,sensors,contact", CASES)
def test_a_run_is_simulates_run(shared_page, tmp_path, musl_math, mode, profile, sensors,
                                contact):
    page = shared_page
    cfg = case_config(tmp_path, mode, sensors, contact)
    torque = {"sine": "%r,%r,%r" % SINE[mode]} if profile else None
    flags = ["--torque-sine", torque["sine"]] if profile else []
    duration = 2.0
    columns, web = page_rows(page, open(cfg).read(), duration, torque)
    header, musl = simulate_rows(cfg, duration, flags, preload=musl_math)
    assert columns == header
    # The same C++ on the same numbers: with the same libm, every column of every row is equal.
    same = (web == musl) | (np.isnan(web) & np.isnan(musl))
    assert same.all(), "first differing row %d" % np.argmin(same.all(axis=1))
    # simulate with its own math functions: both builds run the same written-out sincos and
    # tanh (model/math_functions.h) while |q1| < 1e14, so every bit is equal with no stand-in
    # at all, friction (the one-truth matrix's comes with contact) included.
    _, native = simulate_rows(cfg, duration, flags)
    same = (web == native) | (np.isnan(web) & np.isnan(native))
    assert same.all(), "first differing row %d" % np.argmin(same.all(axis=1))


def simulate_error(tmp_path, text):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    r = run_tool("simulate", "--config", path, "--duration", "1", check=False)
    assert r.returncode == 1, r.stderr
    line = r.stderr.strip().splitlines()[-1]
    prefix = "error: %s: " % path
    assert line.startswith(prefix), line
    # Where simulate names the file, the page names the text it was given.
    return line[len(prefix):].replace(str(path), "the given config")


HOSTILE_CONFIGS = {
    "negative mass": "mechanism: {rod_mass: -1}",
    "NaN stiffness": "mechanism: {spring_stiffness: .nan}",
    "1e308 gravity": "mechanism: {gravity: 1e308}",
    "a typo'd integrator": "simulation: {integrator: rk5}",
    "two documents": "mechanism: {rod_mass: 1}\n---\nsimulation: {}",
    "broken YAML": "mechanism: {rod_mass: [1",
    "a list, not a map": "- 1\n- 2",
    "empty": "",
}


@pytest.mark.parametrize("label", sorted(HOSTILE_CONFIGS))
def test_a_bad_config_is_refused_with_simulates_words(shared_page, tmp_path, label):
    page = shared_page
    base = yaml.safe_load(open(config_path()))
    text = HOSTILE_CONFIGS[label]
    patch = None
    try:
        patch = yaml.safe_load(text)
    except yaml.YAMLError:
        pass
    if isinstance(patch, dict) and label != "two documents":  # one key wrong, the rest good
        for section, values in patch.items():
            base.setdefault(section, {}).update(values)
        text = yaml.safe_dump(base)
    expected = simulate_error(tmp_path, text)
    out = page.call("return window.kaneSim.run({config: args[0], duration: 1})", text)
    assert out == {"rejected": "the given config: " + expected}


@pytest.mark.parametrize("options,named", [
    ("{duration: NaN}", "duration"), ("{duration: -1}", "duration"),
    ("{duration: 1e308}", "duration"), ("{duration: Infinity}", "duration"),
    ("{outputRate: 0}", "outputRate"), ("{outputRate: 333}", "outputRate"),
    ("{outputRate: -Infinity}", "outputRate"), ("{torque: {sine: 'x'}}", "--torque-sine"),
    ("{torque: {sideways: 1}}", "torque"), ("{torque: [[0, 1], [1]]}", "torque"),
    ("{torque: [[0, 1], [-1, 2]]}", "torque"), ("{torque: '1e999'}", "torque"),
    ("{torque: NaN}", "torque"), ("{torque: [[0, NaN]]}", "torque"),
    # Never coerced: Number("") is 0, Number(true) 1, Number("0x10") 16 (simulate refuses 0x10).
    ("{duration: ''}", "duration"), ("{duration: null}", "duration"), ("{duration: true}", "duration"),
    ("{duration: [2]}", "duration"), ("{outputRate: null}", "outputRate"),
    ("{torque: '0x10'}", "torque"), ("{torque: {sine: {a: 1}}}", "torque"), ("5", "kaneSim.run"),
    ("'str'", "kaneSim.run"), ("{config: 5}", "config"),
    ("{config: '['.repeat(1000) + ']'.repeat(1000)}", "nested too deeply"),
])
def test_bad_run_arguments_are_refused_by_name(shared_page, options, named):
    page = shared_page
    out = page.call("return window.kaneSim.run(%s)" % options)
    assert "rejected" in out and named in out["rejected"], out


def make_bag(tmp_path, config="mechanism.yaml"):
    path = str(tmp_path / "run.bag")
    run_tool("simulate", "--config", config_path(config), "--duration", "2",
             "--torque-sine", "1,0.5", "--bag", path)
    return path


def open_bag(page, data):
    return page.call("const bytes = Uint8Array.from(atob(args[0]), (c) => c.charCodeAt(0));"
                     "return window.kaneSim.openBag(bytes.buffer)",
                     __import__("base64").b64encode(data).decode())


@pytest.mark.parametrize("config", ["mechanism.yaml", "sensors.yaml"])
def test_a_bag_opens_with_every_joint_state(page, tmp_path, config):
    if config == "sensors.yaml":  # sensors on: joint_states are the sensors' readings
        cfg = yaml.safe_load(open(config_path()))
        cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
        (tmp_path / "sensors.yaml").write_text(yaml.safe_dump(cfg))
        path = str(tmp_path / "run.bag")
        run_tool("simulate", "--config", tmp_path / "sensors.yaml", "--duration", "2",
                 "--torque-sine", "1,0.5", "--bag", path)
    else:
        path = make_bag(tmp_path)
    with rosbag.Bag(path) as bag:
        stamps = [m.header.stamp.to_sec() for _, m, _ in bag.read_messages(["/joint_states"])]
    out = open_bag(page, open(path, "rb").read())
    assert out["states"] == len(stamps) > 0, out
    assert out["t0"] == pytest.approx(stamps[0]) and out["t1"] == pytest.approx(stamps[-1])
    shown = page.call("return window.kaneSim.shown()")
    assert shown["states"] == len(stamps)
    # The plots' time is sim time, one t per row: the last row is the run's last (t = 2 s).
    final = run_tool("simulate", "--config", tmp_path / "sensors.yaml" if config == "sensors.yaml"
                     else config_path(), "--duration", "2", "--torque-sine", "1,0.5").stdout
    last = [float(v) for v in final.splitlines()[-1].split(",")[:3]]
    assert shown["last"] == last


def test_one_set_of_controls_for_what_is_shown(page, tmp_path):
    """A bag on show: the recording's controls (Play, Step, its time, Live), not the hidden live
    mechanism's; Step moves the recording one sample; Live brings the live controls back."""
    open_bag(page, open(make_bag(tmp_path), "rb").read())
    shown = lambda id_: page.call("return !document.getElementById(args[0]).hidden", id_)  # noqa
    assert shown("replay") and not shown("controls") and not shown("command-row")
    before = page.call("return window.kaneSim.shown().at")
    page.driver.find_element("id", "replay-step").click()
    after = page.call("return new Promise((r) => setTimeout(() => r(window.kaneSim.shown().at), 300))")
    assert after > before, (before, after)
    page.driver.find_element("id", "replay-close").click()
    assert shown("controls") and shown("command-row") and not shown("replay")


def test_a_bag_of_mechanism_states_only_replays(page, tmp_path):
    path = make_bag(tmp_path)
    only = str(tmp_path / "states.bag")
    with rosbag.Bag(path) as bag, rosbag.Bag(only, "w") as out:
        for topic, message, stamp in bag.read_messages(["/mechanism_state"]):
            out.write(topic, message, stamp)
    out = open_bag(page, open(only, "rb").read())
    assert out["states"] == 0 and out["topics"]["state"] == "/mechanism_state", out
    shown = page.call("return window.kaneSim.shown()")
    assert shown["last"][0] == 2.0 and all(np.isfinite(shown["last"])), shown


@pytest.mark.parametrize("label,cut,words", [
    ("truncated", lambda b: b[: len(b) // 2], "truncated"),
    ("zeros", lambda b: bytes(1 << 20), "not a ROS 1 bag"),
    ("empty", lambda b: b"", "not a ROS 1 bag"),
    ("a CSV", lambda b: b"t,q1\n0,1\n", "not a ROS 1 bag"),
    ("cut in its index", lambda b: b[:-2000], "cut short"),
])
def test_a_bad_bag_gets_a_clear_message(page, tmp_path, label, cut, words):
    data = cut(open(make_bag(tmp_path), "rb").read())
    out = open_bag(page, data)
    assert "rejected" in out and words in out["rejected"], out


def test_the_page_draws_the_mechanism_and_its_plots(page):
    page.call("return new Promise((r) => setTimeout(r, 1500))")  # the live mechanism moves
    live = page.call("return window.kaneSim.live()")
    assert live["running"] and live["rows"] > 50, live
    os.makedirs(RESULTS, exist_ok=True)
    shot = os.path.join(RESULTS, "page.png")
    page.driver.save_screenshot(shot)
    image = Image.open(shot).convert("RGB")
    canvas = page.driver.find_element("id", "mechanism").rect
    view = image.crop((int(canvas["x"]), int(canvas["y"]), int(canvas["x"] + canvas["width"]),
                       int(canvas["y"] + canvas["height"])))
    pixels = np.asarray(view).reshape(-1, 3).astype(int)
    # The rods' blue and the sliders' orange (the robot description's materials) are drawn.
    blue = np.sum((pixels[:, 2] > 150) & (pixels[:, 0] < 100))
    orange = np.sum((pixels[:, 0] > 200) & (pixels[:, 1] > 100) & (pixels[:, 1] < 180)
                    & (pixels[:, 2] < 80))
    assert blue > 500 and orange > 200, (blue, orange)
    plots = page.driver.find_element("id", "plots").rect
    area = np.asarray(image.crop((int(plots["x"]), int(plots["y"]),
                                  int(plots["x"] + plots["width"]),
                                  int(plots["y"] + min(plots["height"], 700)))))
    # Curves, not blank panels: the first two plot colours (q1's blue, u2's orange) drawn.
    for rgb in ((0x1f, 0x77, 0xb4), (0xff, 0x7f, 0x0e)):
        drawn = np.sum(np.all(np.abs(area[..., :3].astype(int) - rgb) < 40, axis=-1))
        assert drawn > 200, (rgb, drawn)  # measured 807 and 536; the legend text alone ~50


def test_the_parameter_panel_refuses_with_the_loaders_words(page):
    field = page.driver.find_element("css selector", "input[data-parameter=spring_stiffness]")
    enter = "arguments[0].value = arguments[1]; arguments[0].dispatchEvent(new Event('change'))"
    page.driver.execute_script(enter, field, "-5")
    messages = page.call("return new Promise((r) => setTimeout(() => r("
                         "document.getElementById('messages').textContent), 300))")
    assert "mechanism.spring_stiffness" in messages and "-5" in messages, messages
    # On screen, wherever the page is scrolled, at a laptop's 1400x900 too.
    page.driver.set_window_size(1400, 900)
    page.driver.execute_script("window.scrollTo(0, 0)")
    box = page.call("const r = document.getElementById('messages').firstChild"
                    ".getBoundingClientRect(); return [r.top, r.bottom, window.innerHeight]")
    page.driver.set_window_size(1600, 1000)  # the fixture's size, for the tests after this one
    assert 0 <= box[0] < box[1] <= box[2], box
    assert field.get_attribute("value") == "200"
    page.driver.execute_script(enter, field, "300")
    config = page.call("return new Promise((r) => setTimeout(() => r("
                       "document.getElementById('config').value), 300))")
    assert yaml.safe_load(config)["mechanism"]["spring_stiffness"] == 300


@pytest.mark.parametrize("text,words", [
    ("abc", "initial_state.q1: 'abc' is not a number"),
    ("", "initial_state.q1: '' is not a number"),
    ("0x10", "initial_state.q1: '0x10' is not a number"),  # Number() would take it as 16
    ("1,5", "initial_state.q1: '1,5' is not a number"),
    ("nan", "config key 'initial_state.q1' must be finite"),  # the loader's words
    ("1e999", "config key 'initial_state.q1' must be finite"),
    ("-inf", "config key 'initial_state.q1' must be finite"),
])
def test_the_initial_state_refuses_what_the_loader_refuses(page, text, words):
    field = page.driver.find_element("css selector", "input[data-initial=q1]")
    before = field.get_attribute("value")
    enter = "arguments[0].value = arguments[1]; arguments[0].dispatchEvent(new Event('change'))"
    page.driver.execute_script(enter, field, text)
    messages = page.call("return new Promise((r) => { const poll = () => { const m = "
                         "document.getElementById('messages').textContent; "
                         "m.includes(args[0]) ? r(m) : setTimeout(poll, 50); }; poll(); })", words)
    assert words in messages, messages
    assert field.get_attribute("value") == before
    assert yaml.safe_load(page.call("return document.getElementById('config').value"))[
        "initial_state"]["q1"] == pytest.approx(float(before))


def test_the_initial_state_restarts_the_motion_there(page):
    """A teacher sets the crank at 1 rad, at rest: the mechanism restarts there (the config says
    so, the drawing and the plots start over), and a run of the config agrees."""
    # Paused after it ran (the clock then stands still, whatever the machine's speed).
    page.call("return new Promise((r) => { const poll = () => window.kaneSim.live().time > 0 ? "
              "r() : setTimeout(poll, 50); poll(); })")
    page.driver.find_element("id", "play").click()
    assert not page.call("return window.kaneSim.live()")["running"]
    field = page.driver.find_element("css selector", "input[data-initial=q1]")
    enter = "arguments[0].value = arguments[1]; arguments[0].dispatchEvent(new Event('change'))"
    page.driver.execute_script(enter, field, "1")
    messages = page.call("return new Promise((r) => { const poll = () => { const m = "
                         "document.getElementById('messages').textContent; "
                         "m.includes('restarted') ? r(m) : setTimeout(poll, 50); }; poll(); })")
    assert "initial_state.q1 = 1: the motion restarted there" in messages, messages
    config = yaml.safe_load(page.call("return document.getElementById('config').value"))
    assert config["initial_state"]["q1"] == 1.0
    assert page.call("return window.kaneSim.live()")["time"] == 0.0  # restarted, still paused
    out = page.call("return window.kaneSim.run({duration: 0.5})")
    assert out["rows"][0][1] == 1.0, out["rows"][0]


def test_a_share_link_opens_the_same_run(page):
    url = page.call("return window.kaneSim.shareLink()")
    assert "#run=" in url
    expected = page.call("return window.kaneSim.run({duration: 10, torque: {sine: '1,0.5'}, "
                         "outputRate: 100})")
    page.load(url)  # as a second browser would: the link alone
    shown = page.call("return new Promise((resolve) => { const poll = () => { const s = "
                      "window.kaneSim.shown(); if (s && s.label === 'this run') resolve(s); "
                      "else setTimeout(poll, 100); }; poll(); })")
    assert shown["states"] == len(expected["rows"])
    assert shown["last"] == expected["rows"][-1][:3]


def test_two_runs_overlaid(page):
    """k = 200, then k = 1000 with the overlay ticked: the second run is shown with the first
    drawn under it; each is simulate's run of its own config."""
    panel = lambda k: page.driver.execute_script(  # noqa: E731
        "const f = document.querySelector('input[data-parameter=spring_stiffness]');"
        "f.value = arguments[0]; f.dispatchEvent(new Event('change'))", str(k))
    def run_and_wait():
        page.driver.find_element("id", "run").click()
        return page.call("return new Promise((resolve) => { const poll = () => { const s = "
                         "window.kaneSim.shown(); if (s && s.label === 'this run' && "
                         "s.at !== undefined) resolve(s); else setTimeout(poll, 100); }; "
                         "setTimeout(poll, 300); })")
    panel(200)
    first = run_and_wait()
    assert first["overlay"] is None
    page.driver.find_element("id", "replay-close").click()  # live again: shown() is null
    page.driver.find_element("id", "run-overlay").click()
    panel(1000)
    page.call("return new Promise((r) => setTimeout(r, 300))")
    second = run_and_wait()
    assert second["overlay"] == first["last"], (first, second)
    assert second["last"] != first["last"]  # a stiffer spring, another motion


def test_a_long_run_stops_and_the_page_stays_live(page):
    started = page.call("window.__run = window.kaneSim.run({duration: 1e6, outputRate: 0.1})"
                        ".then((r) => 'finished', (e) => 'rejected: ' + e.message);"
                        "return new Promise((r) => setTimeout(() => r(true), 500))")
    assert started
    page.driver.find_element("id", "run-stop").click()
    assert page.call("return window.__run") == "rejected: stopped by the Stop button"
    assert page.call("return window.kaneSim.live()")["running"]


def drop_file(page, name, data):
    """A file dropped on the page, as a user drags one from the file manager."""
    page.driver.execute_script(
        "const bytes = Uint8Array.from(atob(arguments[1]), (c) => c.charCodeAt(0));"
        "const files = new DataTransfer(); files.items.add(new File([bytes], arguments[0]));"
        "document.getElementById('drop').dispatchEvent(new DragEvent('drop', "
        "{dataTransfer: files, bubbles: true, cancelable: true}));",
        name, __import__("base64").b64encode(data).decode())
    return page.call("return new Promise((resolve) => { const poll = () => { const s = "
                     "window.kaneSim.shown(); const m = document.getElementById('messages')"
                     ".textContent; if (s || m) resolve({shown: s, messages: m}); "
                     "else setTimeout(poll, 100); }; poll(); })")


def test_a_dropped_csv_and_bag_replay(page, tmp_path):
    csv = run_tool("simulate", "--duration", "3", "--torque-sine", "1,0.5").stdout
    rows = [l.split(",") for l in csv.splitlines()[1:]]
    out = drop_file(page, "run.csv", csv.encode())
    assert out["shown"]["states"] == len(rows) == 301, out
    assert out["shown"]["last"] == [float(v) for v in rows[-1][:3]]
    out = drop_file(page, "run.bag", open(make_bag(tmp_path), "rb").read())
    assert out["shown"]["label"] == "run.bag" and out["shown"]["states"] > 0, out
    # The time slider poses the mechanism at the chosen instant.
    page.driver.execute_script("const s = document.getElementById('replay-time'); "
                               "s.value = 10; s.dispatchEvent(new Event('input'))")
    label = page.call("return new Promise((r) => setTimeout(() => "
                      "r(document.getElementById('replay-label').textContent), 300))")
    assert label.startswith("run.bag: 11 / "), label


def test_a_dropped_file_that_is_neither_is_named(page):
    out = drop_file(page, "notes.csv", b"time,angle\n0,1\n")
    assert out["shown"] is None and out["messages"].count("no 't' column") == 1, out


@pytest.mark.parametrize("text,words", [
    ("t,q1,q2\n0,nan,nan\n1,nan,nan\n", "not finite"),
    ("t,q1,q2\n0,Infinity,1\n", "not a number"), ("t,q1,q2\n0,0x1,1\n", "not a number"),
    ("t,q1,q2\n1,0,0\n0,0,0\n", "comes before"), ("t,q1,q2\n0,1\n", "has 2 values"),
    ("t,q1,q2\n", "no rows"), ("", "no rows"),
])
def test_a_csv_that_cannot_be_replayed_is_named(page, text, words):
    out = page.call("return window.kaneSim.openCsv(args[0])", text)
    assert "rejected" in out and words in out["rejected"], out


def share_url(page_url, state, checksum=True):
    """A share link as the page writes one: the state's JSON and its CRC-32 (zlib's is the same
    IEEE polynomial), deflate-raw, base64url; checksum=False: the bare state, no envelope."""
    import base64
    import json
    import zlib
    run = json.dumps(state)
    envelope = json.dumps({"run": run, "crc32": "%08x" % zlib.crc32(run.encode())}) if checksum \
        else run
    packer = zlib.compressobj(wbits=-15)
    packed = packer.compress(envelope.encode()) + packer.flush()
    return page_url + "#run=" + base64.urlsafe_b64encode(packed).decode().rstrip("=")


def _good_state():
    return {"config": open(config_path()).read(), "duration": "1", "outputRate": "100",
            "torqueKind": "none", "torqueText": ""}


def _tampered(page_url):
    """A good link with one character in its middle changed, as a mangled paste does."""
    url = share_url(page_url, _good_state())
    head, fragment = url.split("#run=")
    middle = len(fragment) // 2
    other = "A" if fragment[middle] != "A" else "B"
    return head + "#run=" + fragment[:middle] + other + fragment[middle + 1:]


@pytest.mark.parametrize("fragment,words", [
    ("AAAAbbbbCCCC", "not a kane_sim share link"), ("@@@!!!", "characters a share link never"),
    (None, "config is refused"), ({"config": 5}, "no config text"), (5, "no run"),
    ("tampered", "changed"), ("no checksum", "carries no checksum"),
])
def test_a_bad_share_link_opens_the_defaults_and_says_why(browser, page_url, fragment, words):
    if fragment is None:  # a config the loader refuses
        cfg = yaml.safe_load(open(config_path()))
        cfg["mechanism"]["rod_mass"] = -1
        url = share_url(page_url, {"config": yaml.safe_dump(cfg), "duration": "1",
                                   "outputRate": "100", "torqueKind": "none", "torqueText": ""})
    elif fragment == "tampered":
        url = _tampered(page_url)
    elif fragment == "no checksum":
        url = share_url(page_url, _good_state(), checksum=False)
    elif isinstance(fragment, str):
        url = page_url + "#run=" + fragment
    else:
        url = share_url(page_url, fragment)
    browser.get_log("browser")
    page = Page(browser, url)  # ready: the page runs on the defaults
    messages = page.call("return document.getElementById('messages').textContent")
    assert words in messages and "the default config is loaded" in messages, messages
    assert page.call("return window.kaneSim.live()")["running"]
    assert not page.console_errors()


def test_a_torque_beyond_the_limit_is_shown_clamped_and_said_once(page):
    """1e9 N m typed into the live torque: the field shows the 50 N m applied (the config's
    command.torque_limit), the slider's range is that limit from the first load, and the clamp
    is one message, counted, that does not push the others out while it goes on."""
    limit = yaml.safe_load(open(config_path()))["command"]["torque_limit"]
    assert page.call("return Number(document.getElementById('command').max)") == limit
    for _ in range(3):
        page.driver.execute_script("const f = document.getElementById('command-value');"
                                   "f.value = '1e9'; f.dispatchEvent(new Event('change'))")
    page.call("return new Promise((r) => setTimeout(r, 1000))")  # frames go by
    assert page.call("return Number(document.getElementById('command-value').value)") == limit
    texts = page.call("return [...document.getElementById('messages').children]"
                      ".map((d) => d.textContent)")
    clamps = [t for t in texts if "clamped" in t]
    assert len(clamps) <= 2, texts  # the page's own note, and at most one of the driver's
    assert any("1000000000 N m clamped to %g N m" % limit in t and "(×3)" in t for t in clamps), texts


def red_arc_pixels(page):
    """The torque arrow's red (#d1242f) pixels in the drawing, the page paused."""
    shot = os.path.join(RESULTS, "torque_arc.png")
    os.makedirs(RESULTS, exist_ok=True)
    page.driver.save_screenshot(shot)
    canvas = page.driver.find_element("id", "mechanism").rect
    view = np.asarray(Image.open(shot).convert("RGB").crop(
        (int(canvas["x"]), int(canvas["y"]), int(canvas["x"] + canvas["width"]),
         int(canvas["y"] + canvas["height"])))).astype(int)
    return int(np.sum(np.all(np.abs(view - (0xd1, 0x24, 0x2f)) < 30, axis=-1)))


def test_a_small_torque_is_a_visible_arrow(page):
    """2 N m under the 50 N m limit reads as an arrow, larger torques draw longer ones. Red pixels
    (arc, head and value label) at 2 N m against 50 N m, measured: 96 / 242 = 0.40 with the arc
    growing as the root of the torque; 44 / 240 = 0.18 when it grew linearly (a speck of
    0.2 rad of arc)."""
    pixels = {}
    for torque in (2, 50):
        page.driver.execute_script("const f = document.getElementById('command-value');"
                                   "f.value = arguments[0]; f.dispatchEvent(new Event('change'))",
                                   str(torque))
        page.call("return new Promise((r) => setTimeout(r, 300))")
        pixels[torque] = red_arc_pixels(page)
    assert 0.3 * pixels[50] < pixels[2] < pixels[50], pixels


def test_switching_the_drive_goes_on_from_the_same_instant(page):
    page.call("return new Promise((r) => setTimeout(r, 800))")
    before = page.call("return window.kaneSim.live()")
    page.driver.execute_script("const m = document.getElementById('mode'); m.value = 'position';"
                               "m.dispatchEvent(new Event('change'))")
    after = page.call("return new Promise((r) => setTimeout(() => r(window.kaneSim.live()), 500))")
    assert after["time"] > before["time"] > 0.3, (before, after)
    assert after["rows"] > before["rows"]  # the plots go on, not restarted


def test_a_bag_of_a_node_started_paused_keeps_its_joint_states_on_sim_time(page, tmp_path):
    """A node started paused (the demo's bags) publishes states stamped by the wall clock while its
    sim time stays 0: each joint_states is placed at its state's sim time (the same stamp), so the
    replay starts at t = 0 on the plots' axis, not before it, and the info line says sim time."""
    import rospy
    path, paused = make_bag(tmp_path), str(tmp_path / "paused.bag")
    with rosbag.Bag(path) as bag:
        messages = list(bag.read_messages())
    first = {topic: message for topic, message, _ in reversed(messages)}
    waiting = 30  # 0.3 s of wall time at 100 Hz before the clock runs
    with rosbag.Bag(paused, "w") as out:
        for k in range(waiting, 0, -1):
            for topic in ("/joint_states", "/mechanism_state"):
                message = copy.deepcopy(first[topic])
                message.header.stamp -= rospy.Duration(0.01 * k)
                out.write(topic, message, message.header.stamp)
        for topic, message, stamp in messages:
            out.write(topic, message, stamp)
    out = drop_file(page, "paused.bag", open(paused, "rb").read())
    shown = page.call("return window.kaneSim.shown()")
    assert shown["at"] == 0.0, shown
    assert "sim time 0.000 to 2.000 s" in out["messages"], out
    # Every joint_states of the waiting ticks is at t = 0; the last is at the run's end.
    for index, want in ((waiting - 1, 0.0), (waiting + 1, 0.01), (None, 2.0)):
        page.driver.execute_script(
            "const s = document.getElementById('replay-time'); s.value = arguments[0] === null ? "
            "s.max : arguments[0]; s.dispatchEvent(new Event('input'))", index)
        at = page.call("return new Promise((r) => setTimeout(() => "
                       "r(window.kaneSim.shown().at), 300))")
        assert at == pytest.approx(want, abs=1e-12), (index, at)


def test_the_downloaded_csv_is_simulates_csv(page, musl_math):
    """Download CSV's text, byte for byte simulate's (with the browser's libm)."""
    page.call("return window.kaneSim.run({duration: 2, torque: {sine: '1,0.5'}, outputRate: 50})")
    text = page.call("return window.kaneSim.csv()")
    r = subprocess.run([tool("simulate"), "--config", config_path(), "--duration", "2",
                        "--output-rate", "50", "--torque-sine", "1,0.5"], capture_output=True,
                       text=True, env=dict(os.environ, LD_PRELOAD=musl_math), timeout=60)
    assert r.returncode == 0 and text == r.stdout
