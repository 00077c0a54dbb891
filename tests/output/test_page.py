"""The page's HTML text: self-contained, a policy that allows nothing external, model text
kept as data, the project's errors for what does not fit the model (the browser checks are
in test_page_browser.py)."""

from __future__ import annotations

import json
import re

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.output.page import json_for_html, page_html

HOSTILE_NAME = "</script><script>window.pwned = 1</script>"
HOSTILE_DESCRIPTION = '<img src=x onerror="window.pwned = 2"> & <!-- é'

#: A model whose free texts try to break out of the page (the browser test runs it).
HOSTILE_MODEL = f"""
name = {json.dumps(HOSTILE_NAME)}
description = {json.dumps(HOSTILE_DESCRIPTION)}
coordinates = ["x"]
kinetic = "m*x_dot**2/2"
potential = "k*x**2/2"
[parameters]
k = 1.0
m = 1.0
[initial]
x = 1.0
"""


@pytest.fixture(scope="module")
def pendulum_page() -> str:
    return page_html(lg.load("simple_pendulum"))


def test_page_is_one_self_contained_file(pendulum_page):
    assert pendulum_page.startswith("<!DOCTYPE html>")
    assert len(pendulum_page.encode("utf-8")) < 2_000_000
    # nothing is loaded from anywhere: no element with src or href, no url() but data: fonts
    markup = re.sub(r"<script[^>]*>.*?</script>", "", pendulum_page, flags=re.DOTALL)
    assert not re.search(r"\s(src|href)\s*=", markup)
    urls = re.findall(r"url\(([^)]*)\)", pendulum_page)
    assert urls and all(url.startswith("data:font/woff2;base64,") for url in urls)


def test_content_security_policy_allows_only_the_pages_own_scripts(pendulum_page):
    policy = re.search(r'http-equiv="Content-Security-Policy" content="([^"]*)"', pendulum_page)
    assert policy is not None
    rules = dict(rule.strip().split(" ", 1) for rule in policy.group(1).split(";"))
    assert rules["default-src"] == "'none'"
    assert rules["font-src"] == "data:"
    scripts = rules["script-src"].split()
    assert len(scripts) == 2 and all(s.startswith("'sha256-") for s in scripts)
    assert "unsafe-inline" not in rules["script-src"] and "unsafe-eval" not in rules["script-src"]


def test_json_for_html_escapes_what_could_end_the_script():
    text = json_for_html({"name": "</script><!-- & \u2028\u2029 é"})
    assert not re.search(r"[<>&\u2028\u2029]", text) and text.isascii()
    assert json.loads(text) == {"name": "</script><!-- & \u2028\u2029 é"}


def test_hostile_model_text_never_reaches_the_html_as_markup():
    page = page_html(lg.loads(HOSTILE_MODEL))
    assert HOSTILE_NAME not in page
    markup = re.sub(r"<script[^>]*>.*?</script>", "", page, flags=re.DOTALL)
    assert "<img" not in markup and "onerror" not in markup
    assert page.lower().count("</script>") == 3  # the page's own three script elements
    assert "&lt;/script&gt;&lt;script&gt;" in page  # the title, HTML-escaped


def test_parameters_and_initial_values_are_checked():
    system = lg.load("simple_pendulum")
    with pytest.raises(ModelError, match="unknown parameter 'mass'"):
        page_html(system, parameters={"mass": 1.0})
    with pytest.raises(ModelError, match="'phi' is not a coordinate or velocity"):
        page_html(system, initial={"phi": 1.0})
    with pytest.raises(ModelError, match="theta_dot"):
        page_html(system, initial={"theta_dot": float("nan")})


def test_given_values_are_the_pages_starting_point():
    page = page_html(lg.load("simple_pendulum"), parameters={"g": 1.62}, initial={"theta": 0.3})
    document = json.loads(
        re.search(r'id="lagrangian-model">(.*?)</script>', page, re.DOTALL).group(1)
    )
    assert {p["name"]: p["value"] for p in document["parameters"]}["g"] == 1.62
    assert document["initial"] == {"theta": 0.3, "theta_dot": 0.0}
