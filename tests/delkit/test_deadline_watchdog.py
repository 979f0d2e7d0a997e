"""The console script's watchdog inside :func:`delkit.resources.deadline`: a body that never returns to the
limit (an alarm swallowed by the body, or a body run without the alarm, e.g. around z3) is still ended,
within the grace period, with exit status 3 and the limit's own message."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time

import pytest

BODY = {
    # SIGALRM re-fires every 0.25 s; each TimeLimit is swallowed, as a C extension's finaliser would
    "alarm swallowed": """
        with deadline(0.6, "delkit test"):
            while True:
                try:
                    time.sleep(5)
                except TimeLimit:
                    pass
    """,
    # no alarm: only explicit checks, which this body never makes
    "no alarm": """
        with deadline(0.6, "delkit test", alarm=False):
            time.sleep(5)
    """,
}


@pytest.mark.parametrize("case", sorted(BODY))
def test_watchdog_ends_a_body_that_ignores_the_limit(case):
    code = textwrap.dedent("""
        import time
        from delkit import resources
        from delkit.resources import TimeLimit, deadline
        resources.HARD_EXIT = True
        resources.begin_command()
    """) + textwrap.dedent(BODY[case]) + "\nprint('body returned')\n"
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30)
    took = time.monotonic() - t0
    assert proc.returncode == 3, (proc.returncode, proc.stderr)
    assert "body returned" not in proc.stdout
    assert "delkit test: no answer within --timeout 0.6 s" in proc.stderr
    assert took < 4.0  # 0.6 s + 0.2 s grace + interpreter start; a body left running would take >= 5 s


def test_watchdog_is_disarmed_when_the_body_returns():
    code = textwrap.dedent("""
        import time
        from delkit import resources
        from delkit.resources import deadline
        resources.HARD_EXIT = True
        resources.begin_command()
        with deadline(0.5, "delkit test", alarm=False):
            pass
        with deadline(0.5, "delkit test"):
            pass
        time.sleep(1.2)
        print('still running')
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=30)
    assert proc.returncode == 0 and "still running" in proc.stdout, proc.stderr
