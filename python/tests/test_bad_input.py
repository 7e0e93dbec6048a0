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

    # Environment: every argument of every method, and the OBB environment's missing distances.
    env = fcl_rs.Environment(urdf)
    env.add_shape("box", box, I)
    api = "fcl_rs.Environment"
    expect("Environment KDOP18", lambda: fcl_rs.Environment(urdf, bv="KDOP18"), ValueError, f"{api}: bv 'KDOP18' is not supported")
    expect("Environment AABB", lambda: fcl_rs.Environment(urdf, bv="AABB"), ValueError, "unknown BV type 'AABB'")
    expect("Environment(None)", lambda: fcl_rs.Environment(None), TypeError, "incompatible")
    expect("Environment missing urdf", lambda: fcl_rs.Environment(urdf + ".missing"), RuntimeError, "missing")
    adds = [("add_shape", lambda n, p: env.add_shape(n, sphere, p)),
            ("add_mesh", lambda n, p: env.add_mesh(n, vertices, triangles, p))]
    if hasattr(fcl_rs, "OcTree"):
        adds.append(("add_octree", lambda n, p: env.add_octree(n, fcl_rs.OcTree(vertices, 0.1), p)))
    for method, call in adds:
        expect(f"{method} name ''", lambda: call("", I), ValueError, f"{api}.{method}: name must not be empty")
        expect(f"{method} name taken", lambda: call("box", I), ValueError, f"{api}.{method}: name 'box' is taken")
        expect(f"{method} name None", lambda: call(None, I), TypeError, "incompatible")
        for name, p, error, pattern in bad_poses():
            expect(f"{method} pose {name}", lambda: call("new", p), error, f"{api}.{method}: pose .*{pattern}")
    assert env.obstacle_names == ["box"], env.obstacle_names
    for name, shape in [("mesh", mesh)] + ([("octree", fcl_rs.OcTree(vertices, 0.1))] if hasattr(fcl_rs, "OcTree") else []):
        expect(f"add_shape shape={name}", lambda: env.add_shape("new", shape, I), ValueError if name == "mesh" else TypeError,
               f"{api}.add_shape: shape is refused: .*not a primitive shape" if name == "mesh" else "incompatible")
    expect("add_shape shape=None", lambda: env.add_shape("new", None, I), TypeError, "incompatible")
    # Planes and halfspaces: a normal of three finite numbers with a non-zero finite length, a finite offset.
    for cls in (fcl_rs.Plane, fcl_rs.Halfspace):
        where = f"fcl_rs.{cls.__name__}"
        expect(f"{where} normal nan", lambda: cls([0, nan, 1], 0), ValueError, rf"{where}: normal\[1\] is not finite")
        expect(f"{where} normal inf", lambda: cls([inf, 0, 0], 0), ValueError, rf"{where}: normal\[0\] is not finite")
        expect(f"{where} normal zero", lambda: cls([0, 0, 0], 0), ValueError, f"{where}: normal must have a non-zero finite length")
        expect(f"{where} normal overflow", lambda: cls([1e200, 1e200, 0], 0), ValueError, f"{where}: normal must have a non-zero finite length")
        expect(f"{where} normal shape", lambda: cls([0, 1], 0), ValueError, rf"{where}: normal must have shape \(3,\)")
        expect(f"{where} normal dtype", lambda: cls(["a", "b", "c"], 0), ValueError, f"{where}: normal must hold real numbers")
        expect(f"{where} offset nan", lambda: cls([0, 0, 1], nan), ValueError, f"{where}: offset must be finite")
        expect(f"{where} offset -inf", lambda: cls([0, 0, 1], -inf), ValueError, f"{where}: offset must be finite")
        expect(f"{where} offset None", lambda: cls([0, 0, 1], None), TypeError, "incompatible")
    expect("add_mesh vertices nan", lambda: env.add_mesh("new", np.where(np.eye(4, 3) == 1, nan, vertices), triangles, I),
           ValueError, rf"{api}.add_mesh: vertices\[0, 0\] is not finite")
    expect("add_mesh vertices shape", lambda: env.add_mesh("new", vertices[:, :2], triangles, I), ValueError,
           rf"{api}.add_mesh: vertices must have shape \(V, 3\)")
    expect("add_mesh triangles float", lambda: env.add_mesh("new", vertices, triangles + 0.5, I), ValueError,
           f"{api}.add_mesh: triangles must be an array of integers")
    expect("add_mesh triangles range", lambda: env.add_mesh("new", vertices, triangles + 2, I), ValueError,
           rf"{api}.add_mesh: triangles\[0, 2\] is 4")
    expect("add_mesh empty", lambda: env.add_mesh("new", vertices, np.zeros((0, 3), dtype=int), I), ValueError, "empty mesh")
    if hasattr(fcl_rs, "OcTree"):
        expect("add_octree octree=None", lambda: env.add_octree("new", None, I), TypeError, "incompatible")
        expect("add_octree octree=box", lambda: env.add_octree("new", box, I), TypeError, "incompatible")
    for method, call in [("set_pose", lambda n: env.set_pose(n, I)), ("pose", env.pose), ("remove", env.remove)]:
        expect(f"{method} unknown", lambda: call("nothing"), ValueError, f"{api}.{method}: name 'nothing' names no obstacle")
        expect(f"{method} None", lambda: call(None), TypeError, "incompatible")
    for name, p, error, pattern in bad_poses():
        expect(f"set_pose pose {name}", lambda: env.set_pose("box", p), error, f"{api}.set_pose: pose .*{pattern}")
    expect("contains None", lambda: None in env, TypeError, "incompatible")
    assert env.obstacle_names == ["box"] and np.array_equal(env.pose("box"), I), "a refused edit changed the environment"

    def bad_configurations(argument, single):
        """(name, value, message pattern) of configurations `argument` refuses; (dof,) or (N, dof)."""
        shape = (dof,) if single else (3, dof)
        q = np.zeros(shape); q.flat[2] = nan
        index = "2" if single else "0, 2"
        yield "nan", q, rf"{argument}\[{index}\] is not finite: nan"
        q = np.zeros(shape); q.flat[-1] = inf
        yield "inf", q, rf"{argument}\[.*\] is not finite: inf"
        wrong = (dof - 1,) if single else (3, dof + 1)
        yield "shape", np.zeros(wrong), rf"{argument} must have shape"
        yield "rank", np.zeros((1,) + shape), rf"{argument} must have shape"
        yield "complex", np.zeros(shape, dtype=complex), f"{argument} must hold real numbers"
        yield "None", None, f"{argument} must hold real numbers"
        yield "strings", np.zeros(shape).astype(str), f"{argument} must hold real numbers"

    Z, Z3 = np.zeros(dof), np.zeros((3, dof))
    obb = fcl_rs.Environment(urdf, bv="OBB")
    for name, q, pattern in bad_configurations("q", True):
        expect(f"query q {name}", lambda: env.query(q), ValueError, f"{api}.query: {pattern}")
    for name, q, pattern in bad_configurations("q", False):
        expect(f"check_batch q {name}", lambda: env.check_batch(q), ValueError, f"{api}.check_batch: {pattern}")
    for name, q, pattern in bad_configurations("start", True):
        expect(f"check_motion start {name}", lambda: env.check_motion(q, Z), ValueError, f"{api}.check_motion: {pattern}")
    for name, q, pattern in bad_configurations("end", True):
        expect(f"check_motion end {name}", lambda: env.check_motion(Z, q), ValueError, f"{api}.check_motion: {pattern}")
    for name, q, pattern in bad_configurations("waypoints", False):
        expect(f"check_path waypoints {name}", lambda: env.check_path(q), ValueError, f"{api}.check_path: {pattern}")
    for name, q, pattern in bad_configurations("starts", False):
        expect(f"check_motion_batch starts {name}", lambda: env.check_motion_batch(q, Z3), ValueError, f"{api}.check_motion_batch: {pattern}")
    for name, q, pattern in bad_configurations("ends", False):
        expect(f"check_motion_batch ends {name}", lambda: env.check_motion_batch(Z3, q), ValueError, f"{api}.check_motion_batch: {pattern}")
    expect("check_path no waypoints", lambda: env.check_path(np.zeros((0, dof))), ValueError,
           rf"{api}.check_path: waypoints must have at least one row, got \(0, {dof}\)")
    expect("check_motion_batch rows", lambda: env.check_motion_batch(Z3, Z3[:2]), ValueError,
           rf"{api}.check_motion_batch: ends must have shape \(3, {dof}\), got \(2, {dof}\)")
    for method, call in [("check_motion", lambda **k: env.check_motion(Z, Z, **k)),
                         ("check_path", lambda **k: env.check_path(Z3, **k)),
                         ("check_motion_batch", lambda **k: env.check_motion_batch(Z3, Z3, **k))]:
        for v in (0.0, -1.0, 1.5, nan, inf):
            expect(f"{method} tolerance={v}", lambda: call(tolerance=v), ValueError, f"{api}.{method}: tolerance must be in \\(0, 1\\]")
        expect(f"{method} tolerance='a'", lambda: call(tolerance="a"), TypeError, "incompatible")
        expect(f"{method} earliest=1", lambda: call(earliest=1), TypeError, "incompatible")
    for method, call in [("check_batch", lambda **k: env.check_batch(Z3, **k)),
                         ("check_motion_batch", lambda **k: env.check_motion_batch(Z3, Z3, **k))]:
        expect(f"{method} num_threads=-1", lambda: call(num_threads=-1), ValueError, f"{api}.{method}: num_threads must be >= 0")
        expect(f"{method} num_threads=1.5", lambda: call(num_threads=1.5), TypeError, "incompatible")
    for method, call in [("query", lambda **k: env.query(Z, **k)), ("check_batch", lambda **k: env.check_batch(Z3, **k))]:
        expect(f"{method} pairs=1", lambda: call(pairs=1), TypeError, "incompatible")
        expect(f"{method} minimum_distance=1", lambda: call(minimum_distance=1), TypeError, "incompatible")
    expect("OBB query minimum_distance", lambda: obb.query(Z, minimum_distance=True), ValueError,
           f"{api}.query: minimum_distance needs a distance query, which FCL lacks for OBB trees")
    expect("OBB check_batch minimum_distance", lambda: obb.check_batch(Z3, minimum_distance=True), ValueError,
           f"{api}.check_batch: minimum_distance needs a distance query")
    expect("OBB check_motion", lambda: obb.check_motion(Z, Z), ValueError, f"{api}.check_motion: motion checks need a distance query")
    expect("OBB check_path", lambda: obb.check_path(Z3), ValueError, f"{api}.check_path: motion checks need")
    expect("OBB check_motion_batch", lambda: obb.check_motion_batch(Z3, Z3), ValueError, f"{api}.check_motion_batch: motion checks need")

    if hasattr(fcl_rs, "OcTree"):
        points = np.zeros((4, 3))
        for name, v, pattern in [
                ("nan", np.where(np.eye(4, 3) == 1, nan, points), r"points\[0, 0\] is not finite: nan"),
                ("shape (N, 2)", points[:, :2], r"points must have shape \(N, 3\), got \(4, 2\)"),
                ("shape (12,)", points.ravel(), r"points must have shape \(N, 3\)"),
                ("complex", points.astype(complex), "points must hold real numbers"),
                ("None", None, "points must hold real numbers"),
                ("far", points + [[0, 0, 0], [0, 0, 0], [0, 4000.0, 0], [0, 0, 0]], r"points\[2\] \(0.0+, 4000.0+, 0.0+\) is outside the map"),
                ("very far", points + [[1e300, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]], r"points\[0\] .* is outside the map"),
                ("edge", points + [[0, 0, 0], [0, 0, 3276.8], [0, 0, 0], [0, 0, 0]], r"points\[1\] .* is outside the map")]:
            expect(f"OcTree points {name}", lambda: fcl_rs.OcTree(v, 0.1), ValueError, f"fcl_rs.OcTree: {pattern}")
            octree = fcl_rs.OcTree(vertices, 0.1)
            expect(f"OcTree.insert points {name}", lambda: octree.insert(v), ValueError, f"fcl_rs.OcTree.insert: {pattern}")
            assert octree.num_occupied == fcl_rs.OcTree(vertices, 0.1).num_occupied, "a refused insert changed the map"
        for v in (0.0, -0.1, nan, inf):
            expect(f"OcTree resolution={v}", lambda: fcl_rs.OcTree(points, v), ValueError,
                   "fcl_rs.OcTree: resolution must be positive and finite")
        expect("OcTree resolution='a'", lambda: fcl_rs.OcTree(points, "a"), TypeError, "incompatible")
        for name, origin, pattern in [("shape (2,)", [0, 0], r"sensor_origin must have shape \(3,\), got \(2,\)"),
                                      ("nan", [0, nan, 0], r"sensor_origin\[1\] is not finite"),
                                      ("far", [0, 0, 1e4], r"sensor_origin \(.*\) is outside the map"),
                                      ("strings", ["0", "0", "0"], "sensor_origin must hold real numbers")]:
            expect(f"OcTree.insert sensor_origin {name}", lambda: octree.insert(points, sensor_origin=origin), ValueError,
                   f"fcl_rs.OcTree.insert: {pattern}")
        for method, call in [("from_file", fcl_rs.OcTree.from_file), ("save", octree.save)]:
            expect(f"OcTree.{method} extension", lambda: call("/tmp/map.txt"), ValueError,
                   rf"fcl_rs.OcTree.{method}: path '/tmp/map.txt' must end in .bt \(binary octomap\) or .ot")
            expect(f"OcTree.{method} None", lambda: call(None), TypeError, "incompatible")
        for ext in ("bt", "ot"):
            expect(f"OcTree.from_file missing .{ext}", lambda: fcl_rs.OcTree.from_file(f"/nonexistent/map.{ext}"),
                   RuntimeError, f"fcl_rs.OcTree.from_file: cannot read '/nonexistent/map.{ext}'")
            expect(f"OcTree.save unwritable .{ext}", lambda: octree.save(f"/nonexistent/map.{ext}"),
                   RuntimeError, f"fcl_rs.OcTree.save: cannot write '/nonexistent/map.{ext}'")

    # Solids: a closed tetrahedron; `mesh` runs its edge (0, 1) the same way in two triangles.
    solid = fcl_rs.Solid(fcl_rs.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                                     [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))
    expect("Solid not closed", lambda: fcl_rs.Solid(mesh), ValueError,
           r"fcl_rs::SolidMesh: the mesh is not closed: edge \(0, 1\) has inconsistent orientation")
    for name, g in [("None", None), ("Sphere", sphere), ("array", I)]:
        expect(f"Solid mesh={name}", lambda: fcl_rs.Solid(g), TypeError, "incompatible")
    for method in ("classify", "contains", "distance_to_surface"):
        for name, point, pattern in [("nan", [nan, 0, 0], r"point\[0\] is not finite: nan"),
                                     ("inf", [0, 0, inf], r"point\[2\] is not finite: inf"),
                                     ("shape (2,)", [0, 0], r"point must have shape \(3,\), got \(2,\)"),
                                     ("strings", ["0", "0", "0"], "point must hold real numbers"),
                                     ("None", None, "point must hold real numbers")]:
            expect(f"Solid.{method} {name}", lambda: getattr(solid, method)(point), ValueError,
                   f"fcl_rs.Solid.{method}: {pattern}")
    for name, p, error, pattern in bad_poses():
        expect(f"collide_solids pose_a {name}", lambda: fcl_rs.collide_solids(solid, p, solid, I), error,
               f"fcl_rs.collide_solids: pose_a .*{pattern}")
        expect(f"collide_solids pose_b {name}", lambda: fcl_rs.collide_solids(solid, I, solid, p), error,
               f"fcl_rs.collide_solids: pose_b .*{pattern}")
    for name, g in [("None", None), ("Mesh", mesh), ("int", 3)]:
        expect(f"collide_solids a={name}", lambda: fcl_rs.collide_solids(g, I, solid, I), TypeError, "incompatible")
    expect("collide_solids containment=str", lambda: fcl_rs.collide_solids(solid, I, solid, I, containment="yes"),
           TypeError, "incompatible")

    print("\n".join(failures))
    sys.exit(1 if failures else 0)
''')


def test_every_public_function_refuses_bad_input(chain_urdf):
    child = subprocess.run([sys.executable, "-c", CHILD, chain_urdf], capture_output=True, text=True, timeout=300,
                           env=os.environ)
    cases = [line for line in child.stdout.splitlines() if line.startswith("case ")]
    assert child.returncode >= 0, f"the child crashed (signal {-child.returncode}) in {cases[-1] if cases else 'setup'}"
    assert child.returncode == 0, child.stdout[child.stdout.rfind("case "):] + child.stderr
    assert len(cases) > 700, len(cases)


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
