"""JSON encoding of symbolic results with a whitelist: decoding can build data, never run code.

A value is encoded as plain JSON (``None``, booleans, numbers, strings) or as a one-key
object naming its kind:

* ``{"t": [...]}`` a tuple, ``{"l": [...]}`` a list, ``{"d": [[k, v], ...]}`` a dict;
* ``{"M": [rows, cols, [entries]]}`` a ``sympy.Matrix``;
* ``{"e": node}`` a SymPy expression, ``node`` a list ``[kind, ...]`` with ``kind`` one of
  :data:`NODES` (numbers as decimal strings, symbols with their only allowed assumption,
  ``real``);
* ``{"dc": name, "f": {field: value}}`` an instance of a dataclass registered with
  :func:`register_dataclass`.

Anything else raises :class:`CodecError`, both ways: an unknown node type while encoding (the
value is then not cached) and an unknown tag, node or dataclass while decoding (the file is
ignored). Expressions are rebuilt with ``evaluate=False`` from their stored arguments, so they
come back identical to what was stored.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import sympy as sp

__all__ = ["CodecError", "encode", "decode", "register_dataclass", "NODES"]


class CodecError(ValueError):
    """A value outside the whitelist (encoding), or a document that is not one of ours (decoding)."""


_FUNCTIONS: dict[str, Any] = {
    "sin": sp.sin,
    "cos": sp.cos,
    "tan": sp.tan,
    "asin": sp.asin,
    "acos": sp.acos,
    "atan": sp.atan,
    "atan2": sp.atan2,
}
_OPS: dict[str, Any] = {"Add": sp.Add, "Mul": sp.Mul, "Pow": sp.Pow}
NODES = ("Symbol", "Integer", "Rational", "Float", "pi", *_OPS, *_FUNCTIONS)
"""The SymPy node kinds a cache file may contain."""

_DATACLASSES: dict[str, type] = {}


def register_dataclass(cls: type) -> type:
    """Allow instances of the dataclass ``cls`` in the cache (usable as a decorator)."""
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls.__name__} is not a dataclass")
    _DATACLASSES[cls.__name__] = cls
    return cls


# ------------------------------------------------------------------ encoding
def _node(e: sp.Basic) -> list[Any]:
    if isinstance(e, sp.Symbol) and type(e) is sp.Symbol:
        if e == sp.Symbol(e.name, real=True):
            return ["Symbol", e.name, True]
        if e == sp.Symbol(e.name):
            return ["Symbol", e.name, False]
        raise CodecError(f"symbol {e} has assumptions other than real=True")
    if isinstance(e, sp.Integer):
        return ["Integer", str(int(e))]
    if isinstance(e, sp.Rational):
        return ["Rational", str(int(e.p)), str(int(e.q))]
    if isinstance(e, sp.Float):
        return ["Float", str(e), int(e._prec)]  # noqa: SLF001
    if e is sp.pi:
        return ["pi"]
    for name, op in _OPS.items():
        if type(e) is op:
            return [name, *(_node(a) for a in e.args)]
    for name, fn in _FUNCTIONS.items():
        if type(e) is fn:
            return [name, *(_node(a) for a in e.args)]
    raise CodecError(f"cannot cache a {type(e).__name__}")


def encode(value: object) -> Any:
    """``value`` as JSON-ready data (see the module docstring); raises :class:`CodecError`."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        if value != value or value in (float("inf"), float("-inf")):
            raise CodecError("non-finite float")
        return value
    if isinstance(value, tuple):
        return {"t": [encode(v) for v in value]}
    if isinstance(value, list):
        return {"l": [encode(v) for v in value]}
    if isinstance(value, dict):
        return {"d": [[encode(k), encode(v)] for k, v in value.items()]}
    if isinstance(value, sp.MatrixBase):
        return {"M": [value.rows, value.cols, [encode(e) for e in value]]}
    if isinstance(value, sp.Basic):
        return {"e": _node(value)}
    if dataclasses.is_dataclass(value) and _DATACLASSES.get(type(value).__name__) is type(value):
        return {
            "dc": type(value).__name__,
            "f": {f.name: encode(getattr(value, f.name)) for f in dataclasses.fields(value)},
        }
    raise CodecError(f"cannot cache a {type(value).__name__}")


