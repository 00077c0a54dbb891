"""The page refuses a value that leaves a 3-D body with an inertia no body has, as
``lagrangian simulate --set`` does (model/values.check_parameter_values ->
rigid_body.check_inertia): the command line's stderr, word for word, for the triangle
inequality and a negative principal moment, of a diagonal tensor and of a full one (its
eigenvalues), and the value is not taken; a value the command line takes, the page takes.
"""

from __future__ import annotations

import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.output.page import page_html
from output.browser import open_page

pytestmark = pytest.mark.slow

#: A top whose third moment is I3 - d (d may be given any sign), and a tilted box whose
#: tensor is full: its eigenvalues are a - b, a + b and c.
MODELS = {
    "shifted_top": """
name = "shifted top"
coordinates = ["phi", "theta", "psi"]
[parameters]
M = 1.0
l = 0.3
g = 9.81
I1 = 0.01
I3 = 0.02
d = {value = 0.0, sign = "real"}
[[bodies]]
name = "top"
mass = "M"
position = ["l*sin(theta)*sin(phi)", "-l*sin(theta)*cos(phi)", "l*cos(theta)"]
inertia = ["I1", "I1", "I3 - d"]
orientation = {euler = ["phi", "theta", "psi"], convention = "zxz"}
[gravity]
g = "g"
[initial]
theta = 0.4
psi_dot = 20.0
""",
    "tilted_box": """
name = "tilted box"
coordinates = ["phi", "theta", "psi"]
[parameters]
M = 1.0
l = 0.3
g = 9.81
a = 2.0
b = 0.5
c = 3.0
[[bodies]]
name = "box"
mass = "M"
position = ["l*sin(theta)*sin(phi)", "-l*sin(theta)*cos(phi)", "l*cos(theta)"]
inertia = [["a", "b", "0"], ["b", "a", "0"], ["0", "0", "c"]]
orientation = {euler = ["phi", "theta", "psi"], convention = "zxz"}
[gravity]
g = "g"
[initial]
theta = 0.4
""",
}

#: (model, parameter, a value the command line refuses, a value it takes)
CASES = [
    ("heavy_top", "I3", 0.025, 0.0199),  # I3 beyond I1 + I1 = 0.02
    ("heavy_top", "I1", 0.0099, 0.0101),  # then I3 = 0.02 beyond I1 + I1
    ("shifted_top", "d", 0.03, 0.001),  # I3 - d = -0.01: a negative moment
    ("tilted_box", "c", 4.5, 4.0),  # c > (a - b) + (a + b) = 4
    ("tilted_box", "b", 2.5, 0.2),  # a - b = -0.5: the tensor's negative moment
    ("tilted_box", "a", 1.2, 1.5),  # a - b = 0.7, a + b = 1.7: c = 3 > 2.4
]


def model_path(name: str, folder):
    if name not in MODELS:
        return name
    path = folder / f"{name}.toml"
    path.write_text(MODELS[name], encoding="utf-8")
    return str(path)


def command_line_refusal(model: str, name: str, value: float, capsys) -> str | None:
    """What ``lagrangian simulate MODEL --set NAME=VALUE`` says on stderr when it refuses the
    value (None: it takes it); run in this process (the console script is ``main``), not in a
    new Python that imports the package again (a second each, twelve times)."""
    argv = ["simulate", model, "--set", f"{name}={value!r}", "--t-end", "0.01", "--json"]
    status = main(argv)
    stderr = capsys.readouterr().err
    if status == ExitStatus.SUCCESS:
        return None
    assert status == ExitStatus.BAD_INPUT, stderr
    return stderr.strip().removeprefix("lagrangian: error: ")


@pytest.fixture(scope="module")
def pages(tmp_path_factory, browser):
    folder = tmp_path_factory.mktemp("inertia")
    opened = {}

    def page_of(name: str):
        if name not in opened:
            import lagrangian as lg

            model = model_path(name, folder)
            path = folder / f"{name}.html"
            path.write_text(page_html(lg.load(model)), "utf-8")
            opened[name] = (model, open_page(browser, path))
            opened[name][1].page.evaluate("() => lagrangian.pause()")
        return opened[name]

    yield page_of
    for _, page in opened.values():
        page.page.close()


@pytest.mark.parametrize(("model", "name", "refused", "taken"), CASES)
def test_the_page_refuses_an_impossible_inertia_in_the_command_lines_words(
    pages, model, name, refused, taken, capsys
):
    path, opened = pages(model)
    page = opened.page
    expected = command_line_refusal(path, name, refused, capsys)
    assert expected is not None and "inertia" in expected
    before = page.evaluate(f"() => lagrangian.parameters.{name}")
    thrown = page.evaluate(
        "([n, x]) => { try { lagrangian.set(n, x); } catch (e) { return e.message; } }",
        [name, refused],
    )
    assert thrown == expected
    assert page.evaluate(f"() => lagrangian.parameters.{name}") == before  # kept
    assert command_line_refusal(path, name, taken, capsys) is None
    page.evaluate("([n, x]) => lagrangian.set(n, x)", [name, taken])
    assert page.evaluate(f"() => lagrangian.parameters.{name}") == taken
    page.evaluate("([n, x]) => lagrangian.set(n, x)", [name, before])
    assert opened.errors == []
