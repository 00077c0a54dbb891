"""The editor's web application (Starlette): the editor, the examples, and pages of models.

Routes:

    GET  /            the editor (assets/editor.html, .js, .css)
    GET  /examples    {"examples": [{"name", "title", "text"}]}: the built-in models
    POST /page        the model text (UTF-8, at most 1 MB) -> {"page": HTML} or
                      {"error": the model's one-line message}, both with status 200: the
                      request was fine, the model is the user's (and a browser's console
                      then logs no failed request at each typo); ?exercise=1 asks
                      for the exercise page (the editor's Exercise toggle)

Only the server's own origin may use it: a request must name one of ``hosts`` in its
Host header (a page of another site that re-points its name at 127.0.0.1, DNS
rebinding, names its own), and a request that carries an Origin (every POST a
browser sends does) must come from ``http://<that host>``; a POST without one is
refused too.  Bodies over :data:`MAX_BODY_BYTES` are refused (413) as soon as the
declared length or the bytes read so far exceed it, never read whole.
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import AsyncIterator, Collection
from importlib import resources

import anyio
from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import ClientDisconnect, Request
from starlette.responses import Response
from starlette.routing import Route
from starlette.types import ASGIApp, Receive, Scope, Send

from ..examples import example_names, example_path, example_title
from .hosts import ServedHosts
from .worker import Renderer

#: The largest model text accepted (the model loader's own limit is the same 1 MiB).
MAX_BODY_BYTES = 1 << 20

#: What the editor's documents may do.  A srcdoc frame inherits its parent's policy, so
#: inline scripts and styles (the model's page is one file) and data: fonts and images
#: must be allowed here; the editor itself shows every text by textContent or value.
CONTENT_SECURITY_POLICY = (
    "default-src 'none'; script-src 'self' 'unsafe-inline'; style-src 'self' 'unsafe-inline'; "
    "font-src data:; img-src data: blob:; connect-src 'self'; frame-src 'self'; "
    "base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
)
_HEADERS = {
    "Content-Security-Policy": CONTENT_SECURITY_POLICY,
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}
_ASSETS = {
    "/": ("editor.html", "text/html; charset=utf-8"),
    "/editor.js": ("editor.js", "text/javascript; charset=utf-8"),
    "/editor.css": ("editor.css", "text/css; charset=utf-8"),
}


def create_app(renderer: Renderer, *, hosts: ServedHosts | Collection[str] | None) -> ASGIApp:
    """The application; ``renderer`` makes the pages (started with the application and
    closed with it; its blocking ``render`` runs in a thread); ``hosts``: the Host header
    values of this server (:func:`~lagrangian.serve.hosts.served_hosts`; a collection of
    them; None: any, for a test's application)."""

    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        await run_in_threadpool(renderer.start)
        try:
            yield
        finally:
            await run_in_threadpool(renderer.close)

    # Pages are made one at a time: a request that waited while the user typed on (the
    # editor then gave it up and closed it) is dropped rather than derived for no one.
    one_at_a_time = anyio.Lock()

    async def page(request: Request) -> Response:
        body = await _bounded_body(request)
        if isinstance(body, Response):
            return body
        try:
            text = body.decode("utf-8")
        except UnicodeDecodeError:
            return _json({"error": "the model text is not UTF-8"}, 400)
        async with one_at_a_time:
            if await request.is_disconnected():
                return Response(status_code=204)
            if request.query_params.get("exercise") == "1":  # the editor's Exercise toggle
                rendered = await run_in_threadpool(renderer.render, text, True)
            else:
                rendered = await run_in_threadpool(renderer.render, text)
        answer = {"page": rendered.page} if rendered.error is None else {"error": rendered.error}
        return _json(answer, 200)

    routes = [Route(path, _asset(*asset), methods=["GET"]) for path, asset in _ASSETS.items()]
    examples = _json({"examples": _examples()}, 200)

    async def example_models(request: Request) -> Response:
        return examples

    routes.append(Route("/examples", example_models, methods=["GET"]))
    routes.append(Route("/page", page, methods=["POST"]))
    return SameOriginOnly(Starlette(routes=routes, lifespan=lifespan), hosts=hosts)


class SameOriginOnly:
    """ASGI middleware: refuses (403) a request for another host or from another origin."""

    def __init__(self, app: ASGIApp, *, hosts: ServedHosts | Collection[str] | None):
        self.app = app
        self.hosts: ServedHosts | frozenset[str] | None = (
            hosts
            if hosts is None or isinstance(hosts, ServedHosts)
            else frozenset(host.lower() for host in hosts)
        )

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            refusal = self._refusal(scope)
            if refusal is not None:
                await _json({"error": refusal}, 403)(scope, receive, send)
                return
        await self.app(scope, receive, send)

    def _refusal(self, scope: Scope) -> str | None:
        headers = {}
        for key, value in scope["headers"]:
            name = key.decode("latin-1").lower()
            if name in headers:  # two Host or Origin headers: which one would a proxy read?
                return f"the header {name} is given twice"
            headers[name] = value.decode("latin-1")
        host = headers.get("host", "").lower()
        if not host or (self.hosts is not None and host not in self.hosts):
            return "this server answers only requests for its own address"
        origin = headers.get("origin")
        if origin is None:
            if scope["method"] not in ("GET", "HEAD"):
                return "cross-origin requests are refused (no Origin header)"
        elif origin.lower() != f"http://{host}":
            return "cross-origin requests are refused"
        if headers.get("sec-fetch-site", "same-origin") not in ("same-origin", "none"):
            return "cross-origin requests are refused"
        return None


async def _bounded_body(request: Request) -> bytes | Response:
    """The request's body, or a 413 response once it is known to exceed the limit (a
    204 for a client gone before its body arrived: closed for being too slow, or its
    editor gave the edit up; nothing to log, nor to derive)."""
    too_large = _json({"error": f"the model text is larger than {MAX_BODY_BYTES} bytes"}, 413)
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > MAX_BODY_BYTES):
        return too_large
    chunks, size = [], 0
    try:
        async for chunk in request.stream():
            size += len(chunk)
            if size > MAX_BODY_BYTES:
                return too_large
            chunks.append(chunk)
    except ClientDisconnect:
        return Response(status_code=204)
    return b"".join(chunks)


def _asset(name: str, media_type: str):
    content = (resources.files(__package__) / "assets" / name).read_bytes()

    async def asset(request: Request) -> Response:
        return Response(content, media_type=media_type, headers=_HEADERS)

    return asset


def _examples() -> list[dict[str, str]]:
    """The built-in models as the editor's menu shows them: name, title, file text."""
    return [
        {
            "name": name,
            "title": example_title(name)[0],
            "text": example_path(name).read_text(encoding="utf-8"),
        }
        for name in example_names()
    ]


def _json(content: object, status: int) -> Response:
    text = json.dumps(content, ensure_ascii=False)
    return Response(text, status, headers=_HEADERS, media_type="application/json")
