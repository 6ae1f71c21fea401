"""Straight-line chain code generated per robot: one configuration in scalar floats, a batch in
whole-array NumPy operations.

:class:`Compiled` writes, for one robot, Python source that evaluates its chain
T = F₀ · M₁(q) · F₁ ⋯ M_m(q) · F_m (:meth:`~kinematics.model.Robot.fixed_transforms`) with every
constant folded in: zeros and ones of the fixed transforms vanish, a rotation by ±π/2 is a renaming
with a sign, and each expression is formed once. The text holds only fixed identifiers (``q3``,
``c2``, ``v17``) and float literals written with ``repr`` — never a name or any text of the model —
and is compiled with :func:`compile` once per robot and kind of output.

Run on Python floats with ``math.cos``/``math.sin`` it is the single-configuration path (fk, J,
joint and link frames from one pass, packed into one array). The batched text is the same chain
run on the rows of a chunk (every name then an array over the chunk), with cos and sin formed
from ``numpy.tan`` of the half angle (NumPy's vectorised tan costs a fifth of its sin) and each
array deleted after its last use. The angle is the very argument of
:func:`kinematics.kernel.chain_scan` (q·multiplier + offset); math, NumPy's sin and cos and its
tan all reduce it modulo 2π accurately, so a huge |q| gives the same rigid pose.
"""

from __future__ import annotations

import math
import re
import struct
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Chain", "Compiled", "generate", "MAX_AXES"]

FloatArray = NDArray[np.float64]
MAX_AXES = 64
"""Longest chain (moving axes) given generated code; longer ones use the NumPy scan."""
_TINY = 1e-15  # rotation entries below this (cos ±π/2 = 6e-17) are zeros

# A value of the generated code: a float known when generating, or coefficient × variable.
Value = float | tuple[float, str]
Vector = list[Value]


def _literal(x: float) -> str:
    text = repr(float(x))
    return f"({text})" if text.startswith("-") else text


class _Writer:
    """Emits statements ``vN = expression``, folding constants and reusing single terms."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.count = 0
        self.known: dict[str, tuple[float, str]] = {}

    def line(self, text: str) -> None:
        self.lines.append("    " + text)

    def sum(self, *products: Sequence[Value]) -> Value:
        """Σ of products of values, as a constant, one scaled variable or a new variable."""
        constant = 0.0
        monomials: dict[tuple[str, ...], float] = {}
        for factors in products:
            coef, names = 1.0, []
            for f in factors:
                if isinstance(f, tuple):
                    coef *= f[0]
                    names.append(f[1])
                else:
                    coef *= f
            if coef == 0.0:
                continue
            if names:
                key = tuple(sorted(names))
                monomials[key] = monomials.get(key, 0.0) + coef
            else:
                constant += coef
        terms = [(c, k) for k, c in monomials.items() if c != 0.0]
        if not terms:
            return constant
        if len(terms) == 1 and constant == 0.0 and len(terms[0][1]) == 1:
            return (terms[0][0], terms[0][1][0])
        text = ""
        for c, k in terms:
            product = "*".join(k)
            sign = "-" if c < 0 else "+"
            body = product if abs(c) == 1.0 else f"{repr(abs(c))}*{product}"
            text += f" {sign} {body}" if text else (f"-{body}" if c < 0 else body)
        if constant != 0.0:
            text += f" + {_literal(constant)}"
        return self.name(text)

    def name(self, text: str) -> tuple[float, str]:
        """A variable holding ``text`` (the one already made for the same text, if any)."""
        found = self.known.get(text)
        if found is None:
            self.count += 1
            self.line(f"v{self.count} = {text}")
            found = self.known[text] = (1.0, f"v{self.count}")
        return found


def _text(v: Value) -> str:
    if isinstance(v, tuple):
        c, n = v
        return n if c == 1.0 else f"-{n}" if c == -1.0 else f"{_literal(c)}*{n}"
    return _literal(v)


def _scaled(v: Value, k: float) -> Value:
    return (v[0] * k, v[1]) if isinstance(v, tuple) else v * k


def _clean(x: float) -> float:
    return 0.0 if abs(x) < _TINY else float(x)


@dataclass(frozen=True, eq=False)
class Chain:
    """The numbers of a chain: ``fixed`` (m+1, 4, 4), ``base`` (4, 4), and per axis
    ``child`` (T_joint_child, (m, 4, 4)), its joint index, multiplier, offset and kind; ``dof`` joints."""

    fixed: FloatArray
    base: FloatArray
    child: FloatArray
    index: tuple[int, ...]
    multiplier: tuple[float, ...]
    offset: tuple[float, ...]
    revolute: tuple[bool, ...]
    dof: int


def _apply(w: _Writer, F: FloatArray, cols: list[Vector], p: Vector) -> tuple[list[Vector], Vector]:
    """The frame (cols, p) times the constant transform F."""
    p = [w.sum((p[r],), *((float(F[i, 3]), cols[i][r]) for i in range(3))) for r in range(3)]
    return [
        [w.sum(*((_clean(F[i, j]), cols[i][r]) for i in range(3))) for r in range(3)] for j in range(3)
    ], p


def _frame(cs: list[Vector], pos: Vector) -> list[Value]:
    return [v for r in range(3) for v in (cs[0][r], cs[1][r], cs[2][r], pos[r])] + [0.0, 0.0, 0.0, 1.0]


def generate(
    chain: Chain, frames: bool, links: bool, jacobian: bool, batch: bool = False, rates: bool = False
) -> tuple[str, int]:
    """The source of ``chain(q)`` → a flat tuple: T (16 values, row-major), then the joint frames
    if ``frames`` (16 each, before each axis moves), the link frames if ``links`` (m + 2 of them:
    the base, the link of every axis, the tool), then J if ``jacobian`` (6·dof, row-major), then
    J̇ if ``rates`` (6·dof, row-major; the function is then ``chain(q, u)``, ``u`` the joint rates).
    Also returns the tuple's length. ``q`` (and ``u``) are sequences of the ``dof`` joint values
    (Python floats, or the rows of a batch).
    """
    jacobian = jacobian or rates
    w = _Writer()
    fixed, index, multiplier, offset, revolute, dof = (
        chain.fixed,
        chain.index,
        chain.multiplier,
        chain.offset,
        chain.revolute,
        chain.dof,
    )
    m = len(index)
    w.line(f"{''.join(f'q{i}, ' for i in range(dof))}= q" if dof else "pass")
    if rates and dof:
        w.line(f"{''.join(f'u{i}, ' for i in range(dof))}= u")
    F0 = fixed[0]
    cols: list[Vector] = [[_clean(F0[r, j]) for r in range(3)] for j in range(3)]
    p: Vector = [float(F0[r, 3]) for r in range(3)]
    saved: list[tuple[list[Vector], Vector]] = []
    link_frames: list[Value] = [float(x) for x in chain.base.ravel()]
    for k in range(m):
        saved.append((cols, p))
        qk = f"q{index[k]}"
        arg = qk if multiplier[k] == 1.0 else f"{qk}*{_literal(multiplier[k])}"
        if offset[k] != 0.0:
            arg = f"{arg} + {_literal(offset[k])}"
        if revolute[k]:
            if arg != qk:
                w.line(f"t{k} = {arg}")
                arg = f"t{k}"
            if batch:  # from tan θ/2: NumPy's vectorised tan is 5× its sin, and as exact at any |θ|
                h, g = f"h{k}", f"g{k}"
                w.line(f"{h} = tan({arg}*0.5); {g} = 2.0/(1.0 + {h}*{h}); c{k} = {g} - 1.0; s{k} = {h}*{g}")
            else:
                w.line(f"c{k} = cos({arg}); s{k} = sin({arg})")
            c, s = (1.0, f"c{k}"), (1.0, f"s{k}")
            c0, c1 = cols[0], cols[1]
            cols = [
                [w.sum((c, c0[r]), (s, c1[r])) for r in range(3)],
                [w.sum((c, c1[r]), (-1.0, s, c0[r])) for r in range(3)],
                cols[2],
            ]
        else:
            w.line(f"d{k} = {arg}")
            d = (1.0, f"d{k}")
            p = [w.sum((p[r],), (d, cols[2][r])) for r in range(3)]
        if links:  # T_joint_child is F[k+1] when the next joint's origin is its link frame: shared
            link_frames += _frame(*_apply(w, chain.child[k], cols, p))
        cols, p = _apply(w, fixed[k + 1], cols, p)
    out = _frame(cols, p)
    if frames:
        for cs, pos in saved:
            out += _frame(cs, pos)
    if links:
        out += link_frames + out[:16]
    if jacobian:
        zs, ps = [z for (_, _, z), _ in saved], [pk for _, pk in saved]
        columns = _axis_columns(w, chain, zs, ps, p)
        out += _per_joint(w, chain, columns)
        if rates:
            out += _per_joint(w, chain, _axis_columns_dot(w, chain, zs, ps, p, columns))
    args = "q, u" if rates else "q"
    if not batch:
        body = "\n".join(w.lines)
        return f"def chain({args}):\n{body}\n    return ({''.join(_text(v) + ', ' for v in out)})\n", len(out)
    # A batch writes each value into its row of ``out`` (size, N): no temporary for a sign or a scale.
    stores = "\n".join(f"    {_store(i, v)}" for i, v in enumerate(out))
    body = "\n".join(_released(w.lines, stores))
    return f"def chain({args}, out):\n{body}\n{stores}\n", len(out)


def _store(i: int, v: Value) -> str:
    if not isinstance(v, tuple):
        return f"out[{i}] = {_literal(v)}"
    c, n = v
    if c == 1.0:
        return f"out[{i}] = {n}"
    if c == -1.0:
        return f"negative({n}, out=out[{i}])"
    return f"multiply({n}, {_literal(c)}, out=out[{i}])"


_NAME = re.compile(r"\b[qucstdvhg]\d+\b")


def _released(lines: list[str], result: str) -> list[str]:
    """``lines`` with each variable deleted after its last use (arrays of a batch: their memory
    goes back to be reused at once, so the working set stays in cache)."""
    kept = set(_NAME.findall(result))
    last: dict[str, int] = {}
    for i, line in enumerate(lines):
        for name in _NAME.findall(line.split("=", 1)[1] if " = " in line else line):
            last[name] = i
    out: list[str] = []
    for i, line in enumerate(lines):
        out.append(line)
        done = sorted(n for n, at in last.items() if at == i and n not in kept)
        if done:
            out.append(f"    del {', '.join(done)}")
    return out


def _cross(w: _Writer, a: Vector, b: Vector) -> Vector:
    """a × b, component by component."""
    return [w.sum((a[(i + 1) % 3], b[(i + 2) % 3]), (-1.0, a[(i + 2) % 3], b[(i + 1) % 3])) for i in range(3)]


def _axis_columns(w: _Writer, chain: Chain, zs: list[Vector], ps: list[Vector], tool: Vector) -> list[Vector]:
    """Whitney's column [z × (p_tool − p_k); z] (revolute) or [z; 0] (prismatic) of every axis."""
    columns: list[Vector] = []
    for k, z in enumerate(zs):
        if chain.revolute[k]:
            r = [w.sum((tool[i],), (-1.0, ps[k][i])) for i in range(3)]
            columns.append(_cross(w, z, r) + list(z))
        else:
            columns.append(list(z) + [0.0, 0.0, 0.0])
    return columns


def _axis_columns_dot(
    w: _Writer, chain: Chain, zs: list[Vector], ps: list[Vector], tool: Vector, columns: list[Vector]
) -> list[Vector]:
    """The time derivative of every axis column at joint rates ``u``: with ω_k = Σ_{j<k} ṙ_j z_j
    (revolute j; ṙ_j the rate of axis j) the angular velocity of joint frame k, ż_k = ω_k × z_k,
    and ṗ_tool − ṗ_k = ω_k × (p_tool − p_k) + Σ_{j≥k} ṙ_j (column j's v) (the axes from k on move
    the tool, not the origin of frame k, which lies on axis k), a revolute column's derivative is
    [ż_k × r_k + z_k × (ṗ_tool − ṗ_k); ż_k] and a prismatic one's [ż_k; 0]."""
    m = len(zs)
    rate: list[Value] = [(chain.multiplier[k], f"u{chain.index[k]}") for k in range(m)]
    after: list[Vector] = [[0.0, 0.0, 0.0]] * m  # Σ_{j≥k} ṙ_j v_j
    total: Vector = [0.0, 0.0, 0.0]
    for k in reversed(range(m)):
        total = [w.sum((total[i],), (rate[k], columns[k][i])) for i in range(3)]
        after[k] = total
    omega: Vector = [0.0, 0.0, 0.0]
    out: list[Vector] = []
    for k, z in enumerate(zs):
        zd = _cross(w, omega, z)
        if chain.revolute[k]:
            r = [w.sum((tool[i],), (-1.0, ps[k][i])) for i in range(3)]
            rel = [
                w.sum(
                    (omega[(i + 1) % 3], r[(i + 2) % 3]),
                    (-1.0, omega[(i + 2) % 3], r[(i + 1) % 3]),
                    (after[k][i],),
                )
                for i in range(3)
            ]
            v = [
                w.sum(
                    (zd[(i + 1) % 3], r[(i + 2) % 3]),
                    (-1.0, zd[(i + 2) % 3], r[(i + 1) % 3]),
                    (z[(i + 1) % 3], rel[(i + 2) % 3]),
                    (-1.0, z[(i + 2) % 3], rel[(i + 1) % 3]),
                )
                for i in range(3)
            ]
            out.append(v + zd)
            omega = [w.sum((omega[i],), (rate[k], z[i])) for i in range(3)]
        else:
            out.append(zd + [0.0, 0.0, 0.0])
    return out


