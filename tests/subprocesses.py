"""Child processes that the tests interrupt: a child dumps its threads' stacks on SIGUSR1, and a child that does
not stop in time fails its test with that dump (where it hangs), not with a bare timeout."""

from __future__ import annotations

import signal
import subprocess
import time

import pytest

DUMP_ON_USR1 = "import faulthandler, signal; faulthandler.register(signal.SIGUSR1, all_threads=True)\n"
"""The first line of a child's code: SIGUSR1 writes every thread's Python stack to its stderr."""


def communicate_or_dump(process: subprocess.Popen, timeout: float = 60.0) -> tuple[str, str]:
    """``process.communicate(timeout)``; when the child has not exited by then, its stacks are dumped, it is
    killed and the test fails with the end of its stderr."""
    try:
        return process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.send_signal(signal.SIGUSR1)
        time.sleep(2.0)
        process.kill()
        _, err = process.communicate()
        pytest.fail(f"the child process did not exit within {timeout:.0f} s; its stderr ends:\n{err[-6000:]}")
