"""fcl_rs.Environment: queries against brute force over link x obstacle pairs (the chain's links posed by forward
kinematics written here in numpy, each pair through fcl_rs.collide / fcl_rs.distance), octree obstacles against one
box per occupied cell, sensor updates, motion checks against dense sampling, batches against single calls, edits
from one thread while another runs batches."""
import os
import runpy
import sys
import threading
import time

import numpy as np
import pytest

import fcl_rs
from conftest import SOURCE_DIR, TIP_OBJ, torus

SHARED_DATA = os.environ.get("FCL_RS_SHARED_DATA_DIR") or os.path.join(SOURCE_DIR, "..", "shared", "data")

needs_octomap = pytest.mark.skipif(not hasattr(fcl_rs, "OcTree"), reason="FCL built without octomap")


def at(x, y, z, axis=None, angle=0.0):
    """A pose: translation (x, y, z), rotated by angle about axis."""
    pose = np.eye(4)
    if axis is not None:
        pose[:3, :3] = rotation(np.asarray(axis, dtype=float), angle)
    pose[:3, 3] = (x, y, z)
    return pose


def rotation(axis, angle):
    k = axis / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


# The chain of conftest.CHAIN_URDF: link0 fixed, link i on a joint 0.42 above link i-1 about x (odd i) or y (even
# i), each a 0.12 x 0.12 x 0.4 box 0.2 above its joint; the tip mesh 0.42 above link5, 0.1 above its origin.
LINK_BOX = fcl_rs.Box(0.12, 0.12, 0.4)
TIP_VERTICES = np.array([[float(x) for x in line.split()[1:]] for line in TIP_OBJ.splitlines() if line[0] == "v"])
TIP_TRIANGLES = np.array([[int(i) - 1 for i in line.split()[1:]] for line in TIP_OBJ.splitlines() if line[0] == "f"])
TIP = fcl_rs.Mesh(TIP_VERTICES, TIP_TRIANGLES)
LINKS = [f"link{i}" for i in range(6)] + ["tip"]


def link_geometry(q):
    """(geometry, pose) of every link in model order at configuration q."""
    frame = np.eye(4)
    out = [(LINK_BOX, frame @ at(0, 0, 0.2))]
    for i in range(1, 6):
        frame = frame @ at(0, 0, 0.42, [1, 0, 0] if i % 2 else [0, 1, 0], q[i - 1])
        out.append((LINK_BOX, frame @ at(0, 0, 0.2)))
    frame = frame @ at(0, 0, 0.42)
    out.append((TIP, frame @ at(0, 0, 0.1)))
    return out


# Every shape add_shape takes, and a mesh, around the chain's reach (about 2.5 from its base).
SHAPES = [("wall", fcl_rs.Box(0.05, 1.2, 0.8), at(0.7, 0.2, 1.2)),
          ("ball", fcl_rs.Sphere(0.15), at(-0.5, 0.5, 1.5)),
          ("post", fcl_rs.Cylinder(0.05, 1.0), at(0.0, -0.8, 1.0, [1, 0, 0], 0.4)),
          ("pill", fcl_rs.Capsule(0.06, 0.5), at(-0.9, -0.3, 0.8, [0, 1, 0], 1.0)),
          ("cone", fcl_rs.Cone(0.2, 0.4), at(0.3, 1.0, 0.6)),
          ("egg", fcl_rs.Ellipsoid(0.2, 0.1, 0.15), at(0.0, 0.4, 2.4))]
RING = torus(0.25, 0.06, 12, 6)
RING_POSE = at(-0.4, -0.6, 1.9, [1, 1, 0], 0.7)


def furnish(env):
    for name, shape, pose in SHAPES:
        env.add_shape(name, shape, pose)
    env.add_mesh("ring", *RING, RING_POSE)


def obstacle_geometry():
    return [(name, shape, pose) for name, shape, pose in SHAPES] + [("ring", fcl_rs.Mesh(*RING), RING_POSE)]


# FCL measures shapes (and mesh triangles against shapes) with libccd's iterative GJK, whose answer moves when the
# poses move by rounding (the environment's forward kinematics against this file's): for the curved shapes by up
# to about 1e-4 (7e-5 seen, a box against the cylinder; 2e-6 against the capsule), by about 1e-9 for the others.
CURVED = {"ball", "post", "pill", "cone", "egg"}


def brute_force(robot, obstacles, q, distances=True):
    """Every colliding pair (self pairs from Robot.check, then link x obstacle with fcl_rs.collide) and, sorted,
    every distance with its pair (the self pairs' smallest from Robot.minimum_distance, pair None)."""
    pairs = [(LINKS[a], LINKS[b], True) for a, b in robot.check(q)]
    measured = [(robot.minimum_distance(q), None)] if distances else []
    for link, (geometry, pose) in zip(LINKS, link_geometry(q)):
        for name, obstacle, obstacle_pose in obstacles:
            if fcl_rs.collide(geometry, pose, obstacle, obstacle_pose).is_collision:
                pairs.append((link, name, False))
            elif distances:
                measured.append((fcl_rs.distance(geometry, pose, obstacle, obstacle_pose).min_distance,
                                 (link, name, False)))
    return pairs, sorted(measured, key=lambda m: m[0])


@pytest.fixture
def environment(chain_urdf):
    env = fcl_rs.Environment(chain_urdf)
    furnish(env)
    return env


def configurations(env, rng, n):
    return rng.uniform(env.lower, env.upper, (n, env.dof))


def test_names_limits_and_edits(environment, chain_urdf):
    env = environment
    assert (env.name, env.bv, env.dof) == ("folding_chain", "RS", 5)
    assert env.link_names == LINKS and env.joint_names == [f"joint{i}" for i in range(1, 6)]
    assert np.array_equal(env.lower, [-2.8] * 5) and np.array_equal(env.upper, [2.8] * 5)
    assert env.obstacle_names == [name for name, _, _ in SHAPES] + ["ring"]
    assert "ring" in env and "nothing" not in env
    assert np.array_equal(env.pose("wall"), SHAPES[0][2])
    straight = np.zeros(env.dof)
    assert not env.query(straight)["colliding"]
    # The wall moved onto the upright chain collides with the links it crosses, by name; removed, nothing does.
    env.set_pose("wall", at(0.0, 0.0, 1.2))
    assert np.array_equal(env.pose("wall"), at(0.0, 0.0, 1.2))
    hit = env.query(straight, pairs=True)
    # The wall spans z 0.8 to 1.6: link1 (0.42 to 0.82), link2 (0.84 to 1.24) and link3 (1.26 to 1.66).
    assert hit["colliding"] and hit["pairs"] == [(f"link{i}", "wall", False) for i in (1, 2, 3)]
    env.remove("wall")
    assert "wall" not in env and not env.query(straight)["colliding"]
    assert fcl_rs.Environment(chain_urdf, bv="OBB").bv == "OBB"


@pytest.mark.parametrize("bv", ["RS", "OBBRSS", "RSS", "OBB"])
def test_queries_equal_brute_force(chain_urdf, rng, bv):
    env = fcl_rs.Environment(chain_urdf, bv=bv)
    furnish(env)
    robot = fcl_rs.Robot(chain_urdf)
    obstacles = obstacle_geometry()
    q = configurations(env, rng, 60)
    distances = bv != "OBB"
    world_hits = free = 0
    for row in q:
        pairs, measured = brute_force(robot, obstacles, row, distances)
        result = env.query(row, pairs=True, minimum_distance=distances)
        assert result["pairs"] == pairs, row
        assert result["colliding"] == bool(pairs)
        world_hits += any(not is_link for _, _, is_link in pairs)
        if not distances:
            continue
        if pairs:
            assert result["minimum_distance"] == 0 and result["nearest_pair"] is None
            continue
        free += 1
        (best, best_pair), (second, _) = measured[0], measured[1]
        curved = best_pair is not None and best_pair[1] in CURVED
        tolerance = 1e-4 if curved else 1e-7
        assert abs(result["minimum_distance"] - best) <= tolerance, (row, measured[:2], result)
        if second - best > 2 * tolerance:
            # The nearest pair by name (a self pair: the robot's own; its names are SelfCollision's).
            assert result["nearest_pair"] == best_pair if best_pair else result["nearest_pair"][2]
        points = result["nearest_points"]
        assert points.shape == (2, 3)
        if bv == "RS" and not curved:
            # Exact nearest points (FCL's OBBRSS mesh points were seen not to be the distance apart).
            assert np.linalg.norm(points[0] - points[1]) == pytest.approx(best, rel=1e-6, abs=1e-9)
    # The scene is neither empty nor full.
    assert 3 <= world_hits <= 57
    assert not distances or free >= 5


def test_batches_equal_single_calls(environment, rng):
    env = environment
    q = configurations(env, rng, 30)
    single = [env.query(row, pairs=True, minimum_distance=True) for row in q]
    for threads in (1, 2, 0):
        batch = env.check_batch(q, pairs=True, minimum_distance=True, num_threads=threads)
        assert batch["colliding"].dtype == np.bool_
        assert np.array_equal(batch["colliding"], [r["colliding"] for r in single])
        assert batch["pairs"] == [r["pairs"] for r in single]
        assert np.array_equal(batch["minimum_distance"], [r["minimum_distance"] for r in single])
    flags = env.check_batch(q)
    assert set(flags) == {"colliding"} and not flags["colliding"].flags.owndata
    assert env.check_batch(np.zeros((0, env.dof)))["colliding"].shape == (0,)
    # float32 rows are widened, as everywhere in the module.
    assert np.array_equal(env.check_batch(q.astype(np.float32))["colliding"],
                          env.check_batch(q.astype(np.float32).astype(np.float64))["colliding"])


def segments(env, rng, n, step):
    """n segments from collision-free starts, every joint moving within +-step."""
    starts = []
    while len(starts) < n:
        q = rng.uniform(env.lower, env.upper)
        if not env.query(q)["colliding"]:
            starts.append(q)
    starts = np.array(starts)
    return starts, np.clip(starts + rng.uniform(-step, step, starts.shape), env.lower, env.upper)


def test_motion_checks_agree_with_dense_sampling(environment, rng):
    env = environment
    starts, ends = segments(env, rng, 12, 1.0)
    t = np.linspace(0, 1, 201)
    colliding = 0
    for start, end in zip(starts, ends):
        samples = env.check_batch(start + t[:, None] * (end - start))["colliding"]
        motion = env.check_motion(start, end)
        assert motion["configurations_checked"] > 0
        if not motion["colliding"]:
            assert not samples.any() and motion["free_until"] == 1
            continue
        colliding += 1
        assert env.query(start + motion["parameter"] * (end - start))["colliding"]
        assert 0 <= motion["parameter"] - motion["free_until"] <= 1e-3
        if samples.any():
            assert motion["free_until"] <= t[np.argmax(samples)] + 1e-12
        # Any colliding configuration: still one that collides, and never free where a sample collides.
        anywhere = env.check_motion(start, end, earliest=False, tolerance=0.01)
        assert anywhere["colliding"]
        assert env.query(start + anywhere["parameter"] * (end - start))["colliding"]
    assert 2 <= colliding <= 10


