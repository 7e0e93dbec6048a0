"""Every public function fed NaN, Inf, non-rigid poses, wrong shapes, wrong dtypes and wrong types: each call
raises ValueError (bad values, shapes, dtypes) or TypeError (wrong Python types) naming the argument, and none
crashes. The calls run in a child interpreter: before validation a NaN pose aborted the process inside libccd,
which would have killed pytest itself; a crash now fails this test with the last case the child started."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import fcl_rs
from conftest import random_poses

CHILD = textwrap.dedent(r'''
    import re, sys
    import numpy as np
    import fcl_rs

    urdf = sys.argv[1]
    failures = []

    def expect(name, call, error, pattern):
        """call() must raise `error` with a message matching `pattern`."""
        print("case", name, flush=True)
        try:
            call()
        except error as e:
            if not re.search(pattern, str(e)):
                failures.append(f"{name}: message {str(e)!r} does not match {pattern!r}")
            return
        except Exception as e:
            failures.append(f"{name}: {type(e).__name__} {e}, expected {error.__name__}")
            return
        failures.append(f"{name}: no error, expected {error.__name__}")

    nan, inf = float("nan"), float("inf")
    mesh = fcl_rs.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])
    sphere, box = fcl_rs.Sphere(0.5), fcl_rs.Box(1, 1, 1)
    I = np.eye(4)

    def bad_poses():
        """(name, value, error, message pattern) of poses every pose argument refuses."""
        for i, j in [(0, 0), (1, 2), (2, 3), (0, 3)]:
            for v in (nan, inf, -inf):
                p = I.copy(); p[i, j] = v
                yield f"entry({i},{j})={v}", p, ValueError, rf"is not a rigid transform: entry \({i}, {j}\)"
        p = I.copy(); p[3] = [1, 1, 1, 1]
        yield "last row", p, ValueError, "last row"
        p = I.copy(); p[3, 3] = nan
        yield "last row nan", p, ValueError, "last row"
        yield "scale 2", np.diag([2.0, 2, 2, 1]), ValueError, "not orthonormal"
        yield "scale 1+1e-9", np.diag([1 + 1e-9, 1, 1, 1]), ValueError, "not orthonormal"
        p = I.copy(); p[0, 1] = 0.3
        yield "shear", p, ValueError, "not orthonormal"
        yield "reflection", np.diag([1.0, 1, -1, 1]), ValueError, "reflection"
        yield "float32 scale 1.001", np.diag([1.001, 1, 1, 1]).astype(np.float32), ValueError, "not orthonormal"
        yield "shape (3, 4)", I[:3], ValueError, r"must have shape \(4, 4\), got \(3, 4\)"
        yield "shape (16,)", I.ravel(), ValueError, r"must have shape \(4, 4\), got \(16,\)"
        yield "shape (1, 4, 4)", I[None], ValueError, r"must have shape \(4, 4\)"
        yield "scalar", 1.0, ValueError, r"must have shape \(4, 4\), got \(\)"
        yield "complex", I.astype(complex), ValueError, "dtype complex128"
        yield "bool", I.astype(bool), ValueError, "dtype bool"
        yield "strings", np.full((4, 4), "1"), ValueError, "dtype <U1"
        yield "None", None, ValueError, "dtype object"
        yield "ragged list", [[1, 0, 0, 0], [0, 1, 0]], ValueError, "must be an array of numbers"
        yield "list with nan", [[1, 0, 0, nan], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], ValueError, r"entry \(0, 3\)"

    for fname in ("collide", "distance"):
        f = getattr(fcl_rs, fname)
        for a, b in [(mesh, mesh), (mesh, sphere), (sphere, mesh), (sphere, box)]:
            for name, p, error, pattern in bad_poses():
                expect(f"{fname} pose_a {name}", lambda: f(a, p, b, I), error, f"fcl_rs.{fname}: pose_a .*{pattern}")
                expect(f"{fname} pose_b {name}", lambda: f(a, I, b, p), error, f"fcl_rs.{fname}: pose_b .*{pattern}")
        for name, g in [("None", None), ("str", "mesh"), ("int", 3), ("array", I)]:
            expect(f"{fname} a={name}", lambda: f(g, I, mesh, I), TypeError, "incompatible function arguments")
            expect(f"{fname} b={name}", lambda: f(mesh, I, g, I), TypeError, "incompatible function arguments")
        expect(f"{fname} request=str", lambda: f(mesh, I, mesh, I, "req"), TypeError, "incompatible function arguments")

    poses = np.tile(I, (4, 1, 1))
    for fname in ("collide_batch", "distance_batch"):
        f = getattr(fcl_rs, fname)
        for name, p, error, pattern in bad_poses():
            # Bad values inside a float array: the error names the pose.
            if not (isinstance(p, np.ndarray) and p.shape == (4, 4) and p.dtype.kind == "f"):
                continue
            stack = poses.astype(p.dtype)
            stack[2] = p
            expect(f"{fname} poses_a[2] {name}", lambda: f(mesh, stack, sphere, poses), error, rf"fcl_rs.{fname}: poses_a\[2\] .*{pattern}")
            expect(f"{fname} poses_b[2] {name}", lambda: f(mesh, poses, sphere, stack), error, rf"fcl_rs.{fname}: poses_b\[2\] .*{pattern}")
        expect(f"{fname} shape (4, 4)", lambda: f(mesh, I, sphere, poses), ValueError, r"poses_a must have shape \(N, 4, 4\)")
        expect(f"{fname} shape (4, 3, 4)", lambda: f(mesh, poses, sphere, poses[:, :3]), ValueError, r"poses_b must have shape \(N, 4, 4\), got \(4, 3, 4\)")
        expect(f"{fname} complex", lambda: f(mesh, poses.astype(complex), sphere, poses), ValueError, "poses_a must hold real numbers")
        expect(f"{fname} None poses", lambda: f(mesh, None, sphere, poses), ValueError, "poses_a")
        expect(f"{fname} lengths", lambda: f(mesh, poses, sphere, poses[:3]), ValueError, "4 poses for the first object but 3")
        expect(f"{fname} num_threads=-1", lambda: f(mesh, poses, sphere, poses, num_threads=-1), ValueError, "num_threads must be >= 0")
        expect(f"{fname} num_threads=1.5", lambda: f(mesh, poses, sphere, poses, num_threads=1.5), TypeError, "incompatible")
        expect(f"{fname} a=None", lambda: f(None, poses, sphere, poses), TypeError, "incompatible")

    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    triangles = np.array([[0, 1, 2], [0, 1, 3]])
    for name, v, pattern in [
            ("nan", np.where(np.eye(4, 3) == 1, nan, vertices), r"vertices\[0, 0\] is not finite: nan"),
            ("inf", vertices + [[0, 0, 0], [0, 0, 0], [0, inf, 0], [0, 0, 0]], r"vertices\[2, 1\] is not finite: inf"),
            ("shape (V, 2)", vertices[:, :2], r"vertices must have shape \(V, 3\), got \(4, 2\)"),
            ("shape (12,)", vertices.ravel(), r"vertices must have shape \(V, 3\), got \(12,\)"),
            ("complex", vertices.astype(complex), "vertices must hold real numbers"),
            ("bool", vertices.astype(bool), "vertices must hold real numbers"),
            ("strings", vertices.astype(str), "vertices must hold real numbers"),
            ("None", None, "vertices must hold real numbers"),
            ("empty", np.zeros((0, 3)), r"triangles\[0, 0\] is 0, not a vertex index in \[0, 0\)")]:
        expect(f"Mesh vertices {name}", lambda: fcl_rs.Mesh(v, triangles), ValueError, pattern)
    for name, t, pattern in [
            ("F + 0.5", triangles + 0.5, r"triangles must be an array of integers \(vertex indices\), got dtype float64"),
            ("integral floats", triangles.astype(float), "triangles must be an array of integers"),
            ("bool", triangles.astype(bool), "triangles must be an array of integers"),
            ("strings", triangles.astype(str), "triangles must be an array of integers"),
            ("None", None, "triangles must be an array of integers"),
            ("negative", triangles - 1, r"triangles\[0, 0\] is -1, not a vertex index in \[0, 4\)"),
            ("too large", triangles + 2, r"triangles\[0, 2\] is 4, not a vertex index in \[0, 4\)"),
            ("uint64 huge", np.array([[0, 1, 2**64 - 1]], dtype=np.uint64), r"triangles\[0, 2\] is -1"),
            ("shape (F, 2)", triangles[:, :2], r"triangles must have shape \(F, 3\), got \(2, 2\)"),
            ("shape (6,)", triangles.ravel(), r"triangles must have shape \(F, 3\)"),
            ("empty", np.zeros((0, 3), dtype=int), "empty mesh")]:
        expect(f"Mesh triangles {name}", lambda: fcl_rs.Mesh(vertices, t), ValueError, pattern)

    shapes = {"Box": ("x", "y", "z"), "Sphere": ("radius",), "Ellipsoid": ("a", "b", "c"),
              "Capsule": ("radius", "length"), "Cylinder": ("radius", "length"), "Cone": ("radius", "length")}
    for cls, names in shapes.items():
        for k, arg in enumerate(names):
            for v in (-1.0, 0.0, -0.0, nan, inf, -inf):
                args = [0.5] * len(names); args[k] = v
                expect(f"{cls} {arg}={v}", lambda: getattr(fcl_rs, cls)(*args), ValueError,
                       rf"fcl_rs.{cls}: {arg} must be positive and finite")
            for v in ("1", None, [1.0]):
                args = [0.5] * len(names); args[k] = v
                expect(f"{cls} {arg}={v!r}", lambda: getattr(fcl_rs, cls)(*args), TypeError, "incompatible")

    for v in (0, -1):
        expect(f"CollisionRequest num_max_contacts={v}", lambda: fcl_rs.CollisionRequest(num_max_contacts=v),
               ValueError, f"num_max_contacts must be at least 1, got {v}")
        def assign():
            r = fcl_rs.CollisionRequest()
            r.num_max_contacts = v
        expect(f"CollisionRequest.num_max_contacts = {v}", assign, ValueError, "num_max_contacts must be at least 1")
    expect("CollisionRequest num_max_contacts=1.5", lambda: fcl_rs.CollisionRequest(num_max_contacts=1.5), TypeError, "incompatible")
    expect("CollisionRequest enable_contact='yes'", lambda: fcl_rs.CollisionRequest(enable_contact="yes"), TypeError, "incompatible")
    for field in ("rel_err", "abs_err"):
        for v in (-1.0, nan, inf):
            expect(f"DistanceRequest {field}={v}", lambda: fcl_rs.DistanceRequest(**{field: v}), ValueError,
                   f"fcl_rs.DistanceRequest: {field} must be non-negative and finite")
            def assign():
                r = fcl_rs.DistanceRequest()
                setattr(r, field, v)
            expect(f"DistanceRequest.{field} = {v}", assign, ValueError, f"{field} must be non-negative and finite")
    expect("DistanceRequest enable_nearest_points=2", lambda: fcl_rs.DistanceRequest(enable_nearest_points=2), TypeError, "incompatible")

    robot = fcl_rs.Robot(urdf)
    dof = robot.dof
    expect("random_configurations(-1, 1)", lambda: robot.random_configurations(-1, 1), ValueError,
           "fcl_rs.Robot.random_configurations: n must be >= 0, got -1")
    expect("random_configurations('a', 1)", lambda: robot.random_configurations("a", 1), TypeError, "incompatible")
    expect("random_configurations(1, -1)", lambda: robot.random_configurations(1, -1), TypeError, "incompatible")
    for method in ("check", "minimum_distance"):
        f = getattr(robot, method)
        api = f"fcl_rs.Robot.{method}"
        for name, q, pattern in [
                ("nan", np.where(np.arange(dof) == 2, nan, 0.0), rf"{api}: q\[2\] is not finite: nan"),
                ("inf", np.where(np.arange(dof) == 0, -inf, 0.0), rf"q\[0\] is not finite: -inf"),
                ("short", np.zeros(dof - 1), rf"q must have shape \({dof},\), got \({dof - 1},\)"),
                ("2-D", np.zeros((1, dof)), rf"q must have shape \({dof},\), got \(1, {dof}\)"),
                ("complex", np.zeros(dof, dtype=complex), "q must hold real numbers"),
                ("None", None, "q must hold real numbers"),
                ("strings", ["0"] * dof, "q must hold real numbers")]:
            expect(f"Robot.{method} {name}", lambda: f(q), ValueError, pattern)
    q = np.zeros((3, dof))
    q[1, 3] = nan
    expect("check_batch nan", lambda: robot.check_batch(q), ValueError, r"fcl_rs.Robot.check_batch: q\[1, 3\] is not finite: nan")
    expect("check_batch 1-D", lambda: robot.check_batch(np.zeros(dof)), ValueError, rf"q must have shape \(N, {dof}\), got \({dof},\)")
    expect("check_batch columns", lambda: robot.check_batch(np.zeros((2, dof + 1))), ValueError, rf"got \(2, {dof + 1}\)")
    expect("check_batch num_threads=-1", lambda: robot.check_batch(np.zeros((2, dof)), num_threads=-1), ValueError, "num_threads must be >= 0")
    expect("check_batch pairs=1", lambda: robot.check_batch(np.zeros((2, dof)), pairs=1), TypeError, "incompatible")
    expect("Robot(None)", lambda: fcl_rs.Robot(None), TypeError, "incompatible")

    print("\n".join(failures))
    sys.exit(1 if failures else 0)
''')


def test_every_public_function_refuses_bad_input(chain_urdf):
    child = subprocess.run([sys.executable, "-c", CHILD, chain_urdf], capture_output=True, text=True, timeout=300,
                           env=os.environ)
    cases = [line for line in child.stdout.splitlines() if line.startswith("case ")]
    assert child.returncode >= 0, f"the child crashed (signal {-child.returncode}) in {cases[-1] if cases else 'setup'}"
    assert child.returncode == 0, child.stdout[child.stdout.rfind("case "):] + child.stderr
    assert len(cases) > 400, len(cases)


def test_float32_and_integer_arrays_are_converted(rng):
    """What numpy users hand over: float32 poses (checked at float32's tolerance, then made orthonormal in
    double), float32 or integer vertices, unsigned indices, float32 configurations."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    triangles = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]], dtype=np.uint32)
    exact = fcl_rs.Mesh(vertices.astype(float), triangles.astype(np.int64))
    for v in (vertices, vertices.astype(np.float32)):
        assert fcl_rs.Mesh(v, triangles).num_triangles == 4
    poses = random_poses(rng, 20, 1.5)
    single = poses.astype(np.float32)
    request = fcl_rs.DistanceRequest()
    for p, s in zip(poses, single):
        d64 = fcl_rs.distance(exact, np.eye(4), fcl_rs.Sphere(0.3), p, request).min_distance
        d32 = fcl_rs.distance(exact, np.eye(4, dtype=np.float32), fcl_rs.Sphere(0.3), s, request).min_distance
        assert abs(d32 - d64) <= 1e-6 * (1 + abs(d64))
    d64, _ = fcl_rs.distance_batch(exact, poses, fcl_rs.Sphere(0.3), poses[::-1])
    d32, _ = fcl_rs.distance_batch(exact, single, fcl_rs.Sphere(0.3), single[::-1])
    np.testing.assert_allclose(d32, d64, rtol=1e-6, atol=1e-6)
    # A float32 pose a float64 query would refuse: orthonormal only to float32's precision.
    R = single[0, :3, :3].astype(np.float64)
    assert np.abs(R.T @ R - np.eye(3)).max() > 1e-12


def test_float32_configurations(chain_urdf, rng):
    robot = fcl_rs.Robot(chain_urdf)
    q = robot.random_configurations(20, 7)
    single = q.astype(np.float32)
    widened = single.astype(np.float64)
    assert np.array_equal(robot.check_batch(single)["colliding"], robot.check_batch(widened)["colliding"])
    assert robot.check(single[0]) == robot.check(widened[0])
    assert robot.random_configurations(0, 1).shape == (0, robot.dof)


@pytest.mark.parametrize("n", [0, 1])
def test_empty_and_single_batches(n):
    box = fcl_rs.Box(1, 1, 1)
    poses = np.tile(np.eye(4), (n, 1, 1))
    assert fcl_rs.collide_batch(box, poses, box, poses).shape == (n,)
