"""Adversarial HTTP inputs against ``delkit view``'s server: a real uvicorn server on 127.0.0.1 (the one
:func:`delkit.view.server.start` runs), driven over sockets.

Families (each a list of inputs; an input is one request, one connection or one result folder):

* ``traversal`` — paths that try to leave the page's fixed routes: ``..`` / ``%2e%2e`` / ``%252e`` / ``\\`` /
  ``%00`` / doubled slashes / wrong tokens, aimed at a secret file beside the viewed model and at
  ``/etc/passwd``;
* ``encodings`` — picture numbers that are not plain ASCII digits (``%C2%B2``, Arabic and fullwidth digits,
  invalid UTF-8, 5,000 digits, signs, floats) and odd methods;
* ``json-numbers`` — request bodies with numbers too big to read (5,000 digits, ``1e99999``, ``NaN``), deep
  nesting, wrong types for every field, formulas with huge numbers;
* ``formulas`` — random formula texts over an SMCDEL structure (unknown symbols, SMCDEL and delkit syntax
  mixed, unbalanced brackets, control characters): a truth value or a 400, never a 500;
* ``symlinks`` — e-PICO result folders whose ``final.png`` / ``run.gif`` are links (symbolic: absolute,
  relative ``..``, chains, to directories, to ``/dev/zero``, to a FIFO; hard links to a file outside) or
  whose ``files`` name paths outside; every picture route is fetched and must not return the secret bytes;
* ``slow-clients`` — a header sent a few bytes at a time, a connection that sends nothing, a body that never
  completes, a half header then close, many idle connections at once; each must be cut off within the
  server's timeouts, and a normal request must still be answered;
* ``cross-origin`` — POSTs (and PUT/DELETE) with foreign ``Origin`` / ``Sec-Fetch-Site`` values, and
  ``Host`` headers that are not 127.0.0.1 / localhost (DNS rebinding): all 403.

Every input is checked for: no 500, no traceback in the server's log, no hang (a client timeout), no
leaked secret bytes, and the family's own expectation (e.g. 403). Prints a table (or ``--json``); exits 1
on any failure::

    python bench/fuzz_http.py [--scale 1.0] [--seed 0] [--json]

:func:`families` returns the families as ``name -> run(scale, seed) -> {"inputs": n, "failures": [...]}``
for a driver that runs fuzz families from several modules.
"""

from __future__ import annotations

import argparse
import contextlib
import http.client
import json
import logging
import os
import random
import socket
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

SECRET = b"DELKIT-FUZZ-SECRET-7f3a"
HEADER_TIMEOUT = 0.5
BODY_TIMEOUT = 0.5
CLIENT_TIMEOUT = 10.0

__all__ = ["families", "run_all", "main"]


class _Tracebacks(logging.Handler):
    """Collects log records that carry an exception (uvicorn logs an app's traceback this way)."""

    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.records: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.exc_info or "Traceback" in record.getMessage() or "Exception in ASGI" in record.getMessage():
            self.records.append(record.getMessage()[:300])


@contextlib.contextmanager
def _server(doc) -> Iterator:
    from delkit.view.server import start

    handler = _Tracebacks()
    loggers = [logging.getLogger(n) for n in ("uvicorn", "uvicorn.error", "uvicorn.asgi", "starlette")]
    for lg in loggers:
        lg.addHandler(handler)
    r = start(doc, header_timeout=HEADER_TIMEOUT, body_timeout=BODY_TIMEOUT)
    r.tracebacks = handler.records
    try:
        yield r
    finally:
        r.stop()
        for lg in loggers:
            lg.removeHandler(handler)


def _request(r, method: str, path: str, body: bytes | None = None, headers: dict | None = None) -> tuple[int, bytes]:
    """One request on a fresh connection; (status, body); status -1: the client timed out (a hang)."""
    from urllib.parse import quote

    conn = http.client.HTTPConnection("127.0.0.1", r.port, timeout=CLIENT_TIMEOUT)
    path = quote(path, safe="%/?=&+:@!$'()*,;~-._\\")  # what a client puts on the wire: ASCII, no spaces
    try:
        h = {"Host": f"127.0.0.1:{r.port}", **(headers or {})}
        conn.putrequest(method, path, skip_host=True, skip_accept_encoding=True)
        for k, v in h.items():
            conn.putheader(k, v)
        if body is not None:
            conn.putheader("Content-Length", str(len(body)))
        conn.endheaders(body)
        resp = conn.getresponse()
        return resp.status, resp.read()
    except TimeoutError:
        return -1, b""
    except (ConnectionError, http.client.HTTPException) as exc:
        return -2, str(exc).encode()
    finally:
        conn.close()


