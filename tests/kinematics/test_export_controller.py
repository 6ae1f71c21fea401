"""A controller's kinematics as code: T_base_tool, J, J̇ and ∂J/∂q of the C (gcc -Wall -Wextra -Werror,
called through ctypes), MATLAB (run by Octave) and NumPy exports, against ``kinematics.fk``,
``kinematics.jacobian``, ``kinematics.jacobian_dot`` and central differences of ``kinematics.jacobian``
at random configurations; ``--exact``; names from ``--name`` or the output file; the command line."""

from __future__ import annotations

import ctypes
import re
import subprocess

import numpy as np
import pytest
from kinematics_helpers import import_source, octave_lines
from locations import DATA
from test_export_code import TOL, _needs, c_prefix, compile_c, configurations
from test_export_escaping import hostile_robot

import kinematics
import robots
from kinematics.symbolic.typeset import export as ex
from kinematics.symbolic.typeset.ccode import c_identifier
from kinematics.urdf import to_urdf

XARM = str(DATA / "xarm7_like.urdf")


@pytest.fixture(scope="module")
def urdf_from_puma(tmp_path_factory):
    """The Puma 560 written as a URDF and read back: a URDF arm whose numbers need no snapping."""
    path = tmp_path_factory.mktemp("urdf") / "puma_from_dh.urdf"
    path.write_text(to_urdf(robots.load("puma560")), encoding="utf-8")
    return str(path)


def rates(robot, count, seed=5):
    return np.random.default_rng(seed).uniform(-1.5, 1.5, size=(count, robot.dof))


def central_dJdq(robot, q, frame="base", h=1e-6):
    """∂J/∂q_k by central differences of kinematics.jacobian: (n, 6, n), accurate to about 1e-9."""
    E = np.eye(robot.dof) * h
    return np.stack(
        [
            (kinematics.jacobian(robot, q + e, frame) - kinematics.jacobian(robot, q - e, frame)) / (2 * h)
            for e in E
        ]
    )


def c_call(lib, name, *arrays, out):
    fn = getattr(lib, name)
    fn.restype = None
    ptr = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))  # noqa: E731
    args = [np.ascontiguousarray(a, dtype=np.float64) for a in arrays]
    result = np.zeros(out)
    fn(*map(ptr, args), ptr(result))
    return result


@pytest.mark.parametrize("which", ["puma560", "puma560_mdh", "stanford", "urdf"])
def test_c_fk_jacobian_jdot_and_dJdq_match_the_library(tmp_path, which, urdf_from_puma):
    """DH standard, DH modified, a prismatic joint, and a URDF: every C function to 1e-12 (∂J/∂q to the
    central differences' 1e-7)."""
    robot = robots.load(urdf_from_puma if which == "urdf" else which)
    n = robot.dof
    _, header, source = compile_c(tmp_path, robot, "arm", dJdq=True, name="arm")
    lib, P = compile_c.lib, "arm"
    for name in ("fk", "jacobian", "jacobian_dot", "jacobian_dq"):
        assert f"void {P}_{name}(" in header
    assert "snapped" not in source and "Numbers: the robot file's" in header
    Q, QD = configurations(robot), rates(robot, 6)
    for q, qd in zip(Q, QD, strict=True):
        T = c_call(lib, f"{P}_fk", q, out=16).reshape(4, 4)
        np.testing.assert_allclose(T, kinematics.fk(robot, q), atol=TOL, rtol=0)
        J = c_call(lib, f"{P}_jacobian", q, out=6 * n).reshape(6, n)
        np.testing.assert_allclose(J, kinematics.jacobian(robot, q), atol=TOL, rtol=0)
        Jd = c_call(lib, f"{P}_jacobian_dot", q, qd, out=6 * n).reshape(6, n)
        np.testing.assert_allclose(Jd, kinematics.jacobian_dot(robot, q, qd), atol=TOL, rtol=0)
        dJ = c_call(lib, f"{P}_jacobian_dq", q, out=n * 6 * n).reshape(n, 6, n)
        np.testing.assert_allclose(dJ, central_dJdq(robot, q), atol=1e-7, rtol=0)
        np.testing.assert_allclose(np.einsum("kij,k->ij", dJ, qd), Jd, atol=TOL, rtol=0)


def test_numpy_module_fk_and_jdot_take_a_batch(tmp_path):
    robot = robots.load("panda")
    module = import_source(tmp_path / "panda_k.py", ex.export(robot, "python", dJdq=True), "panda_k")
    Q, QD = configurations(robot, count=50), rates(robot, 51)
    np.testing.assert_allclose(module.T(Q), kinematics.fk(robot, Q), atol=TOL, rtol=0)
    np.testing.assert_allclose(module.J(Q), kinematics.jacobian(robot, Q), atol=TOL, rtol=0)
    np.testing.assert_allclose(module.Jdot(Q, QD), kinematics.jacobian_dot(robot, Q, QD), atol=TOL, rtol=0)
    np.testing.assert_allclose(
        module.Jdot(Q, QD[0]), kinematics.jacobian_dot(robot, Q, QD[0]), atol=TOL, rtol=0
    )
    assert module.dJdq(Q).shape == (51, 7, 6, 7)
    np.testing.assert_allclose(module.dJdq(Q[3]), central_dJdq(robot, Q[3]), atol=1e-7, rtol=0)
    with pytest.raises(ValueError, match="qd should have shape"):
        module.Jdot(Q[0], np.zeros(3))


