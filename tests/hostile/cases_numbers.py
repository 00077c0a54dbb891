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

BODY = """coordinates = ["phi", "theta", "psi"]
[parameters]
m = 1.0
I = 1e200
[[bodies]]
name = "top"
mass = "m"
position = [0, 0, 0]
inertia = [{inertia}]
orientation = {{ euler = ["phi", "theta", "psi"] }}
"""

CASES += [
    *(
        HostileCase(
            f"body-inertia-{name}",
            ("derive", "{dir}/model.toml"),
            error=r"model\.toml: bodies\[0\]\.inertia.*" + error,
            model=BODY.format(inertia=inertia),
        )
        for name, inertia, error in (
            ("10-to-400", '"10**400", "1", "1"', r"the number 1000.* beyond double precision"),
            ("1e400-text", '"1e400", "1", "1"', r"the number 1000.* beyond double precision"),
            ("1e400-literal", "1e400, 1, 1", r"expected a finite number, got inf"),
            ("nan-literal", "nan, 1, 1", r"expected a finite number, got nan"),
            ("square-beyond", '"I*I", "I", "I"', r"the inertia I\*\*2 = inf .* not a finite"),
        )
    ),
    HostileCase(
        "body-inertia-10-to-300-derived-quickly",
        ("derive", "{dir}/model.toml", "--json"),
        exit_code=0,
        output=r'"mass_matrix"',
        model=BODY.format(inertia='"10**300", "10**300 + 1", "3"'),
    ),
    HostileCase(
        "spring-constant-beyond-double",
        ("derive", "{dir}/model.toml"),
        error=r"model\.toml: potential.*the number 1/1000.* beyond double precision",
        model=_potential("x^2/10**400"),
    ),
]

CASES += [
    HostileCase(
        f"simulate-table-t-end-{name}",
        ("simulate", "{dir}/model.toml"),
        error=rf"model\.toml: simulate\.t_end: expected a {kind}, got {shown}$",
        model=_potential("x^2/2") + f"[simulate]\nt_end = {value}\n",
    )
    for name, value, kind, shown in (
        ("text", '"abc"', "number", "'abc'"),
        ("boolean", "true", "number", "True"),
        ("inf", "inf", "finite number", "inf"),
    )
]
