"""The local web server of ``delkit view`` (Starlette on uvicorn), with a small, closed surface.

* It binds 127.0.0.1 only, on a free port (or ``--port``), and answers only under ``/<token>/``, where the
  token is 32 random bytes made for this run (:func:`secrets.token_urlsafe`) and compared in constant time:
  another local user's page cannot drive it without reading the URL the command printed. The ``Host``
  header must name 127.0.0.1 / localhost (DNS rebinding).
* It serves the document built at start-up from the files named on the command line (:func:`make_app` gets
  the :class:`~delkit.view.document.Document`, never a path) and the page's fixed static files by name from
  a table: no request parameter reaches the file system.
* Every request must come from the page itself: a POST whose ``Origin`` (or ``Sec-Fetch-Site``) names another
  site is refused (403), so another site open in the same browser cannot post to the API.
* Slow clients are cut off: a request's header must arrive within :data:`HEADER_TIMEOUT` seconds of the
  connection (or of the previous response) and its body within :data:`BODY_TIMEOUT` (slowloris); the
  connection is closed, or 408 answered.
* Numbers in paths and bodies are bounded (an image number has at most 6 ASCII digits; a JSON number too big
  to read is a 400), and every refusal is a 4xx with a message: no request makes the server answer 500.
* Formulas are parsed by delkit's parser and evaluated by :meth:`KripkeModel.check` — never ``eval``. Request
  bodies are capped at :data:`MAX_BODY` bytes, formulas at ``MAX_FORMULA`` characters and models at
  ``MAX_WORLDS`` worlds, each refused with a message saying the limit.
* Routes: ``GET /<token>/`` the page, ``GET /<token>/static/<name>`` its scripts, ``GET /<token>/api/doc`` the
  document (JSON), ``POST /<token>/api/eval`` ``{"frame", "panel", "formula"}``, ``POST /<token>/api/possible``
  ``{"frame", "panel", "agent", "world"}``, ``GET /<token>/api/image/<frame>`` a frame's picture.
"""

from __future__ import annotations

import asyncio
import json
import re
import secrets
import socket
import threading
from importlib.resources import files
from typing import Any

from delkit.errors import DelkitError, ParseError
from delkit.view.document import Document, document_json, evaluate, possible

__all__ = ["make_app", "bind", "Running", "start", "serve", "MAX_BODY", "STATIC", "HEADER_TIMEOUT", "BODY_TIMEOUT"]

#: the largest request body the server reads (bytes)
MAX_BODY = 64 * 1024

#: seconds a client has to send a request's header (from the connection, or from the previous response)
HEADER_TIMEOUT = 10.0
#: seconds a client has to send a request's body once its header has arrived
BODY_TIMEOUT = 10.0

#: the static files of the page: name → content type (served from the package, by this name only)
STATIC = {"cytoscape.min.js": "text/javascript; charset=utf-8", "view.js": "text/javascript; charset=utf-8",
          "view.css": "text/css; charset=utf-8", "cytoscape.LICENSE.txt": "text/plain; charset=utf-8"}

_CSP = ("default-src 'none'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
        "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'")


def _static(name: str) -> bytes:
    return files("delkit.view").joinpath("static", name).read_bytes()


def make_app(doc: Document, token: str, port: int | None = None, *, body_timeout: float = BODY_TIMEOUT) -> Any:
    """The ASGI app serving ``doc`` under ``/<token>/`` (``port``: the Host header must carry it; the request
    body must arrive within ``body_timeout`` seconds)."""
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
    origins = {f"http://{h}" for h in hosts}

    def error(status: int, message: str, **extra: Any) -> Any:
        return JSONResponse({"ok": False, "error": message, **extra}, status_code=status, headers=headers)

    async def read_json(request: Request) -> Any:
        length = request.headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > MAX_BODY):
            raise _Refused(413, f"request body too large ({length} bytes); the viewer reads at most {MAX_BODY}")
        body = bytearray()

        async def read() -> None:
            async for chunk in request.stream():
                body.extend(chunk)
                if len(body) > MAX_BODY:
                    raise _Refused(413, f"request body too large (over {MAX_BODY} bytes); the viewer reads at "
                                        f"most {MAX_BODY}")

        try:
            await asyncio.wait_for(read(), body_timeout)
        except TimeoutError:
            raise _Refused(408, f"the request body did not arrive within {body_timeout:g} s (got {len(body)} "
                                f"bytes); send it at once") from None
        try:
            data = json.loads(body.decode("utf-8"))
        except (UnicodeDecodeError, ValueError, RecursionError) as exc:  # ValueError: also ints too long to read
            raise _Refused(400, f"the request body is not JSON that the viewer reads ({_short(exc)})") from None
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
        if method != "GET":
            origin = request.headers.get("origin")
            site = request.headers.get("sec-fetch-site")
            if (origin is not None and origin not in origins) or site not in (None, "same-origin", "none"):
                return error(403, f"cross-origin request refused (Origin {origin!r}, Sec-Fetch-Site {site!r}): "
                                  f"the viewer's API answers only its own page")
        try:
            if rest in ([], [""]) and method == "GET":
                return Response(page, media_type="text/html; charset=utf-8", headers=headers)
            if len(rest) == 2 and rest[0] == "static" and method == "GET" and rest[1] in statics:
                return Response(statics[rest[1]], media_type=STATIC[rest[1]], headers=headers)
            if rest == ["api", "doc"] and method == "GET":
                return Response(doc_bytes, media_type="application/json", headers=headers)
            if len(rest) == 3 and rest[:2] == ["api", "image"] and method == "GET":
                if not re.fullmatch(r"[0-9]{1,6}", rest[2]):
                    return error(404, f"no picture {rest[2][:40]!r}: give a frame number "
                                      f"0..{len(doc.frames) - 1} (ASCII digits)")
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
            return error(400, str(exc), line=getattr(exc, "line", None), column=getattr(exc, "column", None))
        except DelkitError as exc:
            return error(400, str(exc))
        except ValueError as exc:  # e.g. an int of thousands of digits in a formula
            return error(400, f"the request cannot be read: {_short(exc)}")
        except RecursionError:
            return error(400, "the formula is nested too deeply to evaluate")
        return error(404, f"no such page: {method} /TOKEN/{'/'.join(rest)}; the viewer serves only its page, "
                          f"its static files and its API")

    methods = ["GET", "POST", "PUT", "DELETE", "PATCH"]
    return Starlette(routes=[Route("/{rest:path}", dispatch, methods=methods)])