def _check(failures: list, what: str, status: int, body: bytes, expect: Callable[[int], bool] | None = None) -> None:
    if status == -1:
        failures.append(f"{what}: hang (no answer within {CLIENT_TIMEOUT} s)")
    elif status >= 500:
        failures.append(f"{what}: {status} {body[:200]!r}")
    elif SECRET in body or b"root:x:0:0" in body:
        failures.append(f"{what}: LEAK: the answer holds the secret bytes")
    elif expect is not None and not expect(status):
        failures.append(f"{what}: unexpected status {status} {body[:200]!r}")


def _model_doc(tmp: Path):
    from delkit import KripkeModel
    from delkit.io.formats import dumps
    from delkit.view.document import load_document

    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": [[0], [1]]}, designated=[0])
    (tmp / "m.json").write_text(dumps(m))
    (tmp / "secret.txt").write_bytes(SECRET)
    return load_document([tmp / "m.json"])


def _finish(r, failures: list, n: int) -> dict:
    time.sleep(0.05)
    failures += [f"server traceback: {t}" for t in r.tracebacks]
    return {"inputs": n, "failures": failures}


# ------------------------------------------------------------------------------------------ families


def fam_traversal(scale: float, seed: int) -> dict:
    rng = random.Random(seed)
    targets = ["secret.txt", "m.json", "etc/passwd", "pyproject.toml", "delkit/view/document.py", "view.html"]
    ups = ["..", "%2e%2e", "%2E%2E", ".%2e", "%252e%252e", "..%2f", "..%5c", "..\\", "%c0%ae%c0%ae", "....//",
           "%2e%2e%2f", ".", "%00", "%2f", "//"]
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d, _server(_model_doc(Path(d))) as r:
        failures: list[str] = []
        n = 0
        cases = []
        for tok in (r.token, r.token + "x", "", r.token[:-1], r.token.upper()):
            for where in ("static", "api/image", "api", "", "static/view.js"):
                for up in ups:
                    for t in targets:
                        cases.append(f"/{tok}/{where}/{up}/{up}/{up}/{t}".replace("///", "/"))
        rng.shuffle(cases)
        cases = cases[:max(20, int(300 * scale))]
        for path in cases:
            for method in ("GET",):
                st, body = _request(r, method, path)
                n += 1
                _check(failures, f"GET {path}", st, body, lambda s: 400 <= s < 500 or s == 200)
                if st == 200 and not path.endswith(("/static/view.js",)):
                    failures.append(f"GET {path}: 200 for a path outside the routes")
        return _finish(r, failures, n)


def fam_encodings(scale: float, seed: int) -> dict:
    rng = random.Random(seed)
    parts = ["%C2%B2", "%D9%A3", "%EF%BC%91", "%E2%91%A0", "%E0%B5%AC", "%FF", "%C0%AF", "%80", "1" * 5000, "9" * 7,
             "-1", "+1", "1.0", "1e3", "0x1", " 1", "1%20", "%00", "0%00", "00000001", "", "%", "%G1", "١٢"]
    parts += ["".join(rng.choice("0123456789²³¹٣%٤") for _ in range(rng.randint(1, 12)))
              for _ in range(int(60 * scale))]
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d, _server(_model_doc(Path(d))) as r:
        failures: list[str] = []
        n = 0
        for p in parts:
            for method in ("GET", "POST", "HEAD"):
                st, body = _request(r, method, f"/{r.token}/api/image/{p}")
                n += 1
                _check(failures, f"{method} image/{p[:40]}", st, body, lambda s: 400 <= s < 500)
        for method in ("OPTIONS", "TRACE", "PATCH", "DELETE", "PUT", "GETX"):
            st, body = _request(r, method, f"/{r.token}/api/doc")
            n += 1
            _check(failures, f"{method} api/doc", st, body, lambda s: 400 <= s < 500)
        return _finish(r, failures, n)


