"""fcl_rs.Environment: world queries against single-geometry queries, motion checks against dense sampling,
batches against single calls, errors."""
import numpy as np
import pytest

import fcl_rs


def at(x, y, z):
    pose = np.eye(4)
    pose[:3, 3] = (x, y, z)
    return pose


@pytest.fixture
def environment(chain_urdf):
    env = fcl_rs.Environment(chain_urdf)
    env.add_shape("wall", fcl_rs.Box(0.05, 2.0, 2.0), at(0.7, 0, 1.0))
    vertices = np.array([[0, 0, 0], [0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]], dtype=float)
    triangles = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    env.add_mesh("tetra", vertices, triangles, at(-0.6, 0.0, 1.2))
    return env


def test_queries_name_pairs_and_measure(environment):
    env = environment
    assert env.obstacle_names == ["wall", "tetra"]
    straight = np.zeros(env.dof)
    assert not env.query(straight)["colliding"]
    result = env.query(straight, pairs=True, minimum_distance=True)
    assert result["pairs"] == []
    assert result["minimum_distance"] > 0
    points = result["nearest_points"]
    assert np.linalg.norm(points[0] - points[1]) == pytest.approx(result["minimum_distance"], abs=1e-9)
    # Moving the wall onto the chain makes the chain's links collide with it, by name.
    env.set_pose("wall", at(0.0, 0, 1.0))
    hit = env.query(straight, pairs=True)
    assert hit["colliding"]
    assert all(other == "wall" and not is_link for _, other, is_link in hit["pairs"])
    env.remove("wall")
    assert not env.query(straight)["colliding"]


def test_motion_checks_agree_with_dense_sampling(environment, rng):
    env = environment
    lower, upper = env.lower, env.upper
    colliding = 0
    for _ in range(12):
        start = rng.uniform(lower, upper)
        if env.query(start)["colliding"]:
            continue
        end = np.clip(start + rng.uniform(-0.8, 0.8, env.dof), lower, upper)
        motion = env.check_motion(start, end)
        samples = [env.query(start + t * (end - start))["colliding"] for t in np.linspace(0, 1, 201)]
        if not motion["colliding"]:
            assert not any(samples)
            continue
        colliding += 1
        assert env.query(start + motion["parameter"] * (end - start))["colliding"]
        assert motion["parameter"] - motion["free_until"] <= 1e-3
        if any(samples):
            assert motion["free_until"] <= np.argmax(samples) / 200 + 1e-9
    assert colliding > 0


def test_batches_equal_single_calls(environment, rng):
    env = environment
    q = rng.uniform(env.lower, env.upper, (10, env.dof))
    ends = rng.uniform(env.lower, env.upper, (10, env.dof))
    batch = env.check_batch(q, minimum_distance=True, num_threads=2)
    motions = env.check_motion_batch(q, ends, num_threads=2)
    for i in range(len(q)):
        single = env.query(q[i], minimum_distance=True)
        assert batch["colliding"][i] == single["colliding"]
        assert batch["minimum_distance"][i] == single["minimum_distance"]
        motion = env.check_motion(q[i], ends[i], earliest=False)
        assert motions["colliding"][i] == motion["colliding"]
        assert motions["parameter"][i] == motion["parameter"]
    path = env.check_path(np.stack([q[0], ends[0]]), earliest=False)
    assert path["colliding"] == motions["colliding"][0]


def test_environment_errors(chain_urdf):
    env = fcl_rs.Environment(chain_urdf)
    with pytest.raises(ValueError, match="KDOP18"):
        fcl_rs.Environment(chain_urdf, bv="KDOP18")
    with pytest.raises(ValueError, match="'m'"):
        env.add_shape("m", fcl_rs.Mesh(np.eye(3), np.array([[0, 1, 2]])), at(0, 0, 0))
    env.add_shape("box", fcl_rs.Box(0.1, 0.1, 0.1), at(2, 0, 0))
    with pytest.raises(ValueError, match="exists"):
        env.add_shape("box", fcl_rs.Box(0.1, 0.1, 0.1), at(2, 0, 0))
    with pytest.raises(ValueError, match="'nothing'"):
        env.remove("nothing")
    with pytest.raises(ValueError, match="values"):
        env.query(np.zeros(env.dof + 1))
    with pytest.raises(ValueError, match="columns"):
        env.check_motion_batch(np.zeros((2, env.dof)), np.zeros((2, env.dof + 1)))
    with pytest.raises(ValueError, match="OBB"):
        fcl_rs.Environment(chain_urdf, bv="OBB").check_motion(np.zeros(env.dof), np.zeros(env.dof))
