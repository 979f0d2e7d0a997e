"""The local web server of ``delkit view`` (Starlette on uvicorn), with a small, closed surface.

* It binds 127.0.0.1 only, on a free port (or ``--port``), and answers only under ``/<token>/``, where the
  token is 32 random bytes made for this run (:func:`secrets.token_urlsafe`) and compared in constant time:
  another local user's page cannot drive it without reading the URL the command printed. The ``Host``
  header must name 127.0.0.1 / localhost (DNS rebinding).
* It serves the document built at start-up from the files named on the command line (:func:`make_app` gets
  the :class:`~delkit.view.document.Document`, never a path) and the page's fixed static files by name from
  a table: no request parameter reaches the file system.
* Formulas are parsed by delkit's parser and evaluated by :meth:`KripkeModel.check` — never ``eval``. Request
  bodies are capped at :data:`MAX_BODY` bytes, formulas at ``MAX_FORMULA`` characters and models at
  ``MAX_WORLDS`` worlds, each refused with a message saying the limit.
* Routes: ``GET /<token>/`` the page, ``GET /<token>/static/<name>`` its scripts, ``GET /<token>/api/doc`` the
  document (JSON), ``POST /<token>/api/eval`` ``{"frame", "panel", "formula"}``, ``POST /<token>/api/possible``
  ``{"frame", "panel", "agent", "world"}``, ``GET /<token>/api/image/<frame>`` a frame's picture.
"""

from __future__ import annotations

import json
import secrets
import socket
import threading
from importlib.resources import files
from typing import Any

from delkit.errors import DelkitError, ParseError
from delkit.view.document import Document, document_json, evaluate, possible

__all__ = ["make_app", "bind", "Running", "start", "serve", "MAX_BODY", "STATIC"]

#: the largest request body the server reads (bytes)
MAX_BODY = 64 * 1024

#: the static files of the page: name → content type (served from the package, by this name only)
STATIC = {"cytoscape.min.js": "text/javascript; charset=utf-8", "view.js": "text/javascript; charset=utf-8",
          "view.css": "text/css; charset=utf-8", "cytoscape.LICENSE.txt": "text/plain; charset=utf-8"}

_CSP = ("default-src 'none'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
        "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'")


def _static(name: str) -> bytes:
    return files("delkit.view").joinpath("static", name).read_bytes()