def test_paths_and_motion_batches_equal_single_calls(environment, rng):
    env = environment
    starts, ends = segments(env, rng, 12, 1.2)
    for earliest in (True, False):
        single = [env.check_motion(a, b, earliest=earliest) for a, b in zip(starts, ends)]
        assert 1 <= sum(s["colliding"] for s in single) <= 11
        for threads in (1, 2):
            batch = env.check_motion_batch(starts, ends, earliest=earliest, num_threads=threads)
            assert np.array_equal(batch["colliding"], [s["colliding"] for s in single])
            assert np.array_equal(batch["parameter"], [s["parameter"] for s in single])
            assert np.array_equal(batch["free_until"], [s["free_until"] for s in single])
    # A path through three waypoints: segment by segment, the first colliding one answers.
    for a, b, c in zip(starts[:-1], ends[:-1], ends[1:]):
        path = env.check_path(np.stack([a, b, c]))
        first, second = env.check_motion(a, b), env.check_motion(b, c)
        if first["colliding"]:
            assert path["colliding"] and path["parameter"] == first["parameter"]
        elif second["colliding"]:
            assert path["colliding"] and path["parameter"] == 1 + second["parameter"]
            assert path["free_until"] == 1 + second["free_until"]
        else:
            assert not path["colliding"] and path["free_until"] == 2
    assert not env.check_path(starts[:1])["colliding"]


def sphere_points(rng, n, centre, radius):
    p = rng.normal(size=(n, 3))
    return radius * p / np.linalg.norm(p, axis=1, keepdims=True) + centre


@needs_octomap
@pytest.mark.parametrize("bv", ["RS", "OBBRSS"])
def test_octree_equals_one_box_per_cell(chain_urdf, rng, bv):
    """The environment with a scanned ball as an octree answers as the environment with one box obstacle per
    occupied cell (named 'cell i'; the octree's pairs name the map once per link)."""
    octree = fcl_rs.OcTree(sphere_points(rng, 600, [0, 0, 0], 0.4), resolution=0.08)
    centres, sizes = octree.occupied_cells()
    assert centres.shape == (octree.num_occupied, 3) and np.all(sizes == 0.08) and 50 < len(sizes) < 600
    pose = at(0.3, 0.2, 1.0, [0, 0, 1], 0.5)
    env, reference = fcl_rs.Environment(chain_urdf, bv=bv), fcl_rs.Environment(chain_urdf, bv=bv)
    env.add_octree("scan", octree, pose)
    for i, (centre, size) in enumerate(zip(centres, sizes)):
        reference.add_shape(f"cell {i}", fcl_rs.Box(size, size, size), pose @ at(*centre))
    hits = 0
    for q in configurations(env, rng, 60):
        got = env.query(q, pairs=True, minimum_distance=True)
        want = reference.query(q, pairs=True, minimum_distance=True)
        assert got["colliding"] == want["colliding"]
        links_hit = []
        for link, other, is_link in want["pairs"]:
            if is_link:
                assert (link, other, True) in got["pairs"]
            elif (link, "scan", False) not in links_hit:
                links_hit.append((link, "scan", False))
        assert [p for p in got["pairs"] if not p[2]] == links_hit
        hits += bool(links_hit)
        assert got["minimum_distance"] == pytest.approx(want["minimum_distance"], rel=1e-9, abs=1e-12)
        if want["nearest_pair"] is not None and not want["nearest_pair"][2]:
            assert got["nearest_pair"] == (want["nearest_pair"][0], "scan", False)
    assert 5 <= hits <= 55


