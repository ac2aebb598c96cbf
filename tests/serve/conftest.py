"""Fixtures of the `linkfit serve` tests: a server on a free loopback port, stopped after."""

import contextlib
import os
import signal
import subprocess

import pytest

CLI = os.environ.get("LINKFIT_CLI", "linkfit")


@contextlib.contextmanager
def running_server(*options):
    """`linkfit serve --port 0 OPTIONS...`: yields (its URL, its process); stopped by SIGINT."""
    process = subprocess.Popen([CLI, "serve", "--port", "0", *options],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = process.stdout.readline()
        assert first.startswith("linkfit serve: http://127.0.0.1:"), (
            first + process.stderr.read())
        yield first.split()[-1], process
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        process.stdout.close()
        process.stderr.close()


@pytest.fixture(scope="module")
def server():
    """A server with the default options, shared by a module's tests."""
    with running_server() as (url, _):
        yield url
