"""``jacobian-lab record``: a demo any static web server can play, with no Python behind it.

``jacobian-lab record ROBOT -o DIR [--preset NAME] [--seconds S] [--fps F]``, with ROBOT a library
name or a path to a robot file (.toml) or URDF. Writes ``DIR/index.html``, ``DIR/viser-client.html``,
``DIR/recording.viser`` and ``DIR/joint_rates.csv`` (see :mod:`app.demo.record`); serve DIR
(``python -m http.server -d DIR``) and open ``index.html``. Every mistake (an unknown robot or
preset, a folder that cannot be written, a non-positive duration or frame rate) is one line on stderr
and exit status 2.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from kinematics.errors import JacobianLabError

from ..core.i18n import CODES, translations
from ..demo.record import DEFAULT_FPS, DEFAULT_SECONDS, UnknownPreset, check_preset, record, write_demo
from .args import MAX_FPS, MAX_SECONDS, bounded
from .export import add_chain_arguments, load_robot
from .packages import add_package_arguments

__all__ = ["main"]

PROG = "jacobian-lab record"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog=PROG,
        description="Record a robot's motion into a singularity as a demo that plays from any static "
        "web server (a course page) with no Python behind it.",
    )
    p.add_argument("robot", help="library robot name (e.g. puma560) or path to a robot .toml or .urdf file")
    p.add_argument("-o", "--output", metavar="DIR", required=True, help="folder to write the demo into")
    p.add_argument(
        "--preset",
        metavar="NAME",
        help="the robot file's [[motions]] preset to play (default: its first one; without presets, "
        "home to its first singular configuration, else to the nearest singularity)",
    )
    p.add_argument(
        "--seconds",
        type=bounded(0.0, MAX_SECONDS, "s"),
        default=DEFAULT_SECONDS,
        metavar="S",
        help=f"longest recording (default: {DEFAULT_SECONDS:g} s, at most {MAX_SECONDS:g}; a preset may stop "
        "earlier)",
    )
    p.add_argument(
        "--fps",
        type=bounded(0.0, MAX_FPS),
        default=DEFAULT_FPS,
        metavar="F",
        help=f"frames per second (default: {DEFAULT_FPS:g}, at most {MAX_FPS:g})",
    )
    p.add_argument(
        "--lang",
        choices=CODES,
        default="en",
        help="the language of the demo's words (its title, status and 3-D labels; default: en)",
    )
    add_chain_arguments(p)
    add_package_arguments(p)
    return p


def _fail(message: str) -> int:
    print(f"{PROG}: error: {message}", file=sys.stderr)
    return 2


def _writable(out: Path) -> str | None:
    """Why the demo cannot be written into ``out`` (created if missing), or None."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        return f"cannot write into {out}: it is a file, not a folder"
    except OSError as exc:
        return f"cannot create {out}: {exc.strerror}"
    if not os.access(out, os.W_OK | os.X_OK):
        return f"cannot write into {out}: permission denied"
    return None


def main(argv: list[str] | None = None) -> int:
    """Run ``jacobian-lab record`` with ``argv`` (default: ``sys.argv[1:]``); returns the exit status.

    0: written; 2: a usage error, an unknown robot or preset, or a folder that cannot be written.
    """
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # -h, or a usage error already printed by argparse (status 2)
        return exc.code if isinstance(exc.code, int) else 2
    if round(args.seconds * args.fps) < 1:
        return _fail(f"{args.seconds:g} s at {args.fps:g} frames per second is not one frame")
    try:
        robot = load_robot(args)
    except JacobianLabError as exc:
        return _fail(str(exc))
    name = robot.name if robot.urdf_path else args.robot
    try:
        check_preset(name, robot, args.preset)
    except UnknownPreset as exc:
        return _fail(str(exc))
    out = Path(args.output)
    problem = _writable(out)
    if problem:
        return _fail(problem)
    try:
        recording = record(name, robot, args.preset, args.seconds, args.fps, translations(args.lang))
    except JacobianLabError as exc:
        return _fail(str(exc))
    try:
        write_demo(recording, out)
    except OSError as exc:
        return _fail(f"cannot write into {out}: {exc.strerror}")
    print(
        f"{out / 'index.html'}: {recording.title}, {recording.duration:.1f} s ({recording.frames} frames). "
        f"Serve it with: python -m http.server -d {out}",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
