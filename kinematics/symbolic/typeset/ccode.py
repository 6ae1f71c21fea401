"""A controller's kinematics as code: C functions (header and source) and a MATLAB/Octave function file.

Both evaluate T_base_tool(q), J(q), J̇(q, q̇) and optionally ∂J/∂q (:mod:`.controller`) with their
common subexpressions computed once per function (``sympy.cse``), in straight-line code with no
allocation and no loop:

* C99, every name beginning with PREFIX (the ``--name``, else the output file's stem):
  ``void PREFIX_fk(const double q[n], double T[16])``, ``void PREFIX_jacobian(const double q[n],
  double J[rows * n])``, ``void PREFIX_jacobian_dot(const double q[n], const double qd[n], double
  Jdot[rows * n])`` and (optionally) ``void PREFIX_jacobian_dq(const double q[n], double dJ[n * rows *
  n])``, all row-major (``J[i*n + j]``, ``T[4*i + j]``, ``dJ[k*rows*n + i*n + j]`` = ∂J[i][j]/∂q[k]); with
  symbolic parameters a ``const double p[k]`` argument comes before the output, in the order of the
  header's comment and of :func:`parameter_order`. Only ``<math.h>`` is used.
* MATLAB/Octave: ``function [J, T, Jdot, dJdq] = NAME(q, qd)`` (``NAME(q, p, qd)`` with parameters)
  computes only the outputs asked for; ``qd`` is needed for ``Jdot`` only; ``dJdq(:, :, k)`` = ∂J/∂qₖ.

Names from the robot file reach the code only as identifiers reduced to ``[A-Za-z0-9_]`` (never a
keyword of the language) and as comments reduced to harmless characters (:func:`.escape.py_docstring`):
no ``*/``, no ``%`` line break, no preprocessor line can come from a name.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

import sympy as sp

from ..model import SymbolicModel
from .controller import Block, ControllerKinematics
from .escape import plain, py_docstring

__all__ = ["c_identifier", "c_source", "header_name", "matlab_source", "numbers_line", "parameter_order"]

_C_KEYWORDS = frozenset(
    "auto break case char const continue default do double else enum extern float for goto if inline int "
    "long register restrict return short signed sizeof static struct switch typedef union unsigned void "
    "volatile while _Bool _Complex _Imaginary bool true false NULL main J q p".split()
)
_MATLAB_KEYWORDS = frozenset(
    "break case catch classdef continue else elseif end for function global if otherwise parfor "
    "persistent return spmd switch try while J q p ans pi i j e".split()
)


def c_identifier(text: object, fallback: str = "robot", reserved: frozenset[str] = _C_KEYWORDS) -> str:
    """An identifier of C (and of MATLAB) made from ``text``: ``[A-Za-z_][A-Za-z0-9_]*``, at most 50
    characters, never one of ``reserved`` (a keyword or a name the generated code uses)."""
    out = re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9_]", "_", plain(text)))[:50].strip("_") or fallback
    if out[0].isdigit():
        out = f"{fallback}_{out}"
    while out in reserved:
        out += "_"
    return out


def header_name(stem: str) -> str:
    """The header's file name for the output file's stem: the stem itself if it is a plain file name
    (letters, digits, ``_.+-``), else its identifier (the source includes the header by that name)."""
    plain_name = re.fullmatch(r"[A-Za-z0-9_][A-Za-z0-9_.+-]{0,99}", stem) is not None
    return (stem if plain_name else c_identifier(stem)) + ".h"


def parameter_order(model: SymbolicModel) -> list[Any]:
    """The symbolic parameters in the order of the generated ``p`` argument (sorted by name)."""
    return sorted(model.params, key=str)


def numbers_line(model: SymbolicModel) -> str:
    """What was done to the robot file's numbers, for a header: kept as written, or snapped."""
    if model.exact:
        return "Numbers: every value of the robot file as written (--exact; nothing snapped)."
    if model.snaps:
        return (
            "Numbers: values of the robot file snapped to exact ones (see the note); "
            "--exact keeps them as written."
        )
    return "Numbers: the robot file's (none needed snapping)."


def _names(model: SymbolicModel, qd: Sequence[Any] = ()) -> dict[Any, Any]:
    """q, p and qd symbols → code names ``q_k``, ``p_k``, ``v_k`` (replaced by array accesses)."""
    names: dict[Any, Any] = {s: sp.Symbol(f"q_{k}") for k, s in enumerate(model.q)}
    names.update({s: sp.Symbol(f"p_{k}") for k, s in enumerate(parameter_order(model))})
    names.update({s: sp.Symbol(f"v_{k}") for k, s in enumerate(qd)})
    return names


