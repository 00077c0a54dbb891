"""`lagrangian page`: the file written (atomically, where asked), --set, one-line errors."""

from __future__ import annotations

import json
import re

from lagrangian.cli import ExitStatus, main


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def _document(path) -> dict:
    text = path.read_text(encoding="utf-8")
    return json.loads(re.search(r'id="lagrangian-model">(.*?)</script>', text, re.DOTALL).group(1))


def test_page_writes_the_file_with_the_values_set(capsys, tmp_path):
    out = tmp_path / "oscillator.html"
    status, stdout, _ = run(
        capsys, "page", "harmonic_oscillator", "--out", str(out), "--set", "k=4", "--set", "x=0.5"
    )
    assert status == ExitStatus.SUCCESS
    assert stdout.startswith(f"wrote {out}")
    document = _document(out)
    assert {p["name"]: p["value"] for p in document["parameters"]}["k"] == 4.0
    assert document["initial"]["x"] == 0.5
    assert [p.name for p in tmp_path.iterdir()] == ["oscillator.html"]  # no temporary left


def test_default_output_is_named_after_the_model(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, _, _ = run(capsys, "page", "simple_pendulum")
    assert status == ExitStatus.SUCCESS
    assert (tmp_path / "simple_pendulum.html").is_file()


def test_bad_inputs_are_one_line_errors(capsys, tmp_path):
    cases = [
        (["--out", str(tmp_path / "page.txt")], "must end in .html"),
        (["--out", str(tmp_path / "missing" / "page.html")], "does not exist"),
        (["--set", "nope=1"], "'nope' is neither a parameter nor a coordinate or velocity"),
        (["--set", "k=-1"], "k"),
    ]
    for extra, message in cases:
        status, _, err = run(capsys, "page", "harmonic_oscillator", *extra)
        assert status == ExitStatus.BAD_INPUT, extra
        assert message in err and len(err.strip().splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []
