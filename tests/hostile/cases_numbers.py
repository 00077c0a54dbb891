"""Numbers beyond double precision, in expressions and in the model's physical values; the
[simulate] table's types; oversized inputs (issue 21, items 4 and 5, low items)."""

from hostile.case import HostileCase

BEYOND = r"the number {made} is beyond double precision \(about 10\^[-0-9.e+]+\)"


def _potential(text: str) -> str:
    return f'coordinates = ["x"]\nkinetic = "x_dot^2/2"\npotential = "{text}"\n'


CASES = [
    *(
        HostileCase(
            f"huge-constant-{name}",
            ("derive", "{dir}/model.toml"),
            error=r"model\.toml.*potential.*" + BEYOND.format(made=made),
            model=_potential(text),
        )
        for name, text, made in (
            ("atan2-cosh-cosh", "atan2(x, -cosh(cosh(123456789)))", r"cosh\(123456789\)"),
            ("sign-cosh-cosh", "sign(1 - cosh(cosh(123456789)))*x", r"cosh\(123456789\)"),
            ("abs-cosh-cosh", "Abs(1 - cosh(cosh(123456789)))*x", r"cosh\(123456789\)"),
            ("atan2-exp-exp", "atan2(x, -exp(exp(123456789)))", r"exp\(123456789\)"),
            ("acos-cosh-cosh", "acos(cosh(cosh(123456789)))*x", r"cosh\(123456789\)"),
            ("power-of-exp", "x*2^exp(700)", r"\(2\)\*\*\(exp\(700\)\)"),
            ("tiny-exp", "atan2(x, exp(-123456789))", r"exp\(-123456789\)"),
        )
    ),
]