def make_app(doc: Document, token: str, port: int | None = None) -> Any:
    """The ASGI app serving ``doc`` under ``/<token>/`` (``port``: the Host header must carry it)."""
    from starlette.applications import Starlette
    from starlette.concurrency import run_in_threadpool
    from starlette.requests import Request
    from starlette.responses import JSONResponse, Response
    from starlette.routing import Route

    doc_bytes = json.dumps(document_json(doc), separators=(",", ":")).encode()
    page = _static("view.html").decode().replace("{{title}}", _html_escape(doc.title)).encode()
    statics = {name: _static(name) for name in STATIC}
    headers = {"Content-Security-Policy": _CSP, "X-Content-Type-Options": "nosniff", "Cache-Control": "no-store",
               "Referrer-Policy": "no-referrer"}
    hosts = {"127.0.0.1", "localhost"} if port is None else {f"127.0.0.1:{port}", f"localhost:{port}"}

    def error(status: int, message: str, **extra: Any) -> Any:
        return JSONResponse({"ok": False, "error": message, **extra}, status_code=status, headers=headers)

    async def read_json(request: Request) -> Any:
        length = request.headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > MAX_BODY):
            raise _Refused(413, f"request body too large ({length} bytes); the viewer reads at most {MAX_BODY}")
        body = bytearray()
        async for chunk in request.stream():
            body += chunk
            if len(body) > MAX_BODY:
                raise _Refused(413, f"request body too large (over {MAX_BODY} bytes); the viewer reads at most "
                                    f"{MAX_BODY}")
        try:
            data = json.loads(body.decode("utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise _Refused(400, f"the request body is not JSON ({exc})") from None
        if not isinstance(data, dict):
            raise _Refused(400, "the request body must be a JSON object")
        return data

    async def dispatch(request: Request) -> Any:
        host = request.headers.get("host", "")
        if host not in hosts:
            return error(403, f"Host {host!r} refused: the viewer answers only on 127.0.0.1")
        parts = request.url.path.split("/")[1:]
        if not parts or not secrets.compare_digest(parts[0].encode(), token.encode()):
            return error(403, "missing or wrong token: open the exact URL that `delkit view` printed "
                              "(http://127.0.0.1:PORT/TOKEN/)")
        rest = parts[1:]
        method = request.method
        try:
            if rest in ([], [""]) and method == "GET":
                return Response(page, media_type="text/html; charset=utf-8", headers=headers)
            if len(rest) == 2 and rest[0] == "static" and method == "GET" and rest[1] in statics:
                return Response(statics[rest[1]], media_type=STATIC[rest[1]], headers=headers)
            if rest == ["api", "doc"] and method == "GET":
                return Response(doc_bytes, media_type="application/json", headers=headers)
            if len(rest) == 3 and rest[:2] == ["api", "image"] and method == "GET" and rest[2].isdigit():
                k = int(rest[2])
                if k < len(doc.frames) and doc.frames[k].image is not None:
                    return Response(doc.frames[k].image, media_type=doc.frames[k].image_type, headers=headers)
                return error(404, f"frame {k} has no picture")
            if rest == ["api", "eval"] and method == "POST":
                data = await read_json(request)
                out = await run_in_threadpool(evaluate, doc, data.get("frame", 0), data.get("panel", "state"),
                                              data.get("formula"))
                return JSONResponse(out, headers=headers)
            if rest == ["api", "possible"] and method == "POST":
                data = await read_json(request)
                out = possible(doc, data.get("frame", 0), data.get("panel", "state"), data.get("agent"),
                               data.get("world"))
                return JSONResponse(out, headers=headers)
        except _Refused as exc:
            return error(exc.status, exc.message)
        except ParseError as exc:
            return error(400, str(exc), line=exc.line, column=exc.column)
        except DelkitError as exc:
            return error(400, str(exc))
        except RecursionError:
            return error(400, "the formula is nested too deeply to evaluate")
        return error(404, f"no such page: {method} /TOKEN/{'/'.join(rest)}; the viewer serves only its page, "
                          f"its static files and its API")

    methods = ["GET", "POST", "PUT", "DELETE", "PATCH"]
    return Starlette(routes=[Route("/{rest:path}", dispatch, methods=methods)])


class _Refused(Exception):
    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status, self.message = status, message


def _html_escape(text: str) -> str:
    from html import escape

    return escape(text)


def bind(port: int = 0) -> socket.socket:
    """A listening socket on 127.0.0.1 (``port`` 0: a free one)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    try:
        sock.bind(("127.0.0.1", port))
    except OSError as exc:
        sock.close()
        raise DelkitError(f"--port {port}: cannot listen on 127.0.0.1:{port} ({exc.strerror}); pick another port "
                          f"or leave --port out for a free one") from None
    sock.listen(64)
    return sock


class Running:
    """A viewer serving in a background thread (tests, notebooks): ``url``, :meth:`stop`."""

    def __init__(self, doc: Document, port: int = 0) -> None:
        import uvicorn

        self.sock = bind(port)
        self.port = self.sock.getsockname()[1]
        self.token = secrets.token_urlsafe(32)
        self.url = f"http://127.0.0.1:{self.port}/{self.token}/"
        app = make_app(doc, self.token, self.port)
        self.server = uvicorn.Server(uvicorn.Config(app, log_level="warning", lifespan="off", access_log=False))
        self.thread = threading.Thread(target=self.server.run, kwargs={"sockets": [self.sock]}, daemon=True)
        self.thread.start()
        while not self.server.started and self.thread.is_alive():
            threading.Event().wait(0.01)

    def stop(self) -> None:
        self.server.should_exit = True
        self.thread.join(timeout=5)
        self.sock.close()


def start(doc: Document, port: int = 0) -> Running:
    """Serve ``doc`` in a background thread; returns the :class:`Running` server (its ``url``)."""
    return Running(doc, port)


def serve(doc: Document, *, port: int = 0, open_browser: bool = True, echo: Any = print) -> None:
    """Serve ``doc`` until interrupted (Ctrl-C), printing the URL (and opening it in the browser)."""
    import uvicorn

    sock = bind(port)
    port = sock.getsockname()[1]
    token = secrets.token_urlsafe(32)
    url = f"http://127.0.0.1:{port}/{token}/"
    app = make_app(doc, token, port)
    echo(f"delkit view: {doc.title} ({len(doc.frames)} frame(s)) at {url}")
    echo("  only this machine can connect (127.0.0.1); the token in the URL is the key; Ctrl-C stops")
    if open_browser:
        import webbrowser

        threading.Timer(0.3, webbrowser.open, args=(url,)).start()
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", lifespan="off", access_log=False))
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
