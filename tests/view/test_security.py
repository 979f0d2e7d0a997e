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
from delkit.io.formats import dumps  # noqa: E402
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


# ------------------------------------------------------------------------------ attacks on the explorer


def test_non_ascii_and_huge_image_numbers_are_4xx(client):
    for part in ("%C2%B2", "%D9%A3", "1" * 5000, "-1", "0x1", "%EF%BC%91"):  # ², Arabic 3, 5,000 digits, fullwidth 1
        r = client.get(f"/{TOKEN}/api/image/{part}")
        assert 400 <= r.status_code < 500, (part, r.status_code)
        assert r.json()["ok"] is False


@pytest.mark.parametrize("body", [b'{"frame": ' + b"9" * 5000 + b', "formula": "p"}',
                                  b'{"formula": "p", "frame": 0, "x": ' + b"1" * 4400 + b"}",
                                  b'{"frame": 1e99999, "formula": "p"}', b"[" * 100_000])
def test_unreadable_json_numbers_and_nesting_are_400(client, body):
    r = client.post(f"/{TOKEN}/api/eval", content=body[:MAX_BODY])
    assert r.status_code in (400, 413) and r.json()["ok"] is False


@pytest.fixture
def smcdel_client(tmp_path):
    path = tmp_path / "muddy.smcdel.txt"
    path.write_text((Path(__file__).resolve().parents[2] / "specs" / "smcdel" / "muddy3.smcdel.txt").read_text())
    return TestClient(make_app(load_document([path]), TOKEN), base_url="http://127.0.0.1")


@pytest.mark.parametrize("formula", ["K_zed p", "nosuchvar", "K_a q7", "p &", "(((", "K_b Kw_a p", "1 &",
                                     "amy knows whether", "¬¬¬", "\x00"])
def test_formulas_over_a_structure_answer_4xx_or_a_truth_value(smcdel_client, formula):
    r = smcdel_client.post(f"/{TOKEN}/api/eval", json={"frame": 0, "panel": "state", "formula": formula})
    assert r.status_code in (200, 400), (formula, r.status_code, r.text[:300])
    if r.status_code == 400:
        assert r.json()["error"]


@pytest.mark.parametrize("headers", [{"origin": "http://evil.example"}, {"origin": "null"},
                                     {"origin": "http://127.0.0.1:1"}, {"sec-fetch-site": "cross-site"},
                                     {"sec-fetch-site": "same-site"}])
def test_cross_origin_posts_are_refused(client, headers):
    r = client.post(f"/{TOKEN}/api/eval", json={"frame": 0, "panel": "state", "formula": "p"}, headers=headers)
    assert r.status_code == 403 and "cross-origin" in r.json()["error"]


def test_same_origin_posts_are_answered(client):
    for headers in ({}, {"origin": "http://127.0.0.1"},
                    {"origin": "http://localhost", "sec-fetch-site": "same-origin"}):
        r = client.post(f"/{TOKEN}/api/eval", json={"frame": 0, "panel": "state", "formula": "p"}, headers=headers)
        assert r.status_code == 200, (headers, r.text)


def _result_dir(tmp_path, link_target=None):
    """A minimal e-PICO result folder (current schema) whose final.png is a picture, or a link to ``link_target``."""
    from PIL import Image

    d = tmp_path / "run"
    d.mkdir()
    if link_target is None:
        Image.new("RGB", (8, 8), (200, 10, 10)).save(d / "final.png")
    else:
        (d / "final.png").symlink_to(link_target)
    result = {"success": True, "goal": "alpha", "reason": "", "steps": [
        {"index": 0, "task": "sense_table_robot1", "text": "robot1: sense()", "t_sim_s": 0.1, "ok": True,
         "message": "", "observed": {}}],
        "belief_log": [{"t_sim_s": 0.1, "task": "sense_table_robot1", "kind": "sensing", "robot": "robot1",
                        "chosen": "observed", "learnt": ["K_robot1 hold(robot1, red)"]}],
        "beliefs": {"robot1": ["K_robot1 hold(robot1, red)"], "robot2": []},
        "files": {"png": str(d / "final.png")}, "sim_seconds": 0.1}
    (d / "result.json").write_text(json.dumps(result))
    return d / "result.json"


def test_a_picture_linking_outside_the_result_folder_is_not_served(tmp_path):
    secret = tmp_path / "secret.png"
    secret.write_bytes(b"\x89PNG\r\n\x1a\nSECRET-BYTES")
    doc = load_document([_result_dir(tmp_path, secret)])
    c = TestClient(make_app(doc, TOKEN), base_url="http://127.0.0.1")
    for k in range(len(doc.frames)):
        r = c.get(f"/{TOKEN}/api/image/{k}")
        assert b"SECRET-BYTES" not in r.content and r.status_code == 404
    assert any("outside the result's folder" in n for n in doc.notes)


def test_a_picture_hard_linked_to_a_file_outside_is_not_served(tmp_path):
    import os

    secret = tmp_path / "secret.png"
    secret.write_bytes(b"\x89PNG\r\n\x1a\nSECRET-BYTES")
    path = _result_dir(tmp_path)
    (path.parent / "final.png").unlink()
    os.link(secret, path.parent / "final.png")
    doc = load_document([path])
    assert all(f.image is None or b"SECRET-BYTES" not in f.image for f in doc.frames)
    assert any("hard links" in n for n in doc.notes)


def test_a_picture_linking_to_a_device_or_a_fifo_is_not_read(tmp_path):
    import os

    path = _result_dir(tmp_path, "/dev/zero")
    fifo = path.parent / "pipe.png"
    os.mkfifo(fifo)
    doc = load_document([path])
    assert all(f.image is None for f in doc.frames)
    (path.parent / "final.png").unlink()
    (path.parent / "final.png").symlink_to(fifo)  # a FIFO inside the folder: not a regular file, never opened
    doc = load_document([path])
    assert all(f.image is None for f in doc.frames) and any("not a regular file" in n for n in doc.notes)


def test_the_run_s_own_picture_is_served(tmp_path):
    doc = load_document([_result_dir(tmp_path)])
    c = TestClient(make_app(doc, TOKEN), base_url="http://127.0.0.1")
    r = c.get(f"/{TOKEN}/api/image/{len(doc.frames) - 1}")
    assert r.status_code == 200 and r.content.startswith(b"\x89PNG")


def _raw(url: str, chunks, pause: float) -> tuple[bytes, float]:
    """The HTTP fuzz's raw client (bench/fuzz_http.py): send ``chunks`` ``pause`` seconds apart; (the answer's
    first line, b'' if the server closed the connection, b'HANG' if it still held it open after 5 s;
    seconds since connecting)."""
    import importlib.util
    from urllib.parse import urlsplit

    spec = importlib.util.spec_from_file_location("fuzz_http", Path(__file__).resolve().parents[2] / "bench"
                                                  / "fuzz_http.py")
    fuzz_http = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fuzz_http)
    return fuzz_http._raw(urlsplit(url).port, list(chunks), pause)


def test_slow_clients_are_cut_off(tmp_path):
    path = tmp_path / "m.json"
    path.write_text(dumps(KripkeModel.build([{"p"}], {"a": [[0]]}, designated=[0])))
    r = start(load_document([path]), header_timeout=0.5, body_timeout=0.5)
    try:
        head = f"GET /{r.token}/api/doc HTTP/1.1\r\nHost: 127.0.0.1:{r.port}\r\n\r\n".encode()
        got, secs = _raw(r.url, [head[i:i + 8] for i in range(0, len(head), 8)], 0.2)  # a whole header, slowly
        assert got == b"" and secs < 4.5, (got, secs)  # closed before the header was complete
        got, secs = _raw(r.url, [b""], 0.0)  # connects and sends nothing
        assert got == b"" and secs < 4.5, (got, secs)
        body = f"POST /{r.token}/api/eval HTTP/1.1\r\nHost: 127.0.0.1:{r.port}\r\nContent-Length: 40\r\n\r\n".encode()
        got, secs = _raw(r.url, [body, b'{"formula"'], 0.1)  # the header in time, the body never completed
        assert b" 408 " in got, got
        got, _ = _raw(r.url, [head], 0.0)  # a client that sends at once is served
        assert got.startswith(b"HTTP/1.1 200"), got
    finally:
        r.stop()
