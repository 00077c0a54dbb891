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
]