def _comment_lines(
    model: SymbolicModel,
    frame: str,
    one: bool = False,
    notes: Sequence[str] = (),
    what: Sequence[str] = (),
) -> list[str]:
    robot = model.robot
    joints = ", ".join(
        (f"q({k + 1}) " if one else f"q[{k}] ")
        + f"{py_docstring(robot.joint_names[k], 60)} [{'rad' if kind == 'revolute' else 'm'}]"
        for k, kind in enumerate(model.joint_kinds)
    )
    params = ", ".join(
        (f"p({k + 1}) " if one else f"p[{k}] ")
        + f"{py_docstring(s, 40)} (robot file: {float(model.params[s])!r})"
        for k, s in enumerate(parameter_order(model))
    )
    return [
        f"Kinematics of the robot {py_docstring(robot.name)} for a controller, generated by Jacobian Lab.",
        *what,
        f"Frame of J: {frame}. Rows [vx, vy, vz, wx, wy, wz]: v [m/s] is the velocity of the tool-frame",
        f"origin and w [rad/s] the angular velocity, per unit joint rate, in {frame} axes.",
        f"Joints: {joints}; qd: their rates [rad/s or m/s], in the same order.",
        *([f"Parameters: {params}."] if params else []),
        numbers_line(model),
        *[f"Note: {py_docstring(note, 2000)}" for note in notes],
        "Regenerate rather than edit (jacobian-lab export ROBOT --format c|matlab).",
    ]


def c_source(
    K: ControllerKinematics,
    model: SymbolicModel,
    *,
    frame: str,
    stem: str,
    prefix: str | None = None,
    notes: Sequence[str] = (),
) -> tuple[str, str]:
    """(header, source) of the C99 functions computing ``K`` at q (and q̇).

    Args:
        K: T, J, J̇ (and ∂J/∂q) in the joint, rate and parameter symbols of ``model``.
        model: Its symbolic model.
        frame: ``"base"`` or ``"tool"`` (documented in the comment).
        stem: The header's file name without ``.h`` (the source includes it); reduced to an identifier.
        prefix: Beginning of every name (default: the robot's name); reduced to an identifier.
        notes: Said in the comment (e.g. values of the robot file snapped to exact ones).
    """
    rows, n = K.shape
    P = c_identifier(prefix if prefix is not None else model.robot.name, reserved=frozenset())
    k = len(model.params)
    par = f"const double p[{k}], " if k else ""
    q_arg, qd_arg = f"const double q[{n}], ", f"const double qd[{n}], "
    functions: list[tuple[str, str, str, str, Block]] = [  # name, inputs, output, comment, program
        (f"{P}_fk", q_arg, "double T[16]", "T_base_tool(q), row-major: T[4 * i + j].", K.T),
        (f"{P}_jacobian", q_arg, f"double J[{rows * n}]", f"J(q), row-major: J[i * {n} + j].", K.J),
        (
            f"{P}_jacobian_dot",
            q_arg + qd_arg,
            f"double Jdot[{rows * n}]",
            "dJ/dt at (q, qd), row-major like J (a = J qdd + Jdot qd).",
            K.Jdot,
        ),
    ]
    if K.dJdq is not None:
        text = f"dJ/dq: dJ[k * {rows * n} + i * {n} + j] is the derivative of J[i][j] by q[k]."
        functions.append((f"{P}_jacobian_dq", q_arg, f"double dJ[{n * rows * n}]", text, K.dJdq))
    what = ["Functions: " + ", ".join(f[0] for f in functions) + " (each declared in the header)."]
    comment = "/*\n" + "".join(
        f" * {line}\n" for line in _comment_lines(model, frame, notes=notes, what=what)
    )
    comment += " */\n"
    guard = c_identifier(stem).upper() + "_H"
    declarations = "".join(
        f"/* {doc} */\nvoid {name}({inputs}{par}{output});\n\n" for name, inputs, output, doc, _ in functions
    )
    header = (
        comment
        + f"#ifndef {guard}\n#define {guard}\n\n"
        + f"#define {P.upper()}_JACOBIAN_ROWS {rows}\n#define {P.upper()}_JACOBIAN_JOINTS {n}\n\n"
        + declarations
        + "#endif\n"
    )
    names = _names(model, K.qd)
    index = {names[s]: f"q[{i}]" for i, s in enumerate(model.q)}
    index.update({names[s]: f"p[{i}]" for i, s in enumerate(parameter_order(model))})
    index.update({names[s]: f"qd[{i}]" for i, s in enumerate(K.qd)})

    def code(expr: Any) -> str:
        text: str = sp.ccode(expr, standard="C99")
        return re.sub(r"\b[qpv]_\d+\b", lambda m: index[sp.Symbol(m.group(0))], text)

    bodies = []
    for name, inputs, output, _, program in functions:
        out = output.split()[1].split("[")[0]
        used = ["q"] + (["qd"] if "qd" in inputs else []) + (["p"] if k else [])
        renamed = program.renamed(names)
        reps, reduced = renamed.reps, renamed.outputs
        body = [f"    (void){v};" for v in used]  # a constant entry leaves an argument unused
        body += [f"    const double {sym} = {code(expr)};" for sym, expr in reps]
        flat = [e for M in reduced for e in M]
        body += [f"    {out}[{i}] = {code(e)};" for i, e in enumerate(flat)]
        bodies.append(f"void {name}({inputs}{par}{output})\n{{\n" + "\n".join(body) + "\n}\n")
    source = comment + f'#include <math.h>\n#include "{header_name(stem)}"\n\n' + "\n".join(bodies)
    return header, source


