"""``check``: a student's own T, V, L, equations, H, momenta or conserved quantities
against what the toolkit derives.

Each answer gets a verdict (``right``, ``equivalent``: right up to what does not change
the physics, said which; ``wrong``) and, when wrong, the terms at fault in the student's
own terms (missing, extra, a wrong factor or sign).  Answers are text for the safe parser
(plain or LaTeX) in the model's names, or SymPy expressions over them.

    >>> import lagrangian as lg
    >>> result = lg.load("simple_pendulum").check(kinetic="m*l^2*theta_dot^2")
    >>> result.verdict, result.reason
    ('wrong', 'the term l^2*m*theta_dot^2 should be l^2*m*theta_dot^2/2')
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager

import sympy
from sympy.core.function import AppliedUndef

from ...derive import EquationsOfMotion
from ...errors import ModelError, ParseError, setting
from ...parsing import Namespace, parse_expression
from . import answers
from .reference import raw_equations, right_kinetic, right_potential, state_symbols
from .result import PROBLEMS, VERDICTS, AnswerCheck, CheckResult, TermProblem
from .sampling import points

__all__ = [
    "PROBLEMS",
    "VERDICTS",
    "AnswerCheck",
    "CheckResult",
    "TermProblem",
    "check",
    "raw_equations",
    "right_kinetic",
    "right_potential",
    "state_symbols",
]


def check(
    eom: EquationsOfMotion,
    *,
    kinetic: str | sympy.Expr | None = None,
    potential: str | sympy.Expr | None = None,
    lagrangian: str | sympy.Expr | None = None,
    equations: Iterable[str | sympy.Expr] = (),
    hamiltonian: str | sympy.Expr | None = None,
    conserved: Iterable[str | sympy.Expr] = (),
    momenta: Mapping[str, str | sympy.Expr] | None = None,
) -> CheckResult:
    """Check each answer given against the system of ``eom``.

    ``equations``: each ``lhs = rhs`` or an expression equal to 0; ``momenta``: ``p_q``
    (or ``q``) -> the student's dL/dq'.  Raises :class:`~lagrangian.errors.ModelError`
    (one line naming the answer and the text) for an unknown name or a syntax error.
    """
    system = eom.system
    if system.functions:
        raise ModelError("check evaluates expressions at points: the model's unspecified "
                         "functions have no values", field="functions")  # fmt: skip
    symbols = dict(system.symbols)
    state = state_symbols(eom)
    parameters = [p.symbol for p in system.parameters]
    at = points(state, parameters)
    namespace = Namespace(symbols=symbols)
    results = []
    if kinetic is not None:
        right = right_kinetic(eom)
        given = _parsed(kinetic, namespace, setting("kinetic"))
        with _about(setting("kinetic")):
            results.append(answers.by_terms("kinetic", _text(kinetic), given, right, state, at))
    if potential is not None:
        right = right_potential(eom)
        given = _parsed(potential, namespace, setting("potential"))
        with _about(setting("potential")):
            results.append(answers.by_terms("potential", _text(potential), given, right, state,
                                            at, up_to_constant=True))  # fmt: skip
    if lagrangian is not None:
        given = _parsed(lagrangian, namespace, setting("lagrangian"))
        with _about(setting("lagrangian")):
            results.append(answers.lagrangian(_text(lagrangian), given, eom, state, at))
    for index, text in enumerate(equations):
        if eom.constraints is not None:
            raise ModelError("equations of a constrained model (with multipliers) are not "
                             "checked", field=setting("equations"))  # fmt: skip
        given = _equation(text, namespace, f"{setting('equations')} {index + 1}")
        with _about(f"{setting('equations')} {index + 1}"):
            results.append(answers.equation(_text(text), given, eom, state, at))
    if hamiltonian is not None:
        results.append(_hamiltonian(hamiltonian, eom, parameters))
    if momenta:
        for name, text in momenta.items():
            coordinate = _coordinate(system, name)
            given = _parsed(text, namespace, f"{setting('momenta')} {name}")
            right = sympy.diff(system.lagrangian, coordinate.q_dot)
            with _about(f"{setting('momenta')} {name}"):
                results.append(answers.by_terms("momentum", _text(text), given, right, state, at))
    conserved = list(conserved)
    if conserved:
        from ..conserved import conserved_quantities

        known = [(q.name, q.expression) for q in conserved_quantities(eom).conserved]
        for text in conserved:
            given = _parsed(text, namespace, setting("conserved"))
            with _about(setting("conserved")):
                results.append(answers.conserved(_text(text), given, eom, known, state, at))
    if not results:
        raise ModelError("nothing to check: give an answer (kinetic, potential, lagrangian, "
                         "equations, hamiltonian, conserved or momenta)")  # fmt: skip
    return CheckResult(tuple(results))


def _hamiltonian(text, eom: EquationsOfMotion, parameters) -> AnswerCheck:
    from ..hamiltonian import hamiltonian

    system = eom.system
    right = hamiltonian(eom).expression
    phase = {c.name: c.q for c in system.coordinates} | {c.p.name: c.p for c in system.coordinates}
    names = phase | {"t": system.time} | {p.name: p.symbol for p in system.parameters}
    given = _parsed(text, Namespace(symbols=names), setting("hamiltonian"))
    state = frozenset([*phase.values(), system.time])
    at = points(state, parameters)
    with _about(setting("hamiltonian")):
        return answers.by_terms("hamiltonian", _text(text), given, right, state, at,
                                up_to_constant=True)  # fmt: skip


@contextmanager
def _about(field: str) -> Iterator[None]:
    """An answer refused while it is compared (too many terms) names the answer."""
    try:
        yield
    except ModelError as error:
        raise error.located(field=field) from None


def _coordinate(system, name: str):
    for c in system.coordinates:
        if name in (c.name, c.momentum_name):
            return c
    known = ", ".join(c.momentum_name for c in system.coordinates)
    raise ModelError(f"'{name}' is not a momentum of the model (momenta: {known})",
                     field=setting("momenta"))  # fmt: skip


def _text(answer: str | sympy.Expr) -> str:
    return answer if isinstance(answer, str) else str(answer)


def _parsed(
    answer: str | sympy.Expr, namespace: Namespace, field: str, shown: str | None = None
) -> sympy.Expr:
    """The answer as SymPy: text through the safe parser, an expression checked for names."""
    if isinstance(answer, str):
        try:
            return parse_expression(answer, namespace)
        except ParseError as error:
            raise ModelError(str(error), field=field, text=shown or answer) from None
    if not isinstance(answer, sympy.Expr):
        raise ModelError(f"expected text or a SymPy expression, got {type(answer).__name__}",
                         field=field)  # fmt: skip
    known = {symbol.name: symbol for symbol in namespace.symbols.values()
             if isinstance(symbol, sympy.Symbol)}  # fmt: skip
    unknown = sorted(s.name for s in answer.free_symbols if s.name not in namespace.symbols)
    if unknown or answer.has(AppliedUndef):
        raise ModelError(f"unknown symbols {unknown}", field=field, text=str(answer))
    # the student's symbols may carry other assumptions than the model's: use the model's
    return answer.xreplace({s: known[s.name] for s in answer.free_symbols if s.name in known})


def _equation(answer: str | sympy.Expr, namespace: Namespace, field: str) -> sympy.Expr:
    """``lhs = rhs`` as lhs - rhs (an expression alone means expression = 0)."""
    if isinstance(answer, sympy.Equality):
        return _parsed(answer.lhs, namespace, field) - _parsed(answer.rhs, namespace, field)
    if not isinstance(answer, str):
        return _parsed(answer, namespace, field)
    sides = answer.split("=")
    if len(sides) > 2 or any(not side.strip() for side in sides):
        raise ModelError("an equation is 'lhs = rhs' or one expression (= 0)", field=field,
                         text=answer)  # fmt: skip
    if len(sides) == 1:
        return _parsed(answer, namespace, field)
    # each side parsed with the other blanked out: an error's position is in the whole text
    lhs, rhs = sides
    left = _parsed(lhs + " " * (len(rhs) + 1), namespace, field, shown=answer)
    right = _parsed(" " * (len(lhs) + 1) + rhs, namespace, field, shown=answer)
    return left - right
