"""``delkit view`` as a command: starts, prints its URL, serves the file named; bad input is one line, exit 2."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DELKIT = str(Path(sys.executable).parent / "delkit")


def _env() -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT)}


def test_delkit_view_serves_the_named_file():
    pytest.importorskip("uvicorn", reason="delkit view needs uvicorn (pip install 'delkit[view]')")
    spec = ROOT / "specs" / "coin_in_the_box"
    proc = subprocess.Popen([DELKIT, "view", str(spec / "domain.epddl"), str(spec / "problem.epddl"),
                             str(spec / "problem.plan"), "--no-browser"], stderr=subprocess.PIPE, text=True,
                            cwd=ROOT, env=_env())
    try:
        url, lines = None, []
        end = time.monotonic() + 60
        while url is None and time.monotonic() < end:
            line = proc.stderr.readline()
            if not line:
                break
            lines.append(line)
            m = re.search(r"(http://127\.0\.0\.1:\d+/[A-Za-z0-9_-]{32,}/)", line)
            url = m.group(1) if m else None
        assert url, "".join(lines)
        with urllib.request.urlopen(url + "api/doc", timeout=20) as r:
            doc = json.loads(r.read())
        assert doc["kind"] == "task" and len(doc["frames"]) == 4
        bad = url.rsplit("/", 2)[0] + "/not-the-token/api/doc"
        with pytest.raises(urllib.error.HTTPError) as exc:
            urllib.request.urlopen(bad, timeout=20)
        assert exc.value.code == 403
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


@pytest.mark.parametrize("args, message", [
    (["view", "no-such-file.json"], "no such file"),
    (["view", "specs/smcdel/muddy3.smcdel.txt", "--max-worlds", "4"], "up to 4"),
    (["model", "draw", "specs/coin_in_the_box/domain.epddl", "specs/coin_in_the_box/problem.epddl", "--plan",
      "specs/coin_in_the_box/problem.plan", "--step", "7", "-o", "x.png"], "the plan has 3 step"),
])
def test_bad_input_is_one_line_and_exit_2(args, message, tmp_path):
    r = subprocess.run([DELKIT, *args], capture_output=True, text=True, cwd=ROOT, env=_env(), timeout=120)
    assert r.returncode == 2, r.stderr
    assert message in r.stderr and "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1
