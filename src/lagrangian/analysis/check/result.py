"""What ``check`` answers: a verdict, its reason, and the terms at fault (frozen objects)."""

from __future__ import annotations

from dataclasses import dataclass

#: The verdicts, best first.
VERDICTS = ("right", "equivalent", "wrong")
#: What can be wrong with one term.
PROBLEMS = ("missing", "extra", "factor", "sign")


def readable(text: str | None) -> str:
    """An expression as a student writes it (``^`` for powers)."""
    return "" if text is None else text.replace("**", "^")


@dataclass(frozen=True)
class TermProblem:
    """One term at fault: ``term`` as the student wrote it (for ``missing``: the term that
    should be there), ``problem`` (one of :data:`PROBLEMS`) and ``expected``, the right
    term (None for ``extra``).  Expressions in SymPy syntax over the model's names."""

    term: str
    problem: str
    expected: str | None

    def sentence(self) -> str:
        term, expected = readable(self.term), readable(self.expected)
        if self.problem == "missing":
            return f"the term {term} is missing"
        if self.problem == "extra":
            return f"the term {term} should not be there"
        if self.problem == "sign":
            return f"the term {term} has the wrong sign: it should be {expected}"
        return f"the term {term} should be {expected}"

    def document(self) -> dict:
        return {"term": self.term, "problem": self.problem, "expected": self.expected}


@dataclass(frozen=True)
class AnswerCheck:
    """One answer checked: ``quantity`` (``kinetic``, ``potential``, ``lagrangian``,
    ``equation``, ``hamiltonian``, ``conserved``, ``momentum``), the text ``given``, the
    ``verdict`` (one of :data:`VERDICTS`), the ``reason`` in words and the ``terms`` at
    fault (empty unless wrong)."""

    quantity: str
    given: str
    verdict: str
    reason: str
    terms: tuple[TermProblem, ...] = ()

    def document(self) -> dict:
        return {
            "quantity": self.quantity,
            "given": self.given,
            "verdict": self.verdict,
            "reason": self.reason,
            "terms": [term.document() for term in self.terms],
        }


@dataclass(frozen=True)
class CheckResult:
    """Every answer checked; ``verdict`` is the worst of theirs, ``reason`` and ``terms``
    theirs together (a single answer's own when there is one)."""

    answers: tuple[AnswerCheck, ...]

    @property
    def verdict(self) -> str:
        return max((a.verdict for a in self.answers), key=VERDICTS.index, default="right")

    @property
    def reason(self) -> str:
        if len(self.answers) == 1:
            return self.answers[0].reason
        return "; ".join(f"{a.quantity}: {a.reason}" for a in self.answers)

    @property
    def terms(self) -> tuple[TermProblem, ...]:
        return tuple(term for a in self.answers for term in a.terms)

    def document(self) -> dict:
        """The JSON document of ``lagrangian check --json``."""
        return {
            "verdict": self.verdict,
            "reason": self.reason,
            "terms": [term.document() for term in self.terms],
            "answers": [a.document() for a in self.answers],
        }

    def __repr__(self) -> str:
        return f"<CheckResult {self.verdict}: {self.reason}>"
