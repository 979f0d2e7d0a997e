"""The viewer's server refuses what it must, with a clear message, and executes nothing it is sent."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

pytest.importorskip("starlette", reason="delkit view needs starlette (pip install 'delkit[view]')")
pytest.importorskip("httpx", reason="starlette's test client needs httpx (pip install 'delkit[view-test]')")

import warnings  # noqa: E402

with warnings.catch_warnings():  # starlette 1.x: "install httpx2" (its test client works with httpx)
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient  # noqa: E402

from delkit import KripkeModel  # noqa: E402
from delkit.errors import ModelError  # noqa: E402
from delkit.io import dumps  # noqa: E402
from delkit.view import document  # noqa: E402
from delkit.view.document import load_document  # noqa: E402
from delkit.view.server import MAX_BODY, make_app, start  # noqa: E402

TOKEN = "t0k3n-for-tests"


@pytest.fixture
def client(tmp_path):
    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0], [1]]}, designated=[0])
    path = tmp_path / "m.json"
    path.write_text(dumps(m))
    return TestClient(make_app(load_document([path]), TOKEN), base_url="http://127.0.0.1")


def test_the_page_and_api_answer_with_the_token(client):
    assert client.get(f"/{TOKEN}/").status_code == 200
    doc = client.get(f"/{TOKEN}/api/doc").json()
    assert doc["frames"][0]["panels"][0]["graph"]["nodes"][0]["props"] == ["p"]
    r = client.post(f"/{TOKEN}/api/eval", json={"frame": 0, "panel": "state", "formula": "K_b p"})
    assert r.json()["truth"] == [True, False]


@pytest.mark.parametrize("path", ["/", "/api/doc", "/wrong-token/api/doc", f"/{TOKEN[:-1]}/", "/etc/passwd"])
def test_missing_or_wrong_token_is_refused(client, path):
    r = client.get(path)
    assert r.status_code == 403
    assert "missing or wrong token" in r.json()["error"]


@pytest.mark.parametrize("path", [f"/{TOKEN}/etc/passwd", f"/{TOKEN}/static/..%2f..%2fpyproject.toml",
                                  f"/{TOKEN}/static/view.html", f"/{TOKEN}/static/%2e%2e/document.py",
                                  f"/{TOKEN}/api/image/0", f"/{TOKEN}/api/file", f"/{TOKEN}/api/doc/x"])
def test_any_other_path_is_refused(client, path):
    r = client.get(path)
    assert r.status_code == 404
    assert "root:" not in r.text and "[project]" not in r.text
    assert r.json()["error"].startswith(("no such page", "frame 0 has no picture"))


def test_query_parameters_do_not_reach_the_file_system(client):
    r = client.get(f"/{TOKEN}/api/doc?path=/etc/passwd&file=../../pyproject.toml")
    assert r.status_code == 200 and "root:" not in r.text and r.json()["sources"][0].endswith("m.json")


def test_oversized_body_is_refused(client):
    r = client.post(f"/{TOKEN}/api/eval", content=b'{"formula": "' + b"p & " * MAX_BODY + b'p"}',
                    headers={"content-type": "application/json"})
    assert r.status_code == 413 and f"at most {MAX_BODY}" in r.json()["error"]

    def chunks():  # no content-length: the cap holds while reading
        for _ in range(MAX_BODY // 1000 + 2):
            yield b" " * 1000

    r = client.post(f"/{TOKEN}/api/eval", content=chunks())
    assert r.status_code == 413


def test_long_formula_and_bad_json_are_refused(client):
    r = client.post(f"/{TOKEN}/api/eval", json={"formula": "p" + " & p" * 1000})
    assert r.status_code == 400 and "at most" in r.json()["error"]
    r = client.post(f"/{TOKEN}/api/eval", content=b"{not json")
    assert r.status_code == 400 and "not JSON" in r.json()["error"]


@pytest.mark.parametrize("text", ["__import__('os')", "__import__('os').system('touch {marker}')",
                                  "eval('1')", "open('/etc/passwd').read()", "p; import os"])
def test_formulas_are_parsed_never_executed(client, tmp_path, monkeypatch, text):
    marker = tmp_path / "executed"
    client.post(f"/{TOKEN}/api/eval", json={"formula": "p &"})  # the error path's lazy imports (namedtuple uses eval)
    calls = []
    import builtins
    import os

    monkeypatch.setattr(os, "system", lambda *a: calls.append(a) or 0)
    real_eval = builtins.eval
    monkeypatch.setattr(builtins, "eval", lambda *a, **k: calls.append(a) or real_eval(*a, **k))
    r = client.post(f"/{TOKEN}/api/eval", json={"formula": text.format(marker=marker)})
    assert r.status_code == 400
    body = r.json()
    assert body["ok"] is False and body["column"] >= 1 and "unexpected" in body["error"]
    assert not calls and not marker.exists()


def test_host_header_must_be_local(client):
    r = client.get(f"/{TOKEN}/api/doc", headers={"host": "evil.example:80"})
    assert r.status_code == 403 and "127.0.0.1" in r.json()["error"]


def test_unknown_panel_agent_world_are_refused(client):
    for body in ({"frame": 7}, {"panel": "x"}, {"agent": "z", "world": 0}, {"agent": "a", "world": 9},
                 {"agent": "a", "world": "0"}):
        path = "possible" if "agent" in body else "eval"
        r = client.post(f"/{TOKEN}/api/{path}", json={"formula": "p", **body})
        assert r.status_code == 400 and r.json()["error"], body


def test_models_above_the_cap_are_refused(tmp_path, monkeypatch):
    m = KripkeModel.build([{"p"}, set(), {"p"}], {"a": [[0, 1, 2]]}, designated=[0])
    path = tmp_path / "m.json"
    path.write_text(dumps(m))
    monkeypatch.setattr(document, "MAX_WORLDS", 2)
    with pytest.raises(ModelError, match="at most 2"):
        load_document([path])


def test_the_server_binds_loopback_only(tmp_path):
    path = tmp_path / "m.json"
    path.write_text(dumps(KripkeModel.build([{"p"}], {"a": [[0]]}, designated=[0])))
    r = start(load_document([path]))
    try:
        assert r.sock.getsockname()[0] == "127.0.0.1"
        assert r.url.startswith(f"http://127.0.0.1:{r.port}/") and len(r.token) >= 32
        import urllib.request

        with urllib.request.urlopen(r.url + "api/doc", timeout=10) as resp:
            assert json.loads(resp.read())["kind"] == "kripke"
    finally:
        r.stop()


def test_only_named_files_are_read(tmp_path):
    with pytest.raises(Exception, match="no such file"):
        load_document([tmp_path / "missing.json"])
    assert Path(document.__file__).parent.joinpath("static", "cytoscape.LICENSE.txt").is_file()
