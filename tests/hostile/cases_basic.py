"""Cases that held before the hardening issue: unknown names, Python syntax, a missing file."""

from hostile.case import HostileCase

CASES = [
    HostileCase(
        "unknown-symbol-in-lagrangian",
        ("derive", "{dir}/model.toml"),
        error=r"model\.toml.*lagrangian.*unknown symbol 'x_dott'",
        model='coordinates = ["x"]\nlagrangian = "x_dott^2"\n',
    ),
    HostileCase(
        "python-attribute-access",
        ("derive", "{dir}/model.toml"),
        error=r"model\.toml.*lagrangian",
        model='coordinates = ["x"]\nlagrangian = "x.__class__"\n',
    ),
    HostileCase("missing-model-file", ("derive", "{dir}/absent.toml"), error=r"absent\.toml"),
    HostileCase(
        "superscript-number-of-4400-digits",
        ("derive", "{dir}/model.toml"),
        error=r"model\.toml: lagrangian: superscript number with 4400 digits too long",
        model='coordinates = ["x"]\nlagrangian = "x_dot^2/2 - x' + "²" * 4400 + '"\n',
    ),
    HostileCase(
        "model-name-of-5000-characters",
        ("derive", "x" * 5000),
        error=r"^lagrangian: error: x{58}\.\.\.x{59}: no such model file or built-in example",
    ),
    HostileCase(
        "model-file-name-of-5000-characters",
        ("derive", "x" * 5000 + ".toml"),
        error=r"\.\.\.x+\.toml: cannot read: File name too long",
    ),
]
