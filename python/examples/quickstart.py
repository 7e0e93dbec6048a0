import numpy as np

import fcl_rs

# An RS tree over a mesh from (V, 3) and (F, 3) arrays (fcl_rs.Mesh.from_file reads OBJ, STL, DAE, ...).
vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
triangles = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
tetra = fcl_rs.Mesh(vertices, triangles)
box = fcl_rs.Box(0.5, 0.5, 0.5)

# One query at 4x4 poses, with python-fcl style requests and results.
box_pose = np.eye(4)
box_pose[:3, 3] = [0.3, 0.3, 0.3]
hit = fcl_rs.collide(tetra, np.eye(4), box, box_pose, fcl_rs.CollisionRequest(num_max_contacts=10, enable_contact=True))
print("colliding:", hit.is_collision, "contacts:", len(hit.contacts))
box_pose[:3, 3] = [2.0, 0.0, 0.0]
gap = fcl_rs.distance(tetra, np.eye(4), box, box_pose, fcl_rs.DistanceRequest(enable_nearest_points=True))
print("distance:", gap.min_distance, "nearest points:", gap.nearest_points.tolist())

# A batch: (N, 4, 4) poses on every core; a bool array back.
n = 1000
tetra_poses = np.repeat(np.eye(4)[None], n, axis=0)
box_poses = tetra_poses.copy()
box_poses[:, 0, 3] = np.linspace(-2.0, 2.0, n)
colliding = fcl_rs.collide_batch(tetra, tetra_poses, box, box_poses)
print("colliding poses:", int(colliding.sum()), "of", n)
