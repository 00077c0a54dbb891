"""Stage 6: text, LaTeX and JSON formatting (plots and animations come later).

Each name is imported when first read (:func:`lagrangian.lazy.on_use`): ``derive --json``
loads the JSON writer only, not the text's and LaTeX's notation.
"""

from ..lazy import on_use

_ON_USE = {
    "derive_document": ".json_out",
    "format_equations": ".text",
    "format_steps": ".text",
    "latex_equations": ".latex",
    "latex_expression": ".latex",
    "latex_steps": ".latex",
    "unicode_expression": ".text",
}

__all__ = sorted(_ON_USE)

__getattr__ = on_use(__name__, _ON_USE)
