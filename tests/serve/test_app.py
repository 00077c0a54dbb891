"""The editor's web application through Starlette's TestClient (no server, no socket).

The security checks run with a stand-in renderer that records what reached it (a
refused request must not); pages and error lines of real models come from the real
worker process, started once for the module.
"""

from __future__ import annotations

import asyncio
import json
import warnings
from collections.abc import Iterator

import pytest

pytest.importorskip("starlette", reason="the serve extra (starlette) is not installed")
pytest.importorskip("httpx", reason="Starlette's TestClient needs httpx")

with warnings.catch_warnings():  # Starlette 1.x announces a move of its TestClient to httpx2
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient

from lagrangian.cli import ExitStatus, main
from lagrangian.errors import LagrangianError
from lagrangian.examples import example_names, example_path
from lagrangian.serve import served_hosts
from lagrangian.serve.app import MAX_BODY_BYTES, create_app
from lagrangian.serve.models import model_from_text
from lagrangian.serve.worker import PageWorker, Rendered

HOST = "127.0.0.1:8765"
ORIGIN = f"http://{HOST}"
SAME_ORIGIN = {"Origin": ORIGIN}
OSCILLATOR = "m*x_dot**2/2 - k*x**2/2"


class Recorder:
    """A renderer that records the texts it is given and answers a fixed page."""

    def __init__(self):
        self.texts: list[str] = []
        self.exercises: list[bool] = []

    def start(self) -> None:
        pass

    def render(self, text: str, exercise: bool = False) -> Rendered:
        self.texts.append(text)
        self.exercises.append(exercise)
        return Rendered(page="<!doctype html><p>page</p>")

    def close(self) -> None:
        pass


def client_of(renderer) -> TestClient:
    return TestClient(create_app(renderer, hosts=served_hosts("127.0.0.1", 8765)), base_url=ORIGIN)


@pytest.fixture
def recorder():
    return Recorder()


@pytest.fixture
def client(recorder):
    with client_of(recorder) as client:
        yield client


@pytest.fixture(scope="module")
def real_client():
    worker = PageWorker()
    with client_of(worker) as client:  # the lifespan starts the worker and stops it
        yield client
    assert worker._process is None  # stopped with the application


# -- pages and errors of real models ----------------------------------------------------
@pytest.mark.slow
def test_a_good_model_returns_its_page(real_client):
    response = real_client.post("/page", content=OSCILLATOR, headers=SAME_ORIGIN)
    assert response.status_code == 200
    page = response.json()["page"]
    assert page.lower().startswith("<!doctype html")
    assert response.headers["content-type"] == "application/json"


def test_a_model_file_returns_its_page(real_client):
    text = example_path("harmonic_oscillator").read_text()
    response = real_client.post("/page", content=text.encode(), headers=SAME_ORIGIN)
    assert response.status_code == 200
    assert response.json()["page"].lower().startswith("<!doctype html")


@pytest.mark.parametrize(
    "text",
    [
        OSCILLATOR + " +",
        'name = "x"\ncoordinates = ["x"]\nlagrangian = "x_dot**2 + y"\n',
        'name = "</script><img src=x onerror=alert(1)>"\ncoordinates = 3\n',
    ],
)
def test_a_bad_model_returns_the_error_line_the_cli_prints(
    real_client, text, tmp_path, monkeypatch, capsys
):
    response = real_client.post("/page", content=text, headers=SAME_ORIGIN)
    assert response.status_code == 200
    assert "page" not in response.json()
    error = response.json()["error"]
    with pytest.raises(LagrangianError) as caught:
        model_from_text(text)
    assert error == str(caught.value)
    if "=" in text:  # the same text as a model file named like the editor, through the CLI
        monkeypatch.chdir(tmp_path)
        (tmp_path / "editor").write_text(text)
        assert main(["derive", "editor"]) == ExitStatus.BAD_INPUT
        assert capsys.readouterr().err == f"lagrangian: error: {error}\n"


def test_a_page_in_the_making_does_not_hold_up_other_requests():
    """The renderer, once called, waits until the editor has been served meanwhile: were
    it run on the event loop, nothing else would be served until it gave up."""
    import threading

    import httpx

    rendering, served = threading.Event(), threading.Event()

    class Waiting(Recorder):
        def render(self, text: str) -> Rendered:
            rendering.set()
            if not served.wait(timeout=60):
                return Rendered(error="the editor was not served meanwhile")
            return super().render(text)

    app = create_app(Waiting(), hosts=None)

    async def both():
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url=ORIGIN) as client:
            posting = asyncio.ensure_future(
                client.post("/page", content=OSCILLATOR, headers=SAME_ORIGIN)
            )
            await asyncio.to_thread(rendering.wait, 60)
            editor = await client.get("/")
            served.set()
            return editor, await posting

    editor, page = asyncio.run(asyncio.wait_for(both(), timeout=120))
    assert editor.status_code == 200
    assert page.json() == {"page": "<!doctype html><p>page</p>"}