def fam_json_numbers(scale: float, seed: int) -> dict:
    rng = random.Random(seed)
    big = "9" * 5000
    values = [big, "-" + big, "1e99999", "-1e99999", "NaN", "Infinity", "-0", "0.5", "true", "null", '"0"', "[]",
              "{}", '"' + "a" * 3000 + '"', "1" * 4301, "[" * 2000 + "]" * 2000, '"\\ud800"', "2e-99999"]
    bodies = []
    for field in ("frame", "panel", "formula", "agent", "world"):
        for v in values:
            for path in ("eval", "possible"):
                bodies.append((path, '{"frame": 0, "panel": "state", "formula": "p", "agent": "a", "world": 0, "'
                               + field + '": ' + v + "}"))
    for _ in range(int(60 * scale)):
        f = rng.choice(["p", "K_a p", "K_b ~p", "C{a,b} p"]) + rng.choice([" & ", " | "]) + rng.choice(
            [big[:rng.randint(1, 5000)], "1", "0", "p" + big[:50]])
        bodies.append(("eval", json.dumps({"frame": 0, "panel": "state", "formula": f})))
    bodies += [("eval", "[" * 100_000), ("eval", "{" * 50_000), ("eval", '{"formula": "p"' + " " * 70_000 + "}"),
               ("eval", "\xff\xfe"), ("eval", ""), ("eval", "null"), ("eval", "[1,2]")]
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d, _server(_model_doc(Path(d))) as r:
        failures: list[str] = []
        for path, b in bodies:
            st, body = _request(r, "POST", f"/{r.token}/api/{path}", b.encode("utf-8", "surrogatepass"),
                                {"Content-Type": "application/json"})
            _check(failures, f"POST {path} {b[:60]!r}", st, body, lambda s: s in (200, 400, 413))
        return _finish(r, failures, len(bodies))


def fam_formulas(scale: float, seed: int) -> dict:
    from delkit.view.document import load_document

    rng = random.Random(seed)
    atoms = ["p", "q", "m1", "m2", "m3", "zed", "K_a", "K_b", "Kw_a", "K_1", "K_2", "Kw_2", "amy", "knows",
             "whether", "&", "|", "~", "->", "(", ")", "C{1,2}", "[!", "]", "<", ">", "T", "F", "⊤", "¬", "\x00",
             "{", "}", ",", "99999999999999999999", "9" * 400, "'", '"', "\\", "_", "⊥", "$", "%"]
    texts = ["".join(rng.choice(atoms) + rng.choice(["", " "]) for _ in range(rng.randint(1, 12)))
             for _ in range(int(200 * scale))]
    texts += ["K_b Kw_a p", "nosuchvar", "1 knows whether m1", "K_zed p", "(((", "m1 &"]
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d:
        src = ROOT / "specs" / "smcdel" / "muddy3.smcdel.txt"
        (Path(d) / "muddy.smcdel.txt").write_text(src.read_text())
        with _server(load_document([Path(d) / "muddy.smcdel.txt"])) as r:
            failures: list[str] = []
            for t in texts:
                st, body = _request(r, "POST", f"/{r.token}/api/eval",
                                    json.dumps({"frame": 0, "panel": "state", "formula": t}).encode(),
                                    {"Content-Type": "application/json"})
                _check(failures, f"formula {t[:60]!r}", st, body, lambda s: s in (200, 400))
            return _finish(r, failures, len(texts))


def _result(d: Path, files: dict) -> Path:
    steps = [{"index": i, "task": "t", "text": f"robot1: step{i}", "t_sim_s": 1.0 + i, "ok": True} for i in range(3)]
    log = [{"t_sim_s": 2.0, "task": "t", "kind": "sensing", "robot": "robot1", "chosen": "observed",
            "learnt": ["K_robot1 hold(robot1, red)"]}]
    (d / "result.json").write_text(json.dumps({"success": True, "goal": "alpha", "steps": steps, "belief_log": log,
                                               "beliefs": {"robot1": []}, "files": files, "sim_seconds": 4.0}))
    return d / "result.json"


