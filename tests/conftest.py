"""Shared test set-up.

Markers: `slow` marks heavy physics checks. The default run (`python -m pytest -q`) runs every
test, slow ones included; `-m "not slow"` skips them. A default per-test timeout is set in
pytest.ini (pytest-timeout); a test may ask for more with @pytest.mark.timeout(seconds).

ROS 2: every test run gets its own ROS_DOMAIN_ID (so that two runs on one machine do not hear
each other) and keeps DDS discovery on this machine (ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST:
no multicast on the network). Child processes inherit both.
"""
import os
import selectors
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest


def ros_domain_id():
    """A ROS domain of this test run (1..100, the range DDS's default ports allow): with pytest-xdist one
    per worker, the workers of one run never sharing one; without it, one from the process id."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if worker is None:
        return 1 + os.getpid() % 100
    run = int(os.environ["PYTEST_XDIST_TESTRUNUID"], 16)
    return 1 + (run % 25) * 4 + int(worker.removeprefix("gw")) % 4


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: heavy physics check (minutes); skip with -m 'not slow'")
    os.environ["ROS_DOMAIN_ID"] = str(ros_domain_id())
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    os.environ.pop("ROS_STATIC_PEERS", None)


def _default_sigint():
    # A child started from a non-interactive shell's background job inherits SIGINT ignored;
    # restore the default so that Ctrl-C / SIGINT reaches it.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.fixture
def spawn():
    """Start a child process (text pipes, own process group); every child is stopped at teardown."""
    children = []

    def start(args, **kwargs):
        child = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                 start_new_session=True, preexec_fn=_default_sigint, **kwargs)
        children.append(child)
        return child

    yield start
    for child in children:
        if child.poll() is None:
            child.kill()
        child.communicate(timeout=10)


@pytest.fixture
def venv_bin():
    """The bin/ folder of the environment the tests run in (the .venv), with the console scripts."""
    return Path(sys.executable).parent


@pytest.fixture
def read_until():
    """read_until(child, text, timeout): lines that a spawned child printed on stderr up to the
    first one containing `text`; fails the test on timeout or if the child exits first."""
    return _read_until


# how long a spawned node may take to say it is up, on a machine whose cores are busy (the suite beside a long
# evaluation)
STARTUP_S = 180.0


def _read_until(child, text, timeout):
    lines = []
    deadline = time.monotonic() + timeout
    fd = child.stderr.fileno()
    with selectors.DefaultSelector() as selector:
        selector.register(fd, selectors.EVENT_READ)
        while not any(text in line for line in lines):
            line = b""
            # byte by byte from the pipe itself: a buffered readline would take the lines after this one into
            # its buffer, where the selector no longer sees them (a node's "monitoring" line was lost so)
            while not line.endswith(b"\n"):
                remaining = deadline - time.monotonic()
                so_far = lines + [line.decode(errors="replace")]
                assert remaining > 0, f"no {text!r} within {timeout} s; stderr so far: {so_far}"
                if selector.select(remaining):
                    byte = os.read(fd, 1)
                    assert byte, f"exited ({child.wait()}) before printing {text!r}; stderr: {lines}"
                    line += byte
            lines.append(line.decode(errors="replace"))
    return lines