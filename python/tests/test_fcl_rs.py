"""The Python module: meshes, shapes, single queries, batches equal to single queries, robots, errors."""
import os
import runpy

import numpy as np
import pytest

import fcl_rs
from conftest import SOURCE_DIR, random_poses, torus

THREADS = [1, 2, 4]


def test_quickstart_runs_and_readme_quotes_it(capsys):
    path = os.path.join(SOURCE_DIR, "python", "examples", "quickstart.py")
    runpy.run_path(path, run_name="__main__")
    out = capsys.readouterr().out
    assert "colliding: True" in out
    # The tetrahedron's vertex (1, 0, 0) is 0.75 from the box's face x = 1.75 (exact mesh-shape leaves).
    assert "distance: 0.75 " in out
    with open(path) as f, open(os.path.join(SOURCE_DIR, "README.md")) as readme:
        assert f.read() in readme.read(), "README's Python quick start differs from python/examples/quickstart.py"


def test_mesh_from_arrays_and_file(tmp_path):
    vertices, triangles = torus()
    mesh = fcl_rs.Mesh(vertices, triangles)
    assert (mesh.num_vertices, mesh.num_triangles) == (len(vertices), len(triangles))
    obj = tmp_path / "torus.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in vertices) +
                   "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles))
    loaded = fcl_rs.Mesh.from_file(str(obj))
    assert loaded.num_triangles == len(triangles)
    pose = np.eye(4)
    pose[0, 3] = 0.6
    assert fcl_rs.collide(loaded, np.eye(4), fcl_rs.Sphere(0.25), pose).is_collision
    pose[0, 3] = 0.0
    assert not fcl_rs.collide(loaded, np.eye(4), fcl_rs.Sphere(0.25), pose).is_collision


def test_contacts_and_nearest_points_like_python_fcl():
    mesh = fcl_rs.Mesh(*torus())
    pose = np.eye(4)
    pose[:3, 3] = [0.8, 0.0, 0.0]  # across the torus' outer equator
    result = fcl_rs.collide(mesh, np.eye(4), fcl_rs.Box(0.2, 0.2, 0.2), pose,
                            fcl_rs.CollisionRequest(num_max_contacts=1000, enable_contact=True))
    assert result.is_collision and len(result.contacts) > 0
    for c in result.contacts:
        assert 0 <= c.b1 < 256 and c.pos.shape == (3,) and abs(np.linalg.norm(c.normal) - 1) < 1e-9
        assert c.penetration_depth >= 0
    pose[:3, 3] = [2.0, 0.0, 0.0]
    far = fcl_rs.distance(mesh, np.eye(4), fcl_rs.Sphere(0.5), pose, fcl_rs.DistanceRequest(enable_nearest_points=True))
    # The torus reaches x = 0.8, the sphere starts at x = 1.5.
    assert far.min_distance == pytest.approx(0.7, abs=1e-9)
    assert far.nearest_points[0] == pytest.approx([0.8, 0, 0], abs=1e-9)
    assert far.nearest_points[1] == pytest.approx([1.5, 0, 0], abs=1e-9)


@pytest.mark.parametrize("other", ["mesh", "box", "capsule", "cylinder", "cone", "ellipsoid"])
def test_collide_batch_equals_single_queries(rng, other):
    mesh = fcl_rs.Mesh(*torus())
    b = {"mesh": fcl_rs.Mesh(*torus(0.4, 0.1)), "box": fcl_rs.Box(0.5, 0.4, 0.3), "capsule": fcl_rs.Capsule(0.1, 0.6),
         "cylinder": fcl_rs.Cylinder(0.2, 0.5), "cone": fcl_rs.Cone(0.2, 0.5),
         "ellipsoid": fcl_rs.Ellipsoid(0.3, 0.2, 0.1)}[other]
    poses_a, poses_b = random_poses(rng, 200, 0.5), random_poses(rng, 200, 0.9)
    single = np.array([fcl_rs.collide(mesh, pa, b, pb).is_collision for pa, pb in zip(poses_a, poses_b)])
    assert 5 < single.sum() < len(single) - 5
    for threads in THREADS:
        batch = fcl_rs.collide_batch(mesh, poses_a, b, poses_b, num_threads=threads)
        assert batch.dtype == np.bool_ and np.array_equal(batch, single)


def test_distance_batch_equals_single_queries(rng):
    mesh, other = fcl_rs.Mesh(*torus()), fcl_rs.Mesh(*torus(0.4, 0.1))
    poses_a, poses_b = random_poses(rng, 100, 0.5), random_poses(rng, 100, 1.5)
    request = fcl_rs.DistanceRequest(enable_nearest_points=True)
    single = [fcl_rs.distance(mesh, pa, other, pb, request) for pa, pb in zip(poses_a, poses_b)]
    for threads in THREADS:
        distances, points = fcl_rs.distance_batch(mesh, poses_a, other, poses_b, num_threads=threads)
        assert distances.shape == (100,) and points.shape == (100, 2, 3)
        assert np.array_equal(distances, [r.min_distance for r in single])
        assert np.array_equal(points, [r.nearest_points for r in single])