def fam_symlinks(scale: float, seed: int) -> dict:
    from PIL import Image

    from delkit.errors import DelkitError
    from delkit.view.document import load_document

    failures: list[str] = []
    n = 0
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d:
        base = Path(d)
        outside = base / "outside"
        outside.mkdir()
        secret_png = outside / "secret.png"
        Image.new("RGB", (4, 4)).save(secret_png)
        secret_png.write_bytes(secret_png.read_bytes() + SECRET)  # a valid PNG that carries the secret
        secret_gif = outside / "secret.gif"
        Image.new("RGB", (4, 4)).save(secret_gif)
        secret_gif.write_bytes(secret_gif.read_bytes() + SECRET)
        fifo = outside / "fifo.png"
        os.mkfifo(fifo)
        kinds: list[tuple[str, Callable[[Path, str], None]]] = [
            ("abs symlink", lambda p, ext: p.symlink_to(outside / f"secret.{ext}")),
            ("relative ../ symlink", lambda p, ext: p.symlink_to(f"../outside/secret.{ext}")),
            ("chain of links", lambda p, ext: (p.parent / f"hop.{ext}").symlink_to(outside / f"secret.{ext}")
             or p.symlink_to(p.parent / f"hop.{ext}")),
            ("link to /etc/passwd", lambda p, ext: p.symlink_to("/etc/passwd")),
            ("link to /dev/zero", lambda p, ext: p.symlink_to("/dev/zero")),
            ("link to a FIFO", lambda p, ext: p.symlink_to(fifo)),
            ("link to a directory", lambda p, ext: p.symlink_to(outside)),
            ("dangling link", lambda p, ext: p.symlink_to(outside / "missing.png")),
            ("self loop", lambda p, ext: p.symlink_to(p)),
            ("hard link outside", lambda p, ext: os.link(outside / f"secret.{ext}", p)),
            ("fifo in the folder", lambda p, ext: os.mkfifo(p)),
            ("directory named like the picture", lambda p, ext: p.mkdir()),
        ]
        names = [{"png": "final.png", "video": "run.gif"}, {"png": str(outside / "secret.png")},
                 {"png": "../outside/secret.png"}, {"png": "/etc/passwd"}, {"video": "../outside/secret.gif"},
                 {"png": "..", "video": "."}, {"png": "", "video": None}, {"png": 7, "video": ["x"]},
                 {"png": "final.png\x00.txt"}, {"png": "%2e%2e/outside/secret.png"}]
        k = 0
        reps = max(1, int(round(3 * scale)))
        for _ in range(reps):
            for label, make in kinds:
                for which in ("png", "gif", "both"):
                    for files in names[:2] if which != "both" else names:
                        k += 1
                        run = base / f"run{k}"
                        run.mkdir()
                        for ext in (["png", "gif"] if which == "both" else [which]):
                            fname = "final.png" if ext == "png" else "run.gif"
                            try:
                                make(run / fname, ext)
                            except OSError:
                                pass
                        try:
                            doc = load_document([_result(run, files)])
                        except DelkitError:
                            n += 1
                            continue
                        except Exception as exc:  # noqa: BLE001 - a traceback is what the fuzz looks for
                            failures.append(f"{label}/{which}/{files}: {type(exc).__name__}: {exc}")
                            n += 1
                            continue
                        n += 1
                        what = f"{label}/{which}/{files}"
                        for f, fr in enumerate(doc.frames):  # what the server would serve: the frames' bytes
                            if fr.image is not None and SECRET in fr.image:
                                failures.append(f"{what}: LEAK: frame {f}'s picture holds the secret bytes")
                        if files is not names[0] or _ > 0:
                            continue
                        with _server(doc) as r:  # and through the real server, for the folder's own names
                            for f in range(len(doc.frames)):
                                st, body = _request(r, "GET", f"/{r.token}/api/image/{f}")
                                _check(failures, f"{what} image {f}", st, body, lambda s: s in (200, 404))
                            failures += [f"server traceback: {t}" for t in r.tracebacks]
    return {"inputs": n, "failures": failures}


