"""J(q) as code for a controller: the C function (compiled by the system's C compiler and called through
ctypes), the MATLAB/Octave function file (run by Octave) and the NumPy module, each against
``kinematics.jacobian`` at random configurations for every library robot and a URDF arm, to 1e-12.

C and Octave come from Debian's packages (``python tests/install_test_deps.py``); in CI a missing one
fails the test instead of skipping it.
"""

from __future__ import annotations

import ctypes
import os
import re
import shutil
import subprocess

import numpy as np
import pytest
from kinematics_helpers import import_source, octave_lines
from locations import DATA
from test_export_escaping import INJECT, SCRIPT, hostile_robot

import kinematics
import robots
from kinematics.symbolic import build_model
from kinematics.symbolic.typeset import export as ex
from kinematics.symbolic.typeset.ccode import c_identifier, parameter_order
from kinematics.urdf import to_urdf

URDF_ARM = str(DATA / "iiwa14_like.urdf")
ROBOTS = [*robots.names(), URDF_ARM]


@pytest.fixture(scope="module")
def urdf_from_puma(tmp_path_factory):
    """The Puma 560 written as a URDF and read back: a URDF arm whose numbers need no snapping."""
    path = tmp_path_factory.mktemp("urdf") / "puma_from_dh.urdf"
    path.write_text(to_urdf(robots.load("puma560")), encoding="utf-8")
    return str(path)


def tolerance(robot, notes_text: str) -> float:
    """1e-12, or what the values of the robot file snapped to exact ones (said in the code's comment:
    a real URDF's 1.5707963268 is π/2 there) can change in J: the largest change [rad or m] times the
    arm's size."""
    changes = [float(x) for x in re.findall(r"largest change ([0-9.e+-]+)", notes_text)]
    if not changes:
        return TOL
    reach = 1.0 + float(np.abs(kinematics.fk(robot, np.zeros(robot.dof))[:3, 3]).sum())
    return TOL + 20 * max(changes) * reach


TOL = 1e-12


def _needs(tool: str) -> str:
    path = shutil.which(tool)
    if path is None:
        if os.environ.get("CI"):
            pytest.fail(f"{tool} is missing: python tests/install_test_deps.py installs it")
        pytest.skip(f"{tool} is not installed (python tests/install_test_deps.py)")
    return path


def configurations(robot, count=5, seed=11):
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.qlim[0]), robot.qlim[0], -np.pi)
    hi = np.where(np.isfinite(robot.qlim[1]), robot.qlim[1], np.pi)
    qs = rng.uniform(lo, hi, size=(count, robot.dof))
    return np.vstack([qs, np.zeros(robot.dof)])


def c_prefix(robot, name=None):
    """The prefix of the exported C names: ``name``, else the robot's name, made an identifier."""
    return c_identifier(robot.name if name is None else name, reserved=frozenset())


def compile_c(tmp_path, robot, stem, symbolic_params=False, frame="base", **options):
    """The exported C of ``robot`` built into a shared library with ``gcc -Wall -Wextra -Werror``:
    (its J function, header, source); the library is ``compile_c.lib``."""
    cc = _needs("gcc")
    header, source = ex.export_c(robot, stem, frame, symbolic_params, **options)
    (tmp_path / f"{stem}.h").write_text(header, encoding="utf-8")
    (tmp_path / f"{stem}.c").write_text(source, encoding="utf-8")
    lib = tmp_path / f"lib{stem}.so"
    subprocess.run(
        [cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-O2", "-shared", "-fPIC"]
        + ["-o", str(lib), str(tmp_path / f"{stem}.c"), "-lm"],
        check=True,
        capture_output=True,
        timeout=120,
    )
    compile_c.lib = ctypes.CDLL(str(lib))
    fn = getattr(compile_c.lib, c_prefix(robot, options.get("name")) + "_jacobian")
    fn.restype = None
    return fn, header, source


def call_c(fn, robot, q, p=None):
    n = robot.dof
    J = np.zeros(6 * n)
    q = np.ascontiguousarray(q, dtype=np.float64)
    ptr = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))  # noqa: E731
    if p is None:
        fn(ptr(q), ptr(J))
    else:
        p = np.ascontiguousarray(p, dtype=np.float64)
        fn(ptr(q), ptr(p), ptr(J))
    return J.reshape(6, n)


@pytest.mark.slow
@pytest.mark.parametrize("name", ROBOTS, ids=lambda n: os.path.basename(n))
def test_c_function_matches_the_numeric_jacobian(tmp_path, name):
    robot = robots.load(name)
    fn, header, source = compile_c(tmp_path, robot, "arm_jacobian")
    assert "malloc" not in source and "for (" not in source  # straight-line code, no allocation
    atol = tolerance(robot, source)
    assert atol < 1e-3
    for q in configurations(robot):
        np.testing.assert_allclose(call_c(fn, robot, q), kinematics.jacobian(robot, q), atol=atol, rtol=0)


def test_c_function_of_a_urdf_arm_matches_to_1e12(tmp_path, urdf_from_puma):
    robot = robots.load(urdf_from_puma)
    fn, _, source = compile_c(tmp_path, robot, "puma_urdf_jacobian")
    assert "snapped" not in source
    for q in configurations(robot):
        np.testing.assert_allclose(call_c(fn, robot, q), kinematics.jacobian(robot, q), atol=TOL, rtol=0)