def test_robot_names_limits_and_batches(chain_urdf, rng):
    robot = fcl_rs.Robot(chain_urdf)
    assert robot.name == "folding_chain" and robot.dof == 5
    assert robot.link_names == [f"link{i}" for i in range(6)] + ["tip"]
    assert robot.joint_names == [f"joint{i}" for i in range(1, 6)]
    assert np.array_equal(robot.lower, [-2.8] * 5) and np.array_equal(robot.upper, [2.8] * 5)
    q = robot.random_configurations(300, seed=7)
    assert q.shape == (300, 5) and (q >= robot.lower).all() and (q <= robot.upper).all()
    single = [robot.check(row) for row in q]
    assert 10 < sum(bool(p) for p in single) < 290
    distances = np.array([robot.minimum_distance(row) for row in q])
    for threads in THREADS:
        out = robot.check_batch(q, pairs=True, minimum_distance=True, num_threads=threads)
        assert np.array_equal(out["colliding"], [bool(p) for p in single])
        assert [[tuple(p) for p in rows] for rows in out["pairs"]] == single
        assert np.array_equal(out["minimum_distance"], distances)
        assert np.array_equal((distances == 0), out["colliding"])
    flags = robot.check_batch(q)
    assert set(flags) == {"colliding"}
    # The output array owns no copy of its own: it wraps the C++ result.
    assert not flags["colliding"].flags.owndata


def test_planning_groups_map_a_planner_joints_onto_the_configuration(chain_urdf, tmp_path):
    srdf = tmp_path / "chain.srdf"
    srdf.write_text("""<robot name="folding_chain">
  <group name="lower"><chain base_link="link0" tip_link="link2"/></group>
  <group name="upper"><joint name="joint5"/><link name="link3"/></group>
  <group name="both"><group name="upper"/><group name="lower"/></group>
  <group_state name="folded" group="both"><joint name="joint1" value="1.5"/><joint name="joint5" value="-2"/>
  </group_state>
</robot>""")
    for cls in (fcl_rs.Robot, fcl_rs.Environment):
        robot = cls(chain_urdf, str(srdf))
        assert robot.groups == {"lower": [0, 1], "upper": [2, 4], "both": [0, 1, 2, 4]}
        assert np.array_equal(robot.default_configuration, np.zeros(5))
        assert np.array_equal(robot.group_state("folded"), [1.5, 0, 0, 0, -2])
        assert np.array_equal(robot.group_state("folded", group="both"), [1.5, 0, 0, 0, -2])
        # A planner's state for a group goes into a whole configuration by the group's indices.
        q = robot.default_configuration
        q[robot.groups["upper"]] = [0.5, -0.5]
        assert np.array_equal(q, [0, 0, 0.5, 0, -0.5])
        with pytest.raises(ValueError, match=r"group_state: fcl_rs: no group state 'open' of group 'both'"):
            robot.group_state("open", group="both")
        assert cls(chain_urdf).groups == {}
    bad = tmp_path / "bad.srdf"
    bad.write_text('<robot name="folding_chain">\n  <group name="a"><joint name="elbow"/></group>\n</robot>\n')
    # Read on first use: an SRDF kept for its disabled pairs loads, its groups raise naming the file and line.
    robot = fcl_rs.Robot(chain_urdf, str(bad))
    with pytest.raises(RuntimeError, match=r"bad.srdf' line 2: joint 'elbow' is not a joint of robot"):
        robot.groups


def test_every_supported_bv_type_checks_like_rs(chain_urdf):
    rs = fcl_rs.Robot(chain_urdf)
    q = rs.random_configurations(100, seed=11)
    expected = [rs.check(row) for row in q]
    for bv in ("OBBRSS", "OBB", "RSS"):
        robot = fcl_rs.Robot(chain_urdf, bv=bv)
        assert [robot.check(row) for row in q] == expected, bv
        assert np.array_equal(robot.check_batch(q, num_threads=2)["colliding"], [bool(p) for p in expected]), bv


def test_errors_keep_the_library_messages(tmp_path, chain_urdf):
    with pytest.raises(ValueError, match=r"fcl_rs.Mesh: triangles\[1, 2\] is 4, not a vertex index in \[0, 4\)"):
        fcl_rs.Mesh(np.eye(4, 3), [[0, 1, 2], [1, 2, 4]])
    with pytest.raises(ValueError, match=r"fcl_rs.Mesh: vertices\[2, 0\] is not finite: nan"):
        fcl_rs.Mesh([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]])
    with pytest.raises(ValueError, match=r"shape \(V, 3\)"):
        fcl_rs.Mesh(np.zeros((3, 2)), [[0, 1, 2]])
    missing = str(tmp_path / "missing.stl")
    with pytest.raises(RuntimeError, match="missing.stl"):
        fcl_rs.Mesh.from_file(missing)
    with pytest.raises(RuntimeError, match="no_robot.urdf"):
        fcl_rs.Robot(str(tmp_path / "no_robot.urdf"))
    with pytest.raises(ValueError, match="unknown BV type 'AABB'"):
        fcl_rs.Robot(chain_urdf, bv="AABB")
    robot = fcl_rs.Robot(chain_urdf)
    with pytest.raises(ValueError, match=r"fcl_rs.Robot.check_batch: q must have shape \(N, 5\), got \(3, 4\)"):
        robot.check_batch(np.zeros((3, 4)))
    with pytest.raises(ValueError, match=r"q\[0, 0\] is not finite"):
        robot.check_batch(np.full((2, 5), np.nan), num_threads=2)
    # Every check goes through the thread-safe const query, which KDOP18's refitted trees cannot serve:
    # refused at construction, naming the types that work.
    for name in ("KDOP18", "kdop18"):
        with pytest.raises(ValueError, match=r"bv 'KDOP18' is not supported .* use one of RS, OBBRSS, OBB, RSS$"):
            fcl_rs.Robot(chain_urdf, bv=name)
    box = fcl_rs.Box(1, 1, 1)
    identity = np.tile(np.eye(4), (3, 1, 1))
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        fcl_rs.collide_batch(box, np.zeros((3, 3, 3)), box, identity)
    with pytest.raises(ValueError, match="3 poses for the first object but 2 for the second"):
        fcl_rs.collide_batch(box, identity, box, identity[:2])
    with pytest.raises(ValueError, match="num_threads must be >= 0"):
        fcl_rs.collide_batch(box, identity, box, identity, num_threads=-2)


def box_mesh(half):
    """A cube of the given half-size at the origin, 12 triangles run consistently (a closed mesh)."""
    vertices = [[(2 * (i & 1) - 1) * half, (2 * (i >> 1 & 1) - 1) * half, (2 * (i >> 2 & 1) - 1) * half]
                for i in range(8)]
    triangles = [[0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5], [0, 1, 5], [0, 5, 4],
                 [2, 6, 7], [2, 7, 3], [0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6]]
    return vertices, triangles


def test_solids_count_containment_and_report_the_vertex_penetration_depth():
    big, little = fcl_rs.Solid(fcl_rs.Mesh(*box_mesh(1.0))), fcl_rs.Solid(fcl_rs.Mesh(*box_mesh(0.25)))
    pose = np.eye(4)
    pose[0, 3] = 0.6
    # The surfaces are apart: read as surfaces (FCL, fcl_rs.collide) nothing collides, read as solids one is inside.
    assert not fcl_rs.collide(little.mesh, pose, big.mesh, np.eye(4)).is_collision
    r = fcl_rs.collide_solids(little, pose, big, np.eye(4), penetration_depth=True)
    assert r["collision"] and r["contact"] == "first_inside_second"
    # The little cube's vertices at x = 0.35 are 0.65 from the face x = 1 (0.75 from the others).
    assert r["penetration_depth"] == pytest.approx(0.65, abs=1e-12)
    assert r["deepest_mesh"] == 0 and r["deepest_vertex"][0] == pytest.approx(0.35, abs=1e-12)
    assert np.linalg.norm(r["nearest_on_other"] - r["deepest_vertex"]) == pytest.approx(0.65, abs=1e-12)
    assert fcl_rs.collide_solids(big, np.eye(4), little, pose)["contact"] == "second_inside_first"
    plain = fcl_rs.collide_solids(little, pose, big, np.eye(4))
    assert plain["penetration_depth"] is None and plain["deepest_vertex"] is None
    assert not fcl_rs.collide_solids(little, pose, big, np.eye(4), containment=False)["collision"]
    pose[0, 3] = 1.0
    assert fcl_rs.collide_solids(little, pose, big, np.eye(4))["contact"] == "surfaces_intersect"
    pose[0, 3] = 5.0
    assert fcl_rs.collide_solids(little, pose, big, np.eye(4))["contact"] == "none"
    assert big.classify([0.2, 0.3, 0.1]) == "inside" and big.contains([0.2, 0.3, 0.1])
    assert big.classify([1.0, 0.3, 0.1]) == "on_surface" and big.contains([1.0, 0.3, 0.1])
    assert big.classify([3, 0, 0]) == "outside" and not big.contains([3, 0, 0])
    d, nearest = big.distance_to_surface([0.2, 0.3, 0.1])
    assert d == pytest.approx(0.7, abs=1e-12)
    np.testing.assert_allclose(nearest, [0.2, 1.0, 0.1], atol=1e-12)