def _per_joint(w: _Writer, chain: Chain, columns: list[Vector]) -> list[Value]:
    """(6·dof values, row-major): the axis columns summed per joint, times their multipliers
    (mimic axes)."""
    J: list[list[Value]] = [[0.0] * chain.dof for _ in range(6)]
    for j in range(chain.dof):
        axes = [k for k in range(len(columns)) if chain.index[k] == j]
        for row in range(6):
            J[row][j] = w.sum(*((_scaled(columns[k][row], chain.multiplier[k]),) for k in axes))
    return [v for row in J for v in row]


Function = Callable[..., tuple[Any, ...]]


class Compiled:
    """The generated chain functions of one robot, each compiled on first use.

    ``single(q, parts)`` for one configuration (n,) → the arrays named in ``parts`` ("T": (4, 4),
    "W": joint frames (m, 4, 4), "L": link frames (m + 2, 4, 4), "J": (6, n)), in that order;
    ``batch(Q, jacobian)`` for one chunk Q (N, n) → (T (N, 4, 4), J (N, 6, n) or None);
    ``single_rates(q, u)`` and ``batch_rates(Q, U)`` → T, J and J̇ at joint rates u.
    """

    def __init__(self, chain: Chain) -> None:
        self.chain = chain
        self._m = len(chain.index)
        self._cache: dict[tuple[str, bool], tuple[Function, Callable[..., bytes], int]] = {}

    def _function(self, parts: str, scalar: bool) -> tuple[Function, Callable[..., bytes], int]:
        key = (parts, scalar)
        found = self._cache.get(key)
        if found is None:
            text, size = generate(
                self.chain, "W" in parts, "L" in parts, "J" in parts, batch=not scalar, rates="D" in parts
            )
            lib: Any = math if scalar else np
            namespace: dict[str, Any] = {"cos": lib.cos, "sin": lib.sin, "tan": lib.tan, "__builtins__": {}}
            namespace.update(negative=np.negative, multiply=np.multiply)
            # Our own text: fixed identifiers and float literals only (see the module's docstring).
            exec(compile(text, "<kinematics.compiled>", "exec"), namespace)
            found = self._cache[key] = (namespace["chain"], struct.Struct(f"{size}d").pack, size)
        return found

    def single(self, q: FloatArray, parts: str) -> list[FloatArray]:
        function, pack, _ = self._function(parts, True)
        a = np.frombuffer(bytearray(pack(*function(q.tolist()))))
        m, at = self._m, 16
        out: list[FloatArray] = [a[:16].reshape(4, 4)]
        if "W" in parts:
            out.append(a[at : at + 16 * m].reshape(m, 4, 4))
            at += 16 * m
        if "L" in parts:
            out.append(a[at : at + 16 * (m + 2)].reshape(m + 2, 4, 4))
            at += 16 * (m + 2)
        if "J" in parts:
            out.append(a[at:].reshape(6, self.chain.dof))
        return out

    def single_rates(self, q: FloatArray, u: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """T (4, 4), J (6, n) and J̇ (6, n) of one configuration q (n,) at joint rates u (n,)."""
        function, pack, _ = self._function("TJD", True)
        a = np.frombuffer(bytearray(pack(*function(q.tolist(), u.tolist()))))
        n = self.chain.dof
        return a[:16].reshape(4, 4), a[16 : 16 + 6 * n].reshape(6, n), a[16 + 6 * n :].reshape(6, n)

    def batch_rates(self, Q: FloatArray, U: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """T (N, 4, 4), J (N, 6, n) and J̇ (N, 6, n) of one chunk Q (N, n) at joint rates U (N, n)."""
        function, _, size = self._function("TJD", False)
        N, n = len(Q), self.chain.dof
        out = np.empty((size, N))
        function(list(np.ascontiguousarray(Q.T)), list(np.ascontiguousarray(U.T)), out)
        T = out[:16].T.reshape(N, 4, 4)
        return T, out[16 : 16 + 6 * n].T.reshape(N, 6, n), out[16 + 6 * n :].T.reshape(N, 6, n)

    def batch(self, Q: FloatArray, jacobian: bool) -> tuple[FloatArray, FloatArray | None]:
        function, _, size = self._function("TJ" if jacobian else "T", False)
        N = len(Q)
        out = np.empty((size, N))
        function(list(np.ascontiguousarray(Q.T)), out)
        T = out[:16].T.reshape(N, 4, 4)
        return T, out[16:].T.reshape(N, 6, self.chain.dof) if jacobian else None