def _raw(port: int, chunks: list[bytes], pause: float, read_for: float = 5.0) -> tuple[bytes, float]:
    """Send ``chunks`` ``pause`` seconds apart; (the answer's first line or b'', seconds until it came or the
    connection closed)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=CLIENT_TIMEOUT)
    t0 = time.monotonic()
    got = b""
    try:
        for i, c in enumerate(chunks):
            if i:
                time.sleep(pause)
            s.sendall(c)
        s.settimeout(read_for)
        while b"\r\n" not in got:
            b = s.recv(4096)
            if not b:
                break
            got += b
    except TimeoutError:
        return b"HANG", time.monotonic() - t0
    except OSError:
        pass
    finally:
        s.close()
    return got.split(b"\r\n", 1)[0], time.monotonic() - t0


def fam_slow_clients(scale: float, seed: int) -> dict:
    rng = random.Random(seed)
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d, _server(_model_doc(Path(d))) as r:
        failures: list[str] = []
        head = f"GET /{r.token}/api/doc HTTP/1.1\r\nHost: 127.0.0.1:{r.port}\r\n".encode()
        post = (f"POST /{r.token}/api/eval HTTP/1.1\r\nHost: 127.0.0.1:{r.port}\r\n"
                f"Content-Type: application/json\r\nContent-Length: 60\r\n\r\n").encode()
        cases: list[tuple[str, list[bytes], float, Callable[[bytes], bool]]] = []
        for step in (1, 2, 3, 5, 8):
            cases.append((f"header drip {step} B", [head[i:i + step] for i in range(0, len(head), step)], 0.05,
                          lambda g: not g.startswith(b"HTTP/1.1 200")))
        cases.append(("nothing sent", [b""], 0.0, lambda g: g == b""))
        cases.append(("half a request line", [b"GET /"], 0.0, lambda g: not g.startswith(b"HTTP/1.1 200")))
        for cut in (1, 10, 30, 59):
            cases.append((f"body of {cut}/60 bytes", [post, b"x" * cut], 0.05, lambda g: b" 408 " in g + b" "))
        for _ in range(int(10 * scale)):
            step = rng.randint(1, 20)
            cases.append((f"random drip {step}", [head[i:i + step] for i in range(0, len(head), step)], 0.05,
                          lambda g: not g.startswith(b"HTTP/1.1 200")))
        results: list = [None] * len(cases)

        def one(i: int) -> None:
            results[i] = _raw(r.port, cases[i][1], cases[i][2])

        threads = [threading.Thread(target=one, args=(i,)) for i in range(len(cases))]
        idle = [socket.create_connection(("127.0.0.1", r.port)) for _ in range(int(40 * scale) + 5)]  # held open
        for t in threads:
            t.start()
        st, body = _request(r, "GET", f"/{r.token}/api/doc")  # a normal client is still served meanwhile
        _check(failures, "normal request beside slow clients", st, body, lambda s: s == 200)
        for t in threads:
            t.join(CLIENT_TIMEOUT + 30)
        for (name, _, _, ok), res in zip(cases, results, strict=True):
            if res is None or res[0] == b"HANG":
                failures.append(f"{name}: not cut off (hang)")
            elif not ok(res[0]):
                failures.append(f"{name}: answered {res[0][:80]!r}")
            elif res[1] > 20 * HEADER_TIMEOUT + len(cases[0][1]) * 0.05 + 5:
                failures.append(f"{name}: cut off only after {res[1]:.1f} s")
        time.sleep(HEADER_TIMEOUT * 3)
        closed = 0
        for s in idle:  # the idle connections were closed by the server
            s.settimeout(2)
            try:
                closed += s.recv(1) == b""
            except OSError:
                closed += 1
            s.close()
        if closed != len(idle):
            failures.append(f"idle connections: {len(idle) - closed} of {len(idle)} still open after "
                            f"{HEADER_TIMEOUT * 3:.1f} s")
        return _finish(r, failures, len(cases) + len(idle) + 1)


def fam_cross_origin(scale: float, seed: int) -> dict:
    rng = random.Random(seed)
    origins = ["http://evil.example", "null", "http://127.0.0.1", "http://127.0.0.1:1", "https://127.0.0.1",
               "http://localhost.evil.example", "http://127.0.0.1.evil.example", "file://", "http://[::1]",
               "http://127.0.0.2", " http://127.0.0.1", "HTTP://127.0.0.1", "", "*", "http://0.0.0.0",
               "http://127.1", "http://2130706433"]
    sites = [None, "cross-site", "same-site", "none", "same-origin", "CROSS-SITE", ""]
    hosts = ["evil.example", "127.0.0.1", "localhost", "127.0.0.1:1", "0.0.0.0", "[::1]", "127.0.0.1.nip.io",
             "", "LOCALHOST", "localhost.", "2130706433"]
    with tempfile.TemporaryDirectory(prefix="fuzz-http-") as d, _server(_model_doc(Path(d))) as r:
        failures: list[str] = []
        n = 0
        mine = {f"http://127.0.0.1:{r.port}", f"http://localhost:{r.port}"}
        body = json.dumps({"frame": 0, "panel": "state", "formula": "p"}).encode()
        combos = [(o, s, m) for o in origins + list(mine) for s in sites for m in ("POST", "PUT", "DELETE")]
        rng.shuffle(combos)
        for o, s, m in combos[:max(30, int(300 * scale))]:
            h = {"Content-Type": "application/json"}
            if o:
                h["Origin"] = o
            if s is not None:
                h["Sec-Fetch-Site"] = s
            st, ans = _request(r, m, f"/{r.token}/api/eval", body, h)
            n += 1
            foreign = bool(o) and o not in mine or (s is not None and s not in ("same-origin", "none"))
            if foreign:
                _check(failures, f"{m} Origin={o!r} Sec-Fetch-Site={s!r}", st, ans, lambda x: x == 403)
            else:
                _check(failures, f"{m} Origin={o!r} Sec-Fetch-Site={s!r}", st, ans,
                       lambda x, m=m: x == 200 if m == "POST" else 400 <= x < 500)
        for host in hosts:
            for path in ("api/doc", ""):
                st, ans = _request(r, "GET", f"/{r.token}/{path}", headers={"Host": host})
                n += 1
                _check(failures, f"Host {host!r}", st, ans, lambda x: x in (400, 403))
        return _finish(r, failures, n)


_FAMILIES: dict[str, Callable[[float, int], dict]] = {
    "traversal": fam_traversal, "encodings": fam_encodings, "json-numbers": fam_json_numbers,
    "formulas": fam_formulas, "symlinks": fam_symlinks, "slow-clients": fam_slow_clients,
    "cross-origin": fam_cross_origin}


def families() -> dict[str, Callable[[float, int], dict]]:
    """The explorer's HTTP fuzz families: name → ``run(scale, seed)`` → ``{"inputs", "failures"}``."""
    return dict(_FAMILIES)