# -- the editor and its examples --------------------------------------------------------
def test_the_editor_is_served_with_its_policy(client):
    response = client.get("/")
    assert response.status_code == 200
    assert 'sandbox="allow-scripts"' in response.text
    policy = response.headers["content-security-policy"]
    assert "default-src 'none'" in policy and "connect-src 'self'" in policy
    assert "frame-ancestors 'none'" in policy
    assert client.get("/editor.js").headers["content-type"].startswith("text/javascript")


def test_the_examples_are_every_built_in_model(client):
    examples = client.get("/examples").json()["examples"]
    assert [example["name"] for example in examples] == list(example_names())
    for example in examples:
        assert example["text"] == example_path(example["name"]).read_text()


# -- bodies ------------------------------------------------------------------------------
def test_the_exercise_toggle_asks_for_the_exercise_page(client, recorder):
    for address in ("/page", "/page?exercise=1", "/page?exercise=0"):
        assert client.post(address, content=OSCILLATOR, headers=SAME_ORIGIN).status_code == 200
    assert recorder.exercises == [False, True, False]


def test_a_body_of_one_megabyte_is_read(client, recorder):
    response = client.post("/page", content=b"x" * MAX_BODY_BYTES, headers=SAME_ORIGIN)
    assert response.status_code == 200
    assert len(recorder.texts[0]) == MAX_BODY_BYTES


def test_a_body_declared_over_one_megabyte_is_refused(client, recorder):
    response = client.post("/page", content=b"x" * (MAX_BODY_BYTES + 1), headers=SAME_ORIGIN)
    assert response.status_code == 413
    assert response.json() == {"error": "the model text is larger than 1048576 bytes"}
    assert recorder.texts == []


def call(app, messages: Iterator[dict]) -> list[dict]:
    """Run ``app`` on one POST /page whose receive hands out ``messages``, then waits;
    the messages it sent back."""
    scope = {
        "type": "http",
        "method": "POST",
        "path": "/page",
        "raw_path": b"/page",
        "query_string": b"",
        "root_path": "",
        "scheme": "http",
        "http_version": "1.1",
        "server": ("127.0.0.1", 8765),
        "headers": [(b"host", HOST.encode()), (b"origin", ORIGIN.encode())],
    }
    sent = []

    async def receive():
        message = next(messages, None)
        if message is None:
            await asyncio.sleep(3600)  # nothing more from the client
        return message

    async def send(message):
        sent.append(message)

    asyncio.run(app(scope, receive, send))
    return sent


def test_a_body_without_length_is_refused_before_it_is_read_whole(recorder):
    """An endless chunked body: refused once the bytes read exceed the limit."""
    chunk = {"type": "http.request", "body": b"x" * 65536, "more_body": True}
    chunks = iter([chunk] * 100)  # 6.5 MB offered
    sent = call(create_app(recorder, hosts=None), chunks)
    assert sent[0]["status"] == 413
    assert len(list(chunks)) == 100 - (MAX_BODY_BYTES // 65536 + 1)  # the rest never read
    assert recorder.texts == []


def test_a_request_given_up_while_it_waited_is_not_derived(recorder):
    body = {"type": "http.request", "body": OSCILLATOR.encode(), "more_body": False}
    sent = call(create_app(recorder, hosts=None), iter([body, {"type": "http.disconnect"}]))
    assert sent[0]["status"] == 204
    assert recorder.texts == []


def test_a_body_that_is_not_utf8_is_refused(client, recorder):
    response = client.post("/page", content=b"\xff\xfe", headers=SAME_ORIGIN)
    assert response.status_code == 400
    assert recorder.texts == []


# -- origins -----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "headers",
    [
        {"Origin": "http://evil.example"},
        {"Origin": "null"},  # a sandboxed frame, the model's page included
        {"Origin": "https://127.0.0.1:8765"},
        {"Origin": "http://127.0.0.1:8766"},
        {},  # a POST without an Origin
        {"Origin": ORIGIN, "Sec-Fetch-Site": "cross-site"},
        {"Origin": "http://evil.example:8765", "Host": "evil.example:8765"},  # DNS rebinding
    ],
)
def test_a_cross_origin_post_is_refused(client, recorder, headers):
    response = client.post("/page", content=OSCILLATOR, headers=headers)
    assert response.status_code == 403
    assert "refused" in response.json()["error"] or "own address" in response.json()["error"]
    assert recorder.texts == []


def test_a_request_for_another_host_is_refused(client):
    assert client.get("/", headers={"Host": "evil.example:8765"}).status_code == 403
    assert client.get("/examples", headers={"Origin": "http://evil.example"}).status_code == 403


@pytest.mark.parametrize("host", ["127.0.0.1:8765", "localhost:8765", "[::1]:8765"])
def test_the_names_of_this_machine_are_its_own_origin(client, recorder, host):
    headers = {"Host": host, "Origin": f"http://{host}", "Sec-Fetch-Site": "same-origin"}
    response = client.post("/page", content=OSCILLATOR, headers=headers)
    assert response.status_code == 200
    assert recorder.texts == [OSCILLATOR]


def test_a_refusal_is_json_not_markup(client):
    response = client.post("/page", content="x", headers={"Origin": "http://<script>"})
    assert response.headers["content-type"] == "application/json"
    assert json.loads(response.text)["error"]