def test_tool_frame_jdot_is_the_derivative_of_the_tool_axes_jacobian(tmp_path):
    """kinematics.jacobian_dot has no tool frame: J̇ is checked against central differences in time of
    kinematics.jacobian(q + t q̇, "tool")."""
    robot = robots.load("puma560")
    module = import_source(tmp_path / "puma_t.py", ex.export(robot, "python", frame="tool"), "puma_t")
    h = 1e-6
    for q, qd in zip(configurations(robot), rates(robot, 6), strict=True):
        fd = (
            kinematics.jacobian(robot, q + h * qd, "tool") - kinematics.jacobian(robot, q - h * qd, "tool")
        ) / (2 * h)
        np.testing.assert_allclose(module.Jdot(q, qd), fd, atol=1e-8, rtol=0)
        assert (
            np.abs(module.Jdot(q, qd) - kinematics.jacobian_dot(robot, q, qd)).max() > 1e-3
        )  # not the base one


def test_octave_runs_j_t_jdot_and_dJdq(tmp_path, urdf_from_puma):
    octave = _needs("octave-cli")
    cases, script = [], ["format long;"]
    for k, name in enumerate(["puma560", "puma560_mdh", urdf_from_puma]):
        robot = robots.load(name)
        function = f"arm_{k}"
        _, text = ex.export_matlab(robot, function=function, dJdq=True)
        assert text.startswith(f"function [J, T, Jdot, dJdq] = {function}(q, qd)")
        (tmp_path / f"{function}.m").write_text(text, encoding="utf-8")
        for q, qd in zip(configurations(robot, count=2), rates(robot, 3), strict=True):
            cases.append((robot, q, qd))
            vq, vqd = (" ".join(f"{v:.17g}" for v in x) for x in (q, qd))
            script.append(f"[J, T, Jd, dJ] = {function}([{vq}], [{vqd}]);")
            script.append("printf('%.17g ', J', T', Jd', permute(dJ, [2 1 3])); printf('\\n');")
    lines = octave_lines(octave, tmp_path, script)
    assert len(lines) == len(cases)
    for (robot, q, qd), line in zip(cases, lines, strict=True):
        n, v = robot.dof, np.array([float(x) for x in line.split()])
        J, T, Jd, dJ = np.split(v, [6 * n, 6 * n + 16, 12 * n + 16])
        np.testing.assert_allclose(J.reshape(6, n), kinematics.jacobian(robot, q), atol=TOL, rtol=0)
        np.testing.assert_allclose(T.reshape(4, 4), kinematics.fk(robot, q), atol=TOL, rtol=0)
        np.testing.assert_allclose(Jd.reshape(6, n), kinematics.jacobian_dot(robot, q, qd), atol=TOL, rtol=0)
        # Octave's dJ(:, :, k), rows transposed: the block k is ∂J/∂q_k row-major
        np.testing.assert_allclose(dJ.reshape(n, 6, n), central_dJdq(robot, q), atol=1e-7, rtol=0)