def run_all(scale: float = 1.0, seed: int = 0, only: list[str] | None = None) -> list[dict]:
    rows = []
    for name, fn in families().items():
        if only and name not in only:
            continue
        t0, c0 = time.monotonic(), time.process_time()
        res = fn(scale, seed)
        rows.append({"family": name, "inputs": res["inputs"], "failures": res["failures"],
                     "wall_s": round(time.monotonic() - t0, 2), "cpu_s": round(time.process_time() - c0, 2)})
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scale", type=float, default=1.0, help="inputs per family relative to the default")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--family", action="append", help="run only this family (repeatable)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    logging.getLogger("uvicorn.error").setLevel(logging.WARNING)
    rows = run_all(args.scale, args.seed, args.family)
    load = open("/proc/loadavg").read().split()[:3]
    total = sum(r["inputs"] for r in rows)
    bad = sum(len(r["failures"]) for r in rows)
    if args.json:
        print(json.dumps({"ok": bad == 0, "inputs": total, "failures": bad, "load": load, "families": rows}))
    else:
        print(f"delkit view HTTP fuzz: {total} inputs, {bad} failures (500s, tracebacks, hangs, leaks, wrong "
              f"answers); load {' '.join(load)}")
        print(f"{'family':14} {'inputs':>7} {'failures':>8} {'wall s':>7} {'cpu s':>6}")
        for r in rows:
            print(f"{r['family']:14} {r['inputs']:>7} {len(r['failures']):>8} {r['wall_s']:>7.1f} {r['cpu_s']:>6.1f}")
        for r in rows:
            for f in r["failures"][:20]:
                print(f"  {r['family']}: {f}")
    return 0 if bad == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
