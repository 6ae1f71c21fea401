"""``jacobian-lab export``: the symbolic Jacobian of a robot as LaTeX, MathML or JSON, and a controller's
kinematics (T_base_tool, J, J̇, optionally ∂J/∂q) as Python/NumPy, C or MATLAB/Octave code.

``jacobian-lab export ROBOT --format latex|mathml|python|numpy|json|c|matlab [--frame base|tool]
[--symbolic-params] [--base LINK] [--tip LINK] [-o FILE]``, with ROBOT a library name or a
path to a robot file (.toml) or URDF (also ``--robot NAME`` or ``--urdf FILE``, as ``serve`` spells
them); the code formats also take ``--exact``, ``--dJdq`` and ``--name NAME``. Output goes to stdout
unless ``-o`` is given; progress is shown on stderr for any step that takes more than a second. The
work is done by :func:`kinematics.symbolic.typeset.export.export`.
"""

from __future__ import annotations

import argparse
import difflib
import sys
import threading
import time
from pathlib import Path

import robots
from kinematics import Robot
from kinematics.conventions import FRAMES
from kinematics.errors import JacobianLabError, UnknownRobotError
from kinematics.files import write_user_file
from kinematics.symbolic.core import DEFAULT_TIMEOUT
from kinematics.symbolic.typeset.ccode import c_identifier, header_name
from kinematics.symbolic.typeset.export import (
    CODE_FORMATS,
    FORMATS,
    ExportError,
    export,
    export_c,
    export_matlab,
)
from kinematics.urdf import parse_xacro_args

from .args import MAX_TIMEOUT, bounded
from .packages import add_package_arguments, package_options

__all__ = [
    "main",
    "add_chain_arguments",
    "add_robot_choice",
    "chosen_robot",
    "load_robot",
    "xacro_arguments",
    "StderrProgress",
    "write_output",
]


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
    try:
        return robots.load(
            args.robot,
            base_link=args.base,
            tip_link=args.tip,
            xacro_args=xacro_arguments(args),
            **package_options(args),
        )
    except UnknownRobotError as exc:
        close = difflib.get_close_matches(str(args.robot).lower(), robots.names(), n=3, cutoff=0.6)
        if not close:
            raise
        raise UnknownRobotError(f"{exc} (did you mean {' or '.join(close)}?)") from None


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


def add_robot_choice(parser: argparse.ArgumentParser) -> None:
    """The robot of ``export``: ``ROBOT`` (a name or a file), or ``--robot NAME`` / ``--urdf FILE`` as
    ``serve`` spells them (:func:`chosen_robot` checks that exactly one is given)."""
    parser.add_argument(
        "robot", nargs="?", help="library robot name (e.g. puma560) or path to a robot .toml or .urdf file"
    )
    parser.add_argument(
        "--robot", dest="robot_option", metavar="NAME", help="a library robot (as serve takes it)"
    )
    parser.add_argument("--urdf", metavar="FILE", help="a URDF (or .xacro) file (as serve takes it)")


def chosen_robot(args: argparse.Namespace) -> str | None:
    """The one robot given (ROBOT, ``--robot`` or ``--urdf``); None if none or several."""
    given = [x for x in (args.robot, args.robot_option, args.urdf) if x is not None]
    return given[0] if len(given) == 1 else None


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="jacobian-lab export",
        description="Export a robot's symbolic Jacobian J(q) as LaTeX, MathML or JSON, or a controller's "
        "kinematics (T_base_tool, J, Jdot, optionally dJ/dq) as a Python/NumPy module, C (with -o FILE.c, "
        "also FILE.h) or a MATLAB/Octave function file.",
    )
    add_robot_choice(p)
    p.add_argument("--format", "-f", choices=FORMATS, default="latex", help="output format (default: latex)")
    p.add_argument("--frame", choices=FRAMES, default="base", help="axes of J's rows (default: base)")
    p.add_argument(
        "--symbolic-params",
        action="store_true",
        help="keep DH lengths and offsets as symbols (a2, d4, ...) instead of numbers",
    )
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    code = ", ".join(CODE_FORMATS)
    p.add_argument(
        "--exact",
        action="store_true",
        help=f"{code}: keep every number of the robot file as written (default: angles within 5e-4 rad "
        "of a multiple of 15 degrees, e.g. 1.5708, are snapped to it for a readable formula; the header "
        "says which)",
    )
    p.add_argument(
        "--dJdq", action="store_true", help=f"{code}: also write dJ/dq, the derivative of J by each joint"
    )
    p.add_argument(
        "--name",
        metavar="NAME",
        help="c: prefix of the C names (NAME_fk, NAME_jacobian, NAME_jacobian_dot, ...); matlab: the "
        "function's name (default: the output file's stem, else the robot's name; made an identifier)",
    )
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
    robot_arg = chosen_robot(args)
    if robot_arg is None:
        parser.print_usage(sys.stderr)
        print(
            "jacobian-lab export: error: give one robot: ROBOT, --robot NAME or --urdf FILE", file=sys.stderr
        )
        return 2
    args.robot = robot_arg
    if args.format not in CODE_FORMATS and (args.exact or args.dJdq or args.name is not None):
        parser.print_usage(sys.stderr)
        formats = ", ".join(CODE_FORMATS)
        print(f"jacobian-lab export: error: --exact, --dJdq and --name are for {formats}", file=sys.stderr)
        return 2
    files: list[tuple[str, str | None]] = []
    try:
        robot = load_robot(args)
        options = (args.frame, args.symbolic_params)
        code = {"exact": args.exact, "dJdq": args.dJdq}
        with StderrProgress() as progress:
            if args.output and args.format == "c":  # FILE.c and its header FILE.h; names from --name or FILE
                out = Path(args.output)
                name = args.name if args.name is not None else out.stem
                header, source = export_c(
                    robot, out.stem, *options, progress, timeout=args.timeout, name=name, **code
                )
                files = [(header, str(out.with_name(header_name(out.stem)))), (source, args.output)]
            elif args.output and args.format == "matlab":  # MATLAB wants the function named as its file
                stem = Path(args.output).stem
                if c_identifier(stem) != stem:
                    raise ExportError(
                        f"a MATLAB function file is named after its function: {stem!r} is not a valid "
                        "name (letters, digits and _, starting with a letter), e.g. -o puma_jacobian.m"
                    )
                if args.name is not None and args.name != stem:
                    raise ExportError(
                        f"a MATLAB function file is named after its function: --name {args.name} needs "
                        f"-o {c_identifier(args.name)}.m (or leave --name out)"
                    )
                _, text = export_matlab(
                    robot, *options, progress, function=stem, timeout=args.timeout, **code
                )
                files = [(text, args.output)]
            else:
                extra = {**code, "name": args.name} if args.format in CODE_FORMATS else {}
                text = export(robot, args.format, *options, progress, timeout=args.timeout, **extra)
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
