import sys

import numpy as np

import fcl_rs


def at(x, y, z):
    pose = np.eye(4)
    pose[:3, 3] = (x, y, z)
    return pose


# A robot from URDF (SRDF: the pairs it never checks) among named obstacles in its root frame.
env = fcl_rs.Environment(sys.argv[1], sys.argv[2])
env.add_shape("table", fcl_rs.Box(0.8, 1.2, 0.04), at(0.6, 0.0, 0.2))
env.add_shape("post", fcl_rs.Cylinder(0.03, 0.8), at(0.35, -0.35, 0.6))
# A depth sensor's points as an octomap (2 cm cells).
rng = np.random.default_rng(1)
ball = rng.normal(size=(500, 3))
ball = 0.05 * ball / np.linalg.norm(ball, axis=1, keepdims=True) + [0.26, 0.17, 0.5]
scan = fcl_rs.OcTree(ball, resolution=0.02)
env.add_octree("scan", scan, np.eye(4))
# One check per configuration: self and world together, the colliding pairs by name, the clearance.
ready = np.array([0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785, 0.0, 0.0][: env.dof])
result = env.query(ready, pairs=True, minimum_distance=True)
print("ready:", result["colliding"], "clearance:", round(result["minimum_distance"], 4), result["nearest_pair"])

# Many configurations on every core: a bool array back.
q = rng.uniform(env.lower, env.upper, (1000, env.dof))
print("colliding configurations:", int(env.check_batch(q)["colliding"].sum()), "of", len(q))

# A straight joint-space motion, exactly (no sampling resolution): the first colliding configuration's parameter.
reach = ready.copy()
reach[0] = 1.2
motion = env.check_motion(ready, reach)
print("motion:", motion["colliding"], "free until:", round(motion["free_until"], 3))

# A new scan from a sensor above the table: the cells along the rays observed free, the end cells occupied. The
# environment reads the map again before its next query.
cloud = np.column_stack([rng.uniform(0.25, 0.35, 200), rng.uniform(-0.05, 0.05, 200), np.full(200, 0.55)])
scan.insert(cloud, sensor_origin=[0.3, 0.0, 1.2])
print("after the scan:", env.query(ready, pairs=True)["pairs"])
