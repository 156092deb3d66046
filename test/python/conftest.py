"""Shared by the Python module's tests (pytest, run by ctest after the build with the devel space
sourced): the package's configs, the `simulate` and `analyze` executables, a scratch folder."""
import os
import signal
import subprocess

import pytest

import kane_sim

# Ctrl-C's tests send SIGINT to this process and expect KeyboardInterrupt. A test run started in
# the background of a non-interactive shell (`cmd &`, nohup) inherits SIGINT ignored, and Python
# then installs no handler: those tests waited for an interrupt that never came. Python's own.
signal.signal(signal.SIGINT, signal.default_int_handler)

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG_DIR = os.path.join(HERE, "..", "..", "config")


def config_path(name="mechanism.yaml"):
    return os.path.join(CONFIG_DIR, name)


def tool(name):
    """A built executable (ctest passes the build folder in KANE_SIM_BUILD_DIR)."""
    path = os.path.join(os.environ["KANE_SIM_BUILD_DIR"], "devel", "lib", "kane_sim", name)
    assert os.path.exists(path), path
    return path


def run_tool(name, *args, check=True):
    r = subprocess.run([tool(name), *map(str, args)], capture_output=True, text=True,
                       timeout=300)
    if check:
        assert r.returncode == 0, r.stderr
    return r


@pytest.fixture
def sim():
    return kane_sim.Simulator(config_path())
