"""Stage 6: text, LaTeX and JSON formatting (plots and animations come later)."""

from .json_out import derive_document
from .latex import latex_equations, latex_expression, latex_steps
from .text import format_equations, format_steps, unicode_expression

__all__ = [
    "derive_document",
    "format_equations",
    "format_steps",
    "latex_equations",
    "latex_expression",
    "latex_steps",
    "unicode_expression",
]
