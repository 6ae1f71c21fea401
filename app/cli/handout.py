"""``jacobian-lab handout``: the derivation of a robot's J as a handout (HTML with MathML, or LaTeX).

``jacobian-lab handout ROBOT [--method whitney|differentiation|propagation|force|all]
[--symbolic-params] [--frame base|tool] [--configuration NAME] [--rates Q̇1 Q̇2 …]
[--lang en|pt|es|pl] [--base LINK] [--tip LINK] -o FILE.html|FILE.tex``, with ROBOT a library name or a
path to a robot file (.toml) or URDF. The format follows the file's extension (``--format`` for
stdout). The worked example is at the named configuration (default ``home``); joint rates are given in deg/s
(revolute) and m/s (prismatic); without them, a motion of the robot file that starts at that
configuration gives the tool velocity for q̇ = J⁻¹ v. ``--lang`` writes it in the language of that
course (its words from the app's catalogs, the robot file's translated texts, decimal commas in pt, es
and pl). The work is done by :func:`kinematics.symbolic.handout.handout`.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

import robots
from app.core.i18n import CODES, translations
from kinematics.conventions import FRAMES
from kinematics.errors import JacobianLabError
from kinematics.symbolic.core import DEFAULT_TIMEOUT
from kinematics.symbolic.handout import HANDOUT_METHODS, handout

from .args import MAX_TIMEOUT, bounded
from .export import StderrProgress, add_chain_arguments, load_robot, write_output
from .packages import add_package_arguments

__all__ = ["main"]

_SUFFIXES = {".html": "html", ".htm": "html", ".tex": "tex"}


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="jacobian-lab handout",
        description="Write the derivation of a robot's Jacobian, step by step, as an HTML page or a "
        "LaTeX document.",
    )
    p.add_argument("robot", help="library robot name (e.g. trr) or path to a robot .toml or .urdf file")
    p.add_argument(
        "--method", "-m", choices=HANDOUT_METHODS, default="all", help="derivation(s) to show (default: all)"
    )
    p.add_argument("--frame", choices=FRAMES, default="base", help="axes of J's rows (default: base)")
    p.add_argument(
        "--symbolic-params",
        action="store_true",
        help="keep DH lengths and offsets as symbols (the course's letters)",
    )
    p.add_argument(
        "--configuration",
        "-c",
        metavar="NAME",
        help="named configuration of the worked example (default: home)",
    )
    p.add_argument(
        "--rates",
        nargs="+",
        type=bounded(-1e4, 1e4, open_low=False),
        metavar="QDOT",
        help="joint rates of the worked example: deg/s (revolute), m/s (prismatic)",
    )
    p.add_argument(
        "-o", "--output", metavar="FILE", help="FILE.html or FILE.tex (default: stdout, see --format)"
    )
    p.add_argument(
        "--format",
        "-f",
        choices=("html", "tex"),
        help="format when writing to stdout, or to override the extension",
    )
    p.add_argument(
        "--lang",
        choices=CODES,
        default="en",
        help="language of the handout: its words, the robot's texts and decimal commas (default: en)",
    )
    add_chain_arguments(p)
    add_package_arguments(p)
    p.add_argument(
        "--timeout",
        type=bounded(0.0, MAX_TIMEOUT, "s"),
        default=DEFAULT_TIMEOUT,
        metavar="SECONDS",
        help=f"time limit (default: {DEFAULT_TIMEOUT:g} s)",
    )
    return p


def _twist(name: str, q: np.ndarray, frame: str) -> list[float] | None:
    """The tool velocity of the robot file's first motion starting at ``q`` (base axes), if any."""
    for m in robots.motions(name):
        if m.frame == "base" and m.q.shape == q.shape and np.allclose(m.q, q):
            return [float(v) for v in m.twist]
    return None


def main(argv: list[str] | None = None) -> int:
    """Run ``jacobian-lab handout`` with ``argv``; returns the exit status.

    0: written; 1: the robot or the handout failed (message on stderr); 2: a usage error.
    """
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # -h or a usage error (already printed by argparse)
        return int(exc.code or 0)
    fmt = args.format
    if args.output is not None and fmt is None:
        fmt = _SUFFIXES.get(Path(args.output).suffix.lower())
        if fmt is None:
            parser.print_usage(sys.stderr)
            print(
                "jacobian-lab handout: error: the output file must end in .html or .tex (or give --format)",
                file=sys.stderr,
            )
            return 2
    if fmt is None:
        parser.print_usage(sys.stderr)
        print(
            "jacobian-lab handout: error: give -o FILE.html|FILE.tex, or --format for stdout", file=sys.stderr
        )
        return 2
    try:
        robot = load_robot(args)
        rates = None
        if args.rates is not None:
            if len(args.rates) != robot.dof:
                raise JacobianLabError(
                    f"--rates: {robot.dof} values expected (one per joint), got {len(args.rates)}"
                )
            rates = [
                math.radians(v) if k == "revolute" else v
                for v, k in zip(args.rates, robot.joint_types, strict=True)
            ]
        q = robot.home if args.configuration is None else robot.configuration(args.configuration)
        twist = None if rates is not None else _twist(args.robot, np.asarray(q, dtype=float), args.frame)
        with StderrProgress(command="handout") as progress:
            text = handout(
                robot,
                fmt,
                args.method,
                frame=args.frame,
                symbolic_params=args.symbolic_params,
                configuration=args.configuration,
                rates=rates,
                twist=twist,
                timeout=args.timeout,
                progress=progress,
                words=translations(args.lang),
            )
    except JacobianLabError as exc:
        print(f"jacobian-lab handout: error: {exc}", file=sys.stderr)
        return 1
    return write_output(text, args.output, "handout")


if __name__ == "__main__":
    sys.exit(main())