def matlab_source(
    K: ControllerKinematics,
    model: SymbolicModel,
    *,
    frame: str,
    function: str | None = None,
    notes: Sequence[str] = (),
) -> tuple[str, str]:
    """(function name, text of its ``.m`` file) computing ``[J, T, Jdot, dJdq]`` at q (and qd), for MATLAB
    and Octave; only the outputs asked for are computed.

    ``function``: the name (MATLAB wants the file's name); default ``ROBOT_jacobian``."""
    rows, n = K.shape
    function = c_identifier(function or f"{model.robot.name}_jacobian", reserved=_MATLAB_KEYWORDS)
    k = len(model.params)
    names = _names(model, K.qd)
    index = {names[s]: f"q({i + 1})" for i, s in enumerate(model.q)}
    index.update({names[s]: f"p({i + 1})" for i, s in enumerate(parameter_order(model))})
    index.update({names[s]: f"qd({i + 1})" for i, s in enumerate(K.qd)})

    def code(expr: Any) -> str:
        text: str = sp.octave_code(expr)
        return re.sub(r"\b[qpv]_\d+\b", lambda m: index[sp.Symbol(m.group(0))], text)

    outputs = "J, T, Jdot" + (", dJdq" if K.dJdq is not None else "")
    args = "q" + (", p" if k else "") + ", qd"
    what = [
        f"[{outputs}] = {function}({args}): J(q) ({rows} x {n}), T = T_base_tool(q) (4 x 4),",
        "Jdot = dJ/dt at (q, qd) (a = J qdd + Jdot qd; qd is needed for Jdot only)"
        + (f", dJdq(:, :, k) = dJ/dq(k) ({rows} x {n} x {n})." if K.dJdq is not None else "."),
    ]
    lines = [f"function [{outputs}] = {function}({args})"]
    lines += [f"% {line}" for line in _comment_lines(model, frame, one=True, notes=notes, what=what)]
    lines += [
        f"  if numel(q) ~= {n}",
        f"    error('{function}: q should have {n} values, got %d', numel(q));",
        "  end",
    ]
    if k:
        lines += [f"  if numel(p) ~= {k}", f"    error('{function}: p should have {k} values');", "  end"]

    def block(out: str, shape: str, program: Block, cell: Any, indent: str) -> list[str]:
        renamed = program.renamed(names)
        reps, reduced = renamed.reps, renamed.outputs
        got = [f"{indent}{sym} = {code(expr)};" for sym, expr in reps]
        got.append(f"{indent}{out} = zeros({shape});")
        for m, M in enumerate(reduced):
            got += [
                f"{indent}{out}({cell(i, j, m)}) = {code(M[i, j])};"
                for i in range(M.rows)
                for j in range(M.cols)
                if M[i, j] != 0
            ]
        return got

    lines += block("J", f"{rows}, {n}", K.J, lambda i, j, m: f"{i + 1}, {j + 1}", "  ")
    lines += ["  if nargout >= 2"]
    lines += block("T", "4, 4", K.T, lambda i, j, m: f"{i + 1}, {j + 1}", "    ")
    lines += ["  end", "  if nargout >= 3"]
    lines += [
        "    if nargin < " + str(3 if k else 2) + f" || numel(qd) ~= {n}",
        f"      error('{function}: Jdot needs qd, {n} joint rates');",
        "    end",
    ]
    lines += block("Jdot", f"{rows}, {n}", K.Jdot, lambda i, j, m: f"{i + 1}, {j + 1}", "    ")
    lines.append("  end")
    if K.dJdq is not None:
        lines += ["  if nargout >= 4"]
        lines += block(
            "dJdq", f"{rows}, {n}, {n}", K.dJdq, lambda i, j, m: f"{i + 1}, {j + 1}, {m + 1}", "    "
        )
        lines.append("  end")
    lines.append("end")
    return function, "\n".join(lines) + "\n"
