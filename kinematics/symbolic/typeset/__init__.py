"""Typesetting symbolic J: printers (LaTeX, MathML, text), layout, escaping, code generation and exports."""