@needs_octomap
def test_sensor_updates_reach_the_environment(chain_urdf, rng, tmp_path):
    """OcTree.insert adds occupied cells and, from a sensor origin, clears the cells its rays cross; every
    environment holding the map answers for the map as it is now (no refresh call)."""
    octree = fcl_rs.OcTree(sphere_points(rng, 100, [1.5, 1.5, 0.5], 0.1), resolution=0.04)
    first, second = fcl_rs.Environment(chain_urdf), fcl_rs.Environment(chain_urdf)
    first.add_octree("scan", octree, np.eye(4))
    second.add_octree("scan", octree, at(0, 0, 0.5))
    upright = np.zeros(first.dof)
    assert not first.query(upright)["colliding"] and not second.query(upright)["colliding"]
    before = octree.num_occupied
    # A point on link2 (z from 0.84 to 1.24 when upright): occupied after one observation.
    octree.insert(np.array([[0.0, 0.0, 1.0]]))
    assert octree.num_occupied == before + 1
    assert first.query(upright, pairs=True)["pairs"] == [("link2", "scan", False)]
    # The second environment holds the map 0.5 higher: the cell (z 1.5) sits on link3 there (z 1.26 to 1.66).
    assert second.query(upright, pairs=True)["pairs"] == [("link3", "scan", False)]
    assert first.check_batch(upright[None])["colliding"][0]
    # Scans from x = 1 through the cell to x = -1: the ray's free observations outweigh the one occupied one
    # after a few scans (octomap's log-odds: +0.85 per hit, -0.4 per miss), and the end cell is occupied.
    for scan in range(3):
        octree.insert(np.array([[-1.0, 0.0, 1.0]]), sensor_origin=[1.0, 0.0, 1.0])
    assert not first.query(upright)["colliding"]
    centres, _ = octree.occupied_cells()
    assert np.any(np.all(np.abs(centres - [-1.0, 0.0, 1.0]) < 0.04, axis=1))
    assert not np.any(np.all(np.abs(centres - [0.0, 0.0, 1.0]) < 0.02, axis=1))
    # Moved and removed like any obstacle.
    first.set_pose("scan", at(1.0, 0.0, 0.0))  # the end cell (-1, 0, 1) onto link2
    assert first.query(upright, pairs=True)["pairs"] == [("link2", "scan", False)]
    first.remove("scan")
    assert not first.query(upright)["colliding"] and second.obstacle_names == ["scan"]
    # Files: .bt keeps each cell occupied or free, .ot the full occupancy; both answer as the map.
    q = configurations(second, rng, 30)
    reference = second.check_batch(q, minimum_distance=True)
    for name in ("map.bt", "map.ot"):
        octree.save(str(tmp_path / name))
        loaded = fcl_rs.OcTree.from_file(str(tmp_path / name))
        assert loaded.resolution == octree.resolution
        assert np.array_equal(loaded.occupied_cells()[0], octree.occupied_cells()[0])
        env = fcl_rs.Environment(chain_urdf)
        env.add_octree("scan", loaded, at(0, 0, 0.5))
        answers = env.check_batch(q, minimum_distance=True)
        assert np.array_equal(answers["colliding"], reference["colliding"])
        assert np.array_equal(answers["minimum_distance"], reference["minimum_distance"])
    # A map without occupied cells collides with nothing.
    empty = fcl_rs.OcTree(np.zeros((0, 3)), 0.1)
    assert empty.num_occupied == 0
    first.add_octree("empty", empty, np.eye(4))
    assert first.query(upright, minimum_distance=True)["minimum_distance"] == \
        fcl_rs.Robot(chain_urdf).minimum_distance(upright)


@needs_octomap
def test_motion_check_meets_the_octree(chain_urdf, rng):
    env = fcl_rs.Environment(chain_urdf)
    env.add_octree("scan", fcl_rs.OcTree(sphere_points(rng, 200, [0.5, 0.0, 1.4], 0.15), 0.04), np.eye(4))
    start, end = np.zeros(env.dof), np.array([0.0, 1.2, 0.0, 0.0, 0.0])  # link2 and up swing towards +x
    motion = env.check_motion(start, end)
    assert motion["colliding"]
    t = np.linspace(0, 1, 201)
    samples = env.check_batch(start + t[:, None] * (end - start))["colliding"]
    assert samples.any() and motion["free_until"] <= t[np.argmax(samples)] + 1e-12
    assert env.query(start + motion["parameter"] * (end - start), pairs=True)["pairs"][0][1] == "scan"
    assert not env.check_motion(start, -end)["colliding"]