def test_octave_jdot_without_qd_is_refused(tmp_path):
    octave = _needs("octave-cli")
    _, text = ex.export_matlab(robots.load("planar2"), function="p2")
    (tmp_path / "p2.m").write_text(text, encoding="utf-8")
    done = subprocess.run(
        [
            octave,
            "--no-gui",
            "--quiet",
            "--eval",
            "[J, T] = p2([1 2]); printf('%.17g\\n', T(1, 4)); [J, T, Jd] = p2([1 2])",
        ],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode != 0 and "Jdot needs qd, 2 joint rates" in done.stderr
    x = float(done.stdout.split()[0])  # T's x with q = (1, 2) rad: a1 cos q1 + a2 cos(q1 + q2)
    assert x == pytest.approx(kinematics.fk(robots.load("planar2"), [1.0, 2.0])[0, 3], abs=1e-12)


@pytest.mark.slow
def test_exact_keeps_the_xarm7_file_numbers(tmp_path):
    """The xArm7's URDF writes right angles as 1.5708: snapped, J differs from the file's by about 1e-5;
    with exact=True it is the file's J (and T, J̇) to 1e-12, and the module says which was done."""
    robot = robots.load(XARM)
    Q, QD = configurations(robot, count=20), rates(robot, 21)
    snapped = import_source(tmp_path / "xs.py", ex.export(robot, "python"), "xs")
    assert np.abs(snapped.J(Q) - kinematics.jacobian(robot, Q)).max() > 1e-6
    assert "snapped to exact ones" in snapped.__doc__ and "--exact keeps them" in snapped.__doc__
    exact = import_source(tmp_path / "xe.py", ex.export(robot, "python", exact=True), "xe")
    assert "every value of the robot file as written" in exact.__doc__ and not exact.NOTES[0].startswith(
        "6 value"
    )
    np.testing.assert_allclose(exact.J(Q), kinematics.jacobian(robot, Q), atol=TOL, rtol=0)
    np.testing.assert_allclose(exact.T(Q), kinematics.fk(robot, Q), atol=TOL, rtol=0)
    np.testing.assert_allclose(exact.Jdot(Q, QD), kinematics.jacobian_dot(robot, Q, QD), atol=TOL, rtol=0)


def test_exact_c_of_an_arm_written_with_1_5708(tmp_path):
    """The hostile robot's twists are written 1.5708: its exact C is the file's J to 1e-12, the snapped
    one is not; the header says which was done."""
    robot = hostile_robot()
    q = np.array([0.3, -0.8, 1.2])
    snapped_fn, header, _ = compile_c(tmp_path, robot, "snapped")
    assert "snapped to exact ones" in header
    assert np.abs(c_call_j(snapped_fn, robot, q) - kinematics.jacobian(robot, q)).max() > 1e-7
    (tmp_path / "e").mkdir()
    exact_fn, header, _ = compile_c(tmp_path / "e", robot, "exact", exact=True)
    assert "every value of the robot file as written (--exact; nothing snapped)" in header
    np.testing.assert_allclose(c_call_j(exact_fn, robot, q), kinematics.jacobian(robot, q), atol=TOL, rtol=0)


def c_call_j(fn, robot, q):
    J = np.zeros(6 * robot.dof)
    ptr = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))  # noqa: E731
    fn(ptr(np.ascontiguousarray(q, dtype=np.float64)), ptr(J))
    return J.reshape(6, robot.dof)


@pytest.mark.parametrize(
    "name, prefix",
    [
        ("my arm", "my_arm"),
        ("3dof", "robot_3dof"),
        ("a;b(){}", "a_b"),
        ("ramię ≥ 2", "rami_2"),
        ("int", "int"),
        ("__x__y", "x_y"),
        (";;;", "robot"),
    ],
)
def test_hostile_names_become_c_identifiers_that_compile(tmp_path, name, prefix):
    robot = robots.load("planar2")
    assert c_prefix(robot, name) == prefix
    fn, header, _ = compile_c(tmp_path, robot, "arm", name=name)  # finds PREFIX_jacobian in the library
    assert f"void {prefix}_fk(" in header and f"#define {prefix.upper()}_JACOBIAN_ROWS 6" in header
    q = np.array([0.4, -1.1])
    np.testing.assert_allclose(c_call_j(fn, robot, q), kinematics.jacobian(robot, q), atol=TOL, rtol=0)
    function, text = ex.export_matlab(robot, function=name)
    assert re.fullmatch(r"[A-Za-z]\w*", function) and text.startswith(f"function [J, T, Jdot] = {function}(")
    assert c_identifier("end", reserved=frozenset({"end"})) == "end_"


def test_export_command_names_options_and_robot_choice(tmp_path, capsys):
    from app.cli.export import main
    from app.cli.main import main as top

    assert main(["--urdf", str(DATA / "iiwa14_like.urdf"), "-f", "c", "-o", str(tmp_path / "iiwa.c")]) == 0
    assert (
        "void iiwa_jacobian_dot(const double q[7], const double qd[7], double Jdot[42]);"
        in (tmp_path / "iiwa.h").read_text()
    )
    assert main(["--robot", "planar2", "-f", "c", "--name", "ctl", "-o", str(tmp_path / "x-y.c")]) == 0
    assert '#include "x-y.h"' in (tmp_path / "x-y.c").read_text()
    assert "void ctl_jacobian(" in (tmp_path / "x-y.h").read_text()
    assert main(["planar2", "-f", "c", "-o", str(tmp_path / "9 arm;.c")]) == 0
    assert "void robot_9_arm_fk(" in (tmp_path / "robot_9_arm.h").read_text()
    assert main(["planar2", "-f", "matlab", "--name", "other", "-o", str(tmp_path / "pm.m")]) == 1
    assert "--name other needs -o other.m" in capsys.readouterr().err
    assert main(["pumaa560"]) == 1
    assert "did you mean puma560" in capsys.readouterr().err
    assert main(["planar2", "--exact"]) == 2  # LaTeX: not code
    assert "--exact, --dJdq and --name are for python, numpy, c, matlab" in capsys.readouterr().err
    assert main(["planar2", "--urdf", str(DATA / "iiwa14_like.urdf")]) == 2
    assert "give one robot" in capsys.readouterr().err
    assert top(["--help"]) == 0
    help_text = " ".join(capsys.readouterr().out.split())
    assert "LaTeX, MathML or JSON" in help_text and "Python/NumPy, C or MATLAB/Octave" in help_text