def test_c_function_with_symbolic_parameters_and_tool_frame(tmp_path):
    """The course's TRR with l1, l2, l3 as an argument: its values reproduce J; doubled lengths double
    the revolute joints' linear columns."""
    robot = robots.load("trr")
    fn, header, _ = compile_c(tmp_path, robot, "trr_jacobian", symbolic_params=True, frame="tool")
    model = build_model(robot, True)
    p = np.array([float(model.params[s]) for s in parameter_order(model)])
    assert f"const double p[{len(p)}]" in header
    for q in configurations(robot):
        J = call_c(fn, robot, q, p)
        np.testing.assert_allclose(J, kinematics.jacobian(robot, q, "tool"), atol=TOL, rtol=0)
    rev = [k == "revolute" for k in robot.joint_types]
    q = configurations(robot)[0]
    np.testing.assert_allclose(call_c(fn, robot, q, 2 * p)[:3, rev], 2 * call_c(fn, robot, q, p)[:3, rev])


def test_c_export_in_one_text_compiles(tmp_path):
    """Without -o, ``export(…, "c")`` is the header and the source in one compilable text."""
    cc = _needs("cc")
    text = ex.export(robots.load("planar2"), "c")
    (tmp_path / "one.c").write_text(text, encoding="utf-8")
    subprocess.run([cc, "-std=c99", "-Wall", "-Werror", "-c", "one.c"], cwd=tmp_path, check=True, timeout=60)


@pytest.mark.slow
def test_octave_function_matches_the_numeric_jacobian(tmp_path, urdf_from_puma):
    """Every library robot and the URDF arm, in one Octave run: J at random q to 1e-12."""
    octave = _needs("octave-cli")
    cases = []
    script = ["format long;"]
    for k, name in enumerate([*ROBOTS, urdf_from_puma]):
        robot = robots.load(name)
        function = f"arm_{k}"
        _, text = ex.export_matlab(robot, function=function)
        (tmp_path / f"{function}.m").write_text(text, encoding="utf-8")
        for q in configurations(robot, count=2):
            cases.append((robot, q, tolerance(robot, text)))
            values = " ".join(f"{v:.17g}" for v in q)
            script.append(f"J = {function}([{values}]); printf('%.17g ', J'); printf('\\n');")
    lines = octave_lines(octave, tmp_path, script)
    assert len(lines) == len(cases)
    for (robot, q, atol), line in zip(cases, lines, strict=True):
        J = np.array([float(v) for v in line.split()]).reshape(6, robot.dof)
        np.testing.assert_allclose(J, kinematics.jacobian(robot, q), atol=atol, rtol=0, err_msg=robot.name)


def test_octave_refuses_a_wrong_q(tmp_path):
    octave = _needs("octave-cli")
    _, text = ex.export_matlab(robots.load("planar2"), function="planar_J")
    (tmp_path / "planar_J.m").write_text(text, encoding="utf-8")
    done = subprocess.run(
        [octave, "--no-gui", "--quiet", "--eval", "planar_J([1 2 3])"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode != 0 and "q should have 2 values, got 3" in done.stderr


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford"])
def test_numpy_module_takes_a_batch(tmp_path, name):
    robot = robots.load(name)
    module = import_source(tmp_path / f"Jn_{name}.py", ex.export(robot, "numpy"), f"Jn_{name}")
    Q = configurations(robot, count=50)
    np.testing.assert_allclose(module.J(Q), kinematics.jacobian(robot, Q), atol=TOL, rtol=0)


def test_hostile_names_stay_comments_and_identifiers(tmp_path):
    """A robot whose every name is hostile: the C compiles with -Werror and computes J, the Octave file
    runs, and no name reaches the code except reduced to [A-Za-z0-9_] or a harmless comment."""
    robot = hostile_robot()
    fn, header, source = compile_c(tmp_path, robot, "hostile_jacobian")
    q = np.array([0.3, -0.8, 1.2])
    atol = tolerance(robot, source)  # its twists are written 1.5708: snapped to π/2, said in the comment
    np.testing.assert_allclose(call_c(fn, robot, q), kinematics.jacobian(robot, q), atol=atol, rtol=0)
    for text in (header, source):
        assert text.count("/*") == text.count("*/")  # a name can never close our comment early
        code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
        name = c_prefix(robot)  # the robot's name, reduced to [A-Za-z0-9_]: every function's prefix
        assert re.fullmatch(r"[A-Za-z_]\w*", name)
        code = code.replace(name, "FUNCTION").replace(name.upper(), "FUNCTION")
        assert "system" not in code and "MARKER" not in code and "script" not in code
        assert re.findall(r'"[^"]*"', code) in ([], ['"hostile_jacobian.h"'])  # no string from a name
        directives = [line.split()[0] for line in code.splitlines() if line.startswith("#")]
        assert set(directives) <= {"#ifndef", "#define", "#endif", "#include"}
    function, mfile = ex.export_matlab(robot)
    assert re.fullmatch(r"[A-Za-z]\w*", function)
    for line in mfile.replace(function, "FUNCTION").splitlines():  # comments stay comments; code has no name
        assert line.startswith("%") and "'" not in line or "system" not in line and "MARKER" not in line
    assert INJECT not in mfile and SCRIPT not in mfile
    assert c_identifier(INJECT).isidentifier() and c_identifier("int") == "int_"


def test_export_command_writes_c_and_header_and_names_the_matlab_function(tmp_path, capsys):
    from app.cli.export import main

    assert main(["export", "planar2", "-f", "c", "-o", str(tmp_path / "arm.c")][1:]) == 0
    assert (tmp_path / "arm.h").read_text().count("void arm_jacobian(") == 1  # named after the file
    assert '#include "arm.h"' in (tmp_path / "arm.c").read_text()
    assert main(["trr", "-f", "matlab", "-o", str(tmp_path / "trr_J.m")]) == 0
    assert (tmp_path / "trr_J.m").read_text().startswith("function [J, T, Jdot] = trr_J(q, qd)")
    assert main(["trr", "-f", "matlab", "-o", str(tmp_path / "trr-J.m")]) == 1
    assert "is not a valid name" in capsys.readouterr().err