def test_edits_wait_for_batches_in_other_threads(environment, rng):
    """Batches run without the GIL; obstacles added and removed meanwhile from another thread never tear one:
    each answer is the world's before or after an edit."""
    env = environment
    q = configurations(env, rng, 60)
    q[0] = 0  # upright: link3 crosses the slab
    without = env.check_batch(q)["colliding"]
    env.add_shape("slab", fcl_rs.Box(3, 3, 0.1), at(0, 0, 1.5))
    with_slab = env.check_batch(q)["colliding"]
    env.remove("slab")
    assert not np.array_equal(without, with_slab)
    answers, stop = [], threading.Event()

    def check():
        while True:
            answers.append(env.check_batch(q, num_threads=2)["colliding"])
            if stop.is_set():
                return

    worker = threading.Thread(target=check)
    worker.start()
    for _ in range(30):
        env.add_shape("slab", fcl_rs.Box(3, 3, 0.1), at(0, 0, 1.5))
        time.sleep(0.0005)  # lets the worker start batches between edits
        env.remove("slab")
        time.sleep(0.0005)
    stop.set()
    worker.join()
    assert answers and all(np.array_equal(a, without) or np.array_equal(a, with_slab) for a in answers)


def test_example_runs_and_readme_quotes_it(capsys, monkeypatch):
    """python/examples/environment.py with the Panda from ../shared/data (a skip without the data, a failure
    under CI=true), and README.md quoting it whole."""
    panda = os.path.join(SHARED_DATA, "robots", "panda")
    if not os.path.isdir(panda):
        message = f"shared data {panda} is missing"
        if os.environ.get("CI", "") not in ("", "0", "false"):
            pytest.fail(message + "; CI=true requires it")
        pytest.skip(message)
    path = os.path.join(SOURCE_DIR, "python", "examples", "environment.py")
    monkeypatch.setattr(sys, "argv", [path, os.path.join(panda, "panda.urdf"), os.path.join(panda, "panda.srdf")])
    runpy.run_path(path, run_name="__main__")
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("ready: False clearance: ") and lines[0].endswith("('panda_hand', 'scan', False)")
    assert 0.01 < float(lines[0].split()[3]) < 0.03  # README: "about 2 cm"
    assert lines[1].startswith("colliding configurations: ") and lines[1].endswith(" of 1000")
    assert 0 < int(lines[1].split()[2]) < 1000
    assert lines[2].startswith("motion: True free until: ") and 0.03 < float(lines[2].split()[-1]) < 0.08
    assert lines[3] == "after the scan: [('panda_hand', 'scan', False)]"
    with open(path) as f, open(os.path.join(SOURCE_DIR, "README.md")) as readme:
        assert f.read() in readme.read(), "README's environment example differs from python/examples/environment.py"


def test_planes_and_halfspaces_are_obstacles(chain_urdf):
    """add_shape takes what Environment::addShape takes, planes and halfspaces included (normal and offset divided
    by the normal's length, as FCL's constructors do): the upright chain (base link z in [0, 0.4], tip near 2.6)
    is 0.01 above a halfspace below z = -0.01, and crosses a plane at z = 1 and a halfspace below z = 0.2."""
    env = fcl_rs.Environment(chain_urdf)
    straight = np.zeros(env.dof)
    floor = fcl_rs.Halfspace([0, 0, 2], -0.02)
    assert np.allclose(floor.normal, [0, 0, 1]) and floor.offset == -0.01
    env.add_shape("floor", floor, np.eye(4))
    result = env.query(straight, pairs=True, minimum_distance=True)
    assert not result["colliding"]
    assert abs(result["minimum_distance"] - 0.01) < 1e-9 and result["nearest_pair"] == ("link0", "floor", False)
    env.add_shape("ceiling", fcl_rs.Plane([0, 0, 1], 1), np.eye(4))
    env.add_shape("ground", fcl_rs.Halfspace([0, 0, 1], 0.2), np.eye(4))
    hit = env.query(straight, pairs=True)
    obstacles = {pair[1] for pair in hit["pairs"]}
    assert hit["colliding"] and {"ceiling", "ground"} <= obstacles and "floor" not in obstacles
