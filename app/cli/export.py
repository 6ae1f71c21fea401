"""``jacobian-lab export``: the symbolic Jacobian of a robot as LaTeX, MathML, Python or JSON.

``jacobian-lab export ROBOT --format latex|mathml|python|numpy|json|c|matlab [--frame base|tool]
[--symbolic-params] [--base LINK] [--tip LINK] [-o FILE]``, with ROBOT a library name or a
path to a robot file (.toml) or URDF. Output goes to stdout unless ``-o`` is given; progress is
shown on stderr for any step that takes more than a second. The work is done by
:func:`kinematics.symbolic.typeset.export.export`.
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
from pathlib import Path

import robots
from kinematics import Robot
from kinematics.conventions import FRAMES
from kinematics.errors import JacobianLabError
from kinematics.files import write_user_file
from kinematics.symbolic.core import DEFAULT_TIMEOUT
from kinematics.symbolic.typeset.ccode import c_identifier
from kinematics.symbolic.typeset.export import FORMATS, ExportError, export, export_c, export_matlab
from kinematics.urdf import parse_xacro_args

from .args import MAX_TIMEOUT, bounded
from .packages import add_package_arguments, package_options

__all__ = ["main", "add_chain_arguments", "load_robot", "xacro_arguments", "StderrProgress", "write_output"]


def add_chain_arguments(parser: argparse.ArgumentParser) -> None:
    """``--base LINK`` and ``--tip LINK``: the ends of the chain taken from a URDF."""
    parser.add_argument(
        "--base", metavar="LINK", help="URDF only: link the chain starts from (default: the root link)"
    )
    parser.add_argument(
        "--tip",
        metavar="LINK",
        help="URDF only: link the chain ends at (default: tool0, *_tcp, flange, ee_link, a tool frame "
        "(*_tool_frame, *tool_link, ee_gripper_link, *_grasptarget), *hand*, else the leaf with the most "
        "moving joints)",
    )
    parser.add_argument(
        "--xacro-arg",
        metavar="NAME:=VALUE",
        action="append",
        default=[],
        help="xacro only: an argument of the .xacro file (repeat for several)",
    )


def load_robot(args: argparse.Namespace) -> Robot:
    """The robot the command line names: ``args.robot`` with ``--base``, ``--tip`` and ``--xacro-arg``
    (see :func:`add_chain_arguments`)."""
    return robots.load(
        args.robot,
        base_link=args.base,
        tip_link=args.tip,
        xacro_args=xacro_arguments(args),
        **package_options(args),
    )


def xacro_arguments(args: argparse.Namespace) -> dict[str, str] | None:
    """The ``--xacro-arg`` values as a mapping (``None`` when none were given).

    Raises:
        UrdfError: a value without ``:=``.
    """
    return parse_xacro_args(args.xacro_arg) if args.xacro_arg else None


class StderrProgress:
    """Shows the current step on stderr, only once the whole job has taken more than ``after`` seconds."""

    def __init__(self, stream=None, after: float = 1.0, command: str = "export") -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.command = command
        self.after = after
        self.message = "working"
        self.shown = ""
        self.lock = threading.Lock()
        self.stop = threading.Event()
        self.start = time.perf_counter()
        self.thread = threading.Thread(target=self._run, daemon=True)

    def __call__(self, message: str) -> None:
        with self.lock:
            self.message = message

    def _show(self, final: bool = False) -> None:
        elapsed = time.perf_counter() - self.start
        with self.lock:
            message = "done" if final else self.message
        if final or message != self.shown:
            self.stream.write(f"jacobian-lab {self.command}: [{elapsed:5.1f} s] {message}\n")
            self.stream.flush()
            self.shown = message

    def _run(self) -> None:
        if self.stop.wait(self.after):
            return
        while not self.stop.wait(0.25):
            self._show()

    def __enter__(self) -> StderrProgress:
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.thread.join()
        if self.shown:
            self._show(final=True)


_StderrProgress = StderrProgress  # the name the tests use


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="jacobian-lab export",
        description="Export a robot's symbolic Jacobian J(q) as LaTeX, MathML, a Python/NumPy module, JSON, "
        "C (with -o FILE.c, also FILE.h) or a MATLAB/Octave function file.",
    )
    p.add_argument("robot", help="library robot name (e.g. puma560) or path to a robot .toml or .urdf file")
    p.add_argument("--format", "-f", choices=FORMATS, default="latex", help="output format (default: latex)")
    p.add_argument("--frame", choices=FRAMES, default="base", help="axes of J's rows (default: base)")
    p.add_argument(
        "--symbolic-params",
        action="store_true",
        help="keep DH lengths and offsets as symbols (a2, d4, ...) instead of numbers",
    )
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    add_chain_arguments(p)
    add_package_arguments(p)
    p.add_argument(
        "--timeout",
        type=bounded(0.0, MAX_TIMEOUT, "s"),
        default=DEFAULT_TIMEOUT,
        metavar="SECONDS",
        help=f"simplification time limit (default: {DEFAULT_TIMEOUT:g} s)",
    )
    return p


def main(argv: list[str] | None = None) -> int:
    """Run ``jacobian-lab export`` with ``argv`` (default: ``sys.argv[1:]``); returns the exit status.

    0: written; 1: the robot or the export failed (message on stderr); 2: a usage error.
    """
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # -h or a usage error (already printed by argparse)
        return int(exc.code or 0)
    files: list[tuple[str, str | None]] = []
    try:
        robot = load_robot(args)
        options = (args.frame, args.symbolic_params)
        with StderrProgress() as progress:
            if args.output and args.format == "c":  # FILE.c and its header FILE.h
                out = Path(args.output)
                header, source = export_c(robot, out.stem, *options, progress, timeout=args.timeout)
                files = [(header, str(out.with_suffix(".h"))), (source, args.output)]
            elif args.output and args.format == "matlab":  # MATLAB wants the function named as its file
                stem = Path(args.output).stem
                if c_identifier(stem) != stem:
                    raise ExportError(
                        f"a MATLAB function file is named after its function: {stem!r} is not a valid "
                        "name (letters, digits and _, starting with a letter), e.g. -o puma_jacobian.m"
                    )
                _, text = export_matlab(robot, *options, progress, function=stem, timeout=args.timeout)
                files = [(text, args.output)]
            else:
                text = export(robot, args.format, *options, progress, timeout=args.timeout)
                files = [(text, args.output)]
    except JacobianLabError as exc:
        print(f"jacobian-lab export: error: {exc}", file=sys.stderr)
        return 1
    for text, output in files:
        status = write_output(text, output, "export")
        if status:
            return status
    return 0


def write_output(text: str, output: str | None, command: str) -> int:
    """Write ``text`` to the file ``output`` (standard output when ``None``); the exit status, with
    ``jacobian-lab COMMAND: error: cannot write …`` on stderr when the file cannot be written."""
    if output is None:
        sys.stdout.write(text)
        return 0
    try:
        write_user_file(output, text.encode("utf-8"))  # never blocks on a FIFO or a device
    except OSError as exc:
        print(f"jacobian-lab {command}: error: cannot write {output}: {exc.strerror}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