def _short(exc: BaseException) -> str:
    text = str(exc)
    return text if len(text) <= 200 else text[:200] + "…"


class _Refused(Exception):
    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status, self.message = status, message


def _html_escape(text: str) -> str:
    from html import escape

    return escape(text)


def _protocol(header_timeout: float) -> type:
    """uvicorn's h11 protocol with a header deadline: a connection (or the next request on a kept-alive one)
    whose request header has not arrived within ``header_timeout`` seconds is closed (slowloris: uvicorn
    alone cancels its keep-alive timer on every byte received, and has none before the first request)."""
    import h11
    from uvicorn.protocols.http.h11_impl import H11Protocol

    class TimedH11(H11Protocol):
        _deadline: Any = None

        def _arm(self) -> None:
            self._disarm()
            self._deadline = self.loop.call_later(header_timeout, self._too_slow)

        def _disarm(self) -> None:
            if self._deadline is not None:
                self._deadline.cancel()
                self._deadline = None

        def _too_slow(self) -> None:
            self._deadline = None
            if not self.transport.is_closing() and self.conn.their_state is h11.IDLE:
                self.transport.close()

        def connection_made(self, transport: Any) -> None:  # type: ignore[override]
            super().connection_made(transport)
            self._arm()

        def data_received(self, data: bytes) -> None:
            super().data_received(data)
            if self.conn.their_state is not h11.IDLE:
                self._disarm()  # the header is in: the body has its own deadline (make_app)

        def on_response_complete(self) -> None:
            super().on_response_complete()
            if not self.transport.is_closing() and self.conn.their_state is h11.IDLE:
                self._arm()

        def connection_lost(self, exc: Exception | None) -> None:
            self._disarm()
            super().connection_lost(exc)

    return TimedH11


def _config(app: Any, header_timeout: float) -> Any:
    import uvicorn

    return uvicorn.Config(app, log_level="warning", lifespan="off", access_log=False,
                          http=_protocol(header_timeout), timeout_keep_alive=int(max(1, header_timeout)))


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

    def __init__(self, doc: Document, port: int = 0, *, header_timeout: float = HEADER_TIMEOUT,
                 body_timeout: float = BODY_TIMEOUT) -> None:
        import uvicorn

        self.sock = bind(port)
        self.port = self.sock.getsockname()[1]
        self.token = secrets.token_urlsafe(32)
        self.url = f"http://127.0.0.1:{self.port}/{self.token}/"
        app = make_app(doc, self.token, self.port, body_timeout=body_timeout)
        self.server = uvicorn.Server(_config(app, header_timeout))
        self.thread = threading.Thread(target=self.server.run, kwargs={"sockets": [self.sock]}, daemon=True)
        self.thread.start()
        while not self.server.started and self.thread.is_alive():
            threading.Event().wait(0.01)

    def stop(self) -> None:
        self.server.should_exit = True
        self.thread.join(timeout=5)
        self.sock.close()


def start(doc: Document, port: int = 0, **timeouts: float) -> Running:
    """Serve ``doc`` in a background thread; returns the :class:`Running` server (its ``url``);
    ``header_timeout`` / ``body_timeout``: see :data:`HEADER_TIMEOUT`, :data:`BODY_TIMEOUT`."""
    return Running(doc, port, **timeouts)


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
    server = uvicorn.Server(_config(app, HEADER_TIMEOUT))
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