# ------------------------------------------------------------------ decoding
def _int(text: object) -> int:
    if not isinstance(text, str) or len(text) > 4000:
        raise CodecError("bad integer")
    return int(text)


def _expr(node: object) -> sp.Basic:
    if not isinstance(node, list) or not node or not isinstance(node[0], str):
        raise CodecError("bad expression node")
    kind, args = node[0], node[1:]
    if kind == "Symbol":
        if len(args) != 2 or not isinstance(args[0], str) or not isinstance(args[1], bool):
            raise CodecError("bad symbol")
        return sp.Symbol(args[0], real=True) if args[1] else sp.Symbol(args[0])
    if kind == "Integer" and len(args) == 1:
        return sp.Integer(_int(args[0]))
    if kind == "Rational" and len(args) == 2:
        return sp.Rational(_int(args[0]), _int(args[1]))
    if kind == "Float" and len(args) == 2 and isinstance(args[0], str) and isinstance(args[1], int):
        try:
            mantissa = float(args[0])
        except ValueError:
            raise CodecError("bad float") from None
        if mantissa != mantissa or abs(mantissa) == float("inf"):
            raise CodecError("non-finite float")
        return sp.Float(args[0], precision=max(1, min(args[1], 10_000)))
    if kind == "pi" and not args:
        return sp.pi
    if kind in _OPS:
        return _OPS[kind](*(_expr(a) for a in args), evaluate=False)
    if kind in _FUNCTIONS:
        return _FUNCTIONS[kind](*(_expr(a) for a in args), evaluate=False)
    raise CodecError(f"node {kind!r} is not allowed")


def decode(data: object) -> object:
    """The value encoded by :func:`encode`; raises :class:`CodecError` on anything else."""
    if data is None or isinstance(data, (bool, str, int, float)):
        return data
    if not isinstance(data, dict) or len(data) not in (1, 2):
        raise CodecError("bad value")
    if "dc" in data:
        cls = _DATACLASSES.get(data["dc"]) if isinstance(data["dc"], str) else None
        fields = data.get("f")
        if cls is None or not isinstance(fields, dict):
            raise CodecError(f"dataclass {data['dc']!r} is not allowed")
        names = {f.name for f in dataclasses.fields(cls)}
        if set(fields) - names:
            raise CodecError(f"unknown fields for {cls.__name__}")
        return cls(**{k: decode(v) for k, v in fields.items()})
    if len(data) != 1:
        raise CodecError("bad value")
    ((tag, body),) = data.items()
    if tag in ("t", "l") and isinstance(body, list):
        items = [decode(v) for v in body]
        return tuple(items) if tag == "t" else items
    if tag == "d" and isinstance(body, list):
        out = {}
        for pair in body:
            if not isinstance(pair, list) or len(pair) != 2:
                raise CodecError("bad dict item")
            key = decode(pair[0])
            if isinstance(key, (dict, list)):
                raise CodecError("unhashable key")
            out[key] = decode(pair[1])
        return out
    if tag == "M" and isinstance(body, list) and len(body) == 3:
        rows, cols, entries = body
        if not (isinstance(rows, int) and isinstance(cols, int) and isinstance(entries, list)):
            raise CodecError("bad matrix")
        if rows < 0 or cols < 0 or rows * cols != len(entries):
            raise CodecError("bad matrix shape")
        return sp.Matrix(rows, cols, [decode(e) for e in entries])
    if tag == "e":
        return _expr(body)
    raise CodecError(f"tag {tag!r} is not allowed")
