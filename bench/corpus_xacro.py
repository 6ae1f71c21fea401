"""Corpus check of xacro without a ROS workspace: the Robotics Toolbox's xacro robots (the ``rtb-data``
wheel), opened with no ``ROS_PACKAGE_PATH`` / ``AMENT_PREFIX_PATH``, then with one ``--package`` option.

Nothing is downloaded by this script and none of it is kept in the repo::

    pip download --no-deps rtb-data -d /tmp/rtb/dl && unzip -qo /tmp/rtb/dl/*.whl -d /tmp/rtb/unpacked
    PYTHONPATH=$PWD python bench/corpus_xacro.py /tmp/rtb/unpacked/rtbdata/xacro

Every ``.xacro`` file is expanded with its default arguments. A file of macros only (it defines
``xacro:macro``s and no link: meant to be included) is counted apart. A robot that does not open because
``$(find PKG)`` finds no package is opened again with ONE option, as a user would give it: ``--package
PKG=DIR`` with DIR the corpus folder whose name PKG starts with or that starts with PKG
(``kuka_kr6_support`` → ``kuka_description/kuka_kr6``, ``abb_irb140`` → ``abb_irb140_description``).
Its visual meshes are counted too (found / referenced). ``--before`` runs without the option (the code
before ``--package`` existed has no such parameter): run it on the old checkout for the "before" figure.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from pathlib import Path

from kinematics.errors import JacobianLabError
from kinematics.urdf import mesh_report, robot_from_urdf

_MISSING = re.compile(r"\$\(find ([\w.-]+)\)")
_BODY = re.compile(r"<!--.*?-->|<xacro:macro\b.*?</xacro:macro>", re.S)
_CALL = re.compile(r"<(?:xacro:(?!include|property|arg|macro|if|unless)[\w]+|link)\b")


def is_robot(path: Path) -> bool:
    """Whether a xacro file describes a robot: outside its macro definitions and comments it has a link or
    calls a macro (else it is a file of macros only, meant to be included, like ``*_macro.xacro``)."""
    return bool(_CALL.search(_BODY.sub("", path.read_text(encoding="utf-8", errors="replace"))))


def _mapping(corpus: Path, package: str) -> Path | None:
    folders = sorted((p for p in corpus.rglob("*") if p.is_dir()), key=lambda p: len(p.parts))
    for folder in folders:
        if package.startswith(folder.name + "_") or folder.name.startswith(package + "_"):
            return folder
    return None


def _open(path: Path, named: dict[str, Path] | None) -> tuple[str, int, int]:
    robot = robot_from_urdf(path, package_dirs=named) if named else robot_from_urdf(path)
    found, missing = mesh_report(path)
    return f"{robot.name} {robot.dof} joints", len(found), len(found) + len(missing)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("corpus", type=Path, help="the rtbdata/xacro folder")
    parser.add_argument("--before", action="store_true", help="never give --package (the old code)")
    args = parser.parse_args(argv)
    for var in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH"):
        os.environ.pop(var, None)
    corpus = args.corpus.resolve()
    robots = macros = plain = mapped = 0
    meshes = [0, 0]
    failed: list[str] = []
    for path in sorted(corpus.rglob("*.xacro")):
        rel = path.relative_to(corpus)
        if not is_robot(path):
            macros += 1
            continue
        try:
            what, found, total = _open(path, None)
            robots, plain = robots + 1, plain + 1
            print(f"ok       {rel}: {what}, meshes {found}/{total}")
        except JacobianLabError as exc:
            text = str(exc)
            missing = _MISSING.search(text)
            robots += 1
            folder = _mapping(corpus, missing.group(1)) if missing and not args.before else None
            if missing is None or folder is None:
                failed.append(f"{rel}: {text[:300]}")
                print(f"FAILED   {rel}: {text[:300]}")
                continue
            option = f"--package {missing.group(1)}={folder.relative_to(corpus)}"
            try:
                what, found, total = _open(path, {missing.group(1): folder})
            except JacobianLabError as exc2:
                failed.append(f"{rel} ({option}): {str(exc2)[:300]}")
                print(f"FAILED   {rel} ({option}): {str(exc2)[:300]}")
                continue
            mapped += 1
            print(f"ok+1     {rel} with {option}: {what}, meshes {found}/{total}")
        meshes[0] += found
        meshes[1] += total
    print(
        f"\n{robots} xacro robots ({macros} files of macros only left out): {plain} open with no option and "
        f"no ROS variables, {mapped} more with one --package option; {len(failed)} do not open; "
        f"meshes of the robots that open: {meshes[0]} of {meshes[1]} found"
    )
    return 0 if not failed else 1


if __name__ == "__main__":
    sys.exit(main())
