"""Cases of ``export`` (issue 21): the model's free text must stay inside the generated
file's comments (items 1), constants and large integers must be valid in every language
(items 7, 8), the file's name must not break or shadow what it calls (item 10, and Python
modules), ``--baumgarte`` must be usable (item 11), and ``sign`` must print (low item)."""

from __future__ import annotations

from hostile.case import HostileCase

BODY = 'coordinates = ["x"]\nkinetic = "m*x_dot^2/2"\npotential = "{potential}"\n'
PARAMETERS = "[parameters]\nm = 1.0\nk = 2.0\n"
EXPORT = ("export", "{dir}/model.toml", "--to")


def _model(name: str = "model", description: str = "", potential: str = "k*x^2/2") -> str:
    """A model file whose name and description are TOML basic strings (escapes written as
    given: ``\\n`` is a newline in the file's string)."""
    text = f'name = "{name}"\n'
    if description:
        text += f'description = "{description}"\n'
    return text + BODY.format(potential=potential) + PARAMETERS


C_INJECTION = "*/ int pwned(void) { return 3; } /*"

CASES = [
    # -- item 1: free text ends no comment ------------------------------------------------
    HostileCase(
        "export-c-name-ends-comment",
        (*EXPORT, "c"),
        exit_code=0,
        output=r"\* \* / int pwned\(void\) \{ return 3; \} / \*",
        model=_model(C_INJECTION),
    ),
    HostileCase(
        "export-c-description-ends-comment",
        (*EXPORT, "c"),
        exit_code=0,
        output=r"(?m)^ \* a\n \* \* / int pwned",
        model=_model(description="a\\n" + C_INJECTION),
    ),
    HostileCase(
        "export-numpy-name-ends-docstring",
        (*EXPORT, "numpy"),
        exit_code=0,
        output=r'(?m)^# """; import os; os\._exit\(3\) #: Lagrange',
        model=_model('\\"\\"\\"; import os; os._exit(3) #'),
    ),
    HostileCase(
        "export-numpy-coding-declaration",
        (*EXPORT, "numpy"),
        exit_code=0,
        output=r"\A# -\*- coding: utf-8 -\*-\n# coding: utf-7",
        model=_model("coding: utf-7"),
    ),
    HostileCase(
        "export-julia-description-lines",
        (*EXPORT, "julia"),
        exit_code=0,
        output=r'(?m)^# = # println\("pwned"\)$',
        model=_model(description='ok\\n=# println(\\"pwned\\")'),
    ),
    HostileCase(
        "export-matlab-description-lines",
        (*EXPORT, "matlab"),
        exit_code=0,
        output=r"(?m)^% disp\('pwned'\)$",
        model=_model(description="ok\\ndisp('pwned')"),
    ),
    HostileCase(
        "export-name-newline",
        (*EXPORT, "julia"),
        r"name: control character U\+000A not allowed in text",
        model=_model('a\\nprintln(\\"pwned\\")'),
    ),
    HostileCase(
        "export-name-carriage-return",
        (*EXPORT, "matlab"),
        r"name: control character U\+000D not allowed in text",
        model=_model("a\\rdisp(1)"),
    ),
    HostileCase(
        "export-name-nul",
        (*EXPORT, "numpy"),
        r"name: control character U\+0000 not allowed in text",
        model=_model("a\\u0000b"),
    ),
    HostileCase(
        "export-description-line-separator",
        (*EXPORT, "c"),
        r"description: control character U\+2028 not allowed in text",
        model=_model(description="a\\u2028b"),
    ),
    # -- items 7 and 8: constants and large integers ---------------------------------------
    HostileCase(
        "export-c-math-macros",
        (*EXPORT, "c"),
        exit_code=0,
        output=r"\blog\(2\)",
        model=_model(potential="k*x^2*sqrt(2) + x*log(2) + x*log(10) + 2*x/pi + x/pi"),
    ),
    HostileCase(
        "export-c-huge-integer",
        (*EXPORT, "c"),
        exit_code=0,
        output=r"3\.6893488147419103e\+19",
        model=_model(potential="k*x^2*(2^64 + 1)"),
    ),
    HostileCase(
        "export-julia-huge-integer",
        (*EXPORT, "julia"),
        exit_code=0,
        output=r"-2e\+30 \* p_k",
        model=_model(potential="k*x^2*10^30"),
    ),
    # -- item 10 and the Python module's name ----------------------------------------------
    *(
        HostileCase(
            f"export-matlab-stem-{stem}",
            ("export", "simple_pendulum", "--to", "matlab", "--out", f"{{dir}}/{stem}.m"),
            rf"the MATLAB function cannot be named '{stem}': it is a keyword"
            if keyword
            else rf"the MATLAB function cannot be named '{stem}': the file calls '{stem}'",
        )
        for stem, keyword in (
            ("end", True),
            ("function", True),
            ("rhs", False),
            ("pi", False),
            ("zeros", False),
        )
    ),
    HostileCase(
        "export-numpy-stem-numpy",
        ("export", "simple_pendulum", "--to", "numpy", "--out", "{dir}/numpy.py"),
        r"--out: a module named 'numpy' would be imported instead of Python's 'numpy'",
    ),
    HostileCase(
        "export-numpy-stem-keyword",
        ("export", "simple_pendulum", "--to", "numpy", "--out", "{dir}/class.py"),
        r"--out: a Python module needs a name that is an identifier and not a keyword",
    ),
    # -- item 11: --baumgarte ---------------------------------------------------------------
    *(
        HostileCase(
            f"export-baumgarte-{value}",
            ("export", "rolling_disc", "--to", "c", "--baumgarte", value),
            rf"baumgarte: the Baumgarte stabilisation rate alpha must be a number from 0 "
            rf"\(none\) to 1e\+06 \(1 / time unit\), not {shown}",
        )
        for value, shown in (("nan", "nan"), ("inf", "inf"), ("1e308", r"1e\+308"))
    ),
    # -- sign: its derivative's delta function, and no printer advice --------------------------
    HostileCase(
        "export-sign-in-potential",
        (*EXPORT, "julia"),
        exit_code=0,
        output=r"f\[1\] = -p_k \.\* sign\(q_x\)",
        model=_model(potential="k*x*sign(x)"),
    ),
]
