import os
import sys

import numpy as np
import pytest

SOURCE_DIR = os.environ.get("FCL_RS_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "python", "examples"))

# A chain of six box links on revolute joints about x and y that folds onto itself (primitives only, so no
# mesh files), plus one link with a mesh from an OBJ file.
CHAIN_URDF = """<?xml version="1.0"?>
<robot name="folding_chain">
  <link name="link0"><collision><origin xyz="0 0 0.2"/><geometry><box size="0.12 0.12 0.4"/></geometry></collision></link>
{links}
  <link name="tip"><collision><origin xyz="0 0 0.1"/><geometry><mesh filename="tip.obj"/></geometry></collision></link>
  <joint name="tip_joint" type="fixed"><parent link="link5"/><child link="tip"/><origin xyz="0 0 0.42"/></joint>
</robot>
"""
LINK = """  <link name="link{i}"><collision><origin xyz="0 0 0.2"/><geometry><box size="0.12 0.12 0.4"/></geometry></collision></link>
  <joint name="joint{i}" type="revolute"><parent link="link{p}"/><child link="link{i}"/><origin xyz="0 0 0.42"/>
    <axis xyz="{axis}"/><limit lower="-2.8" upper="2.8" effort="1" velocity="1"/></joint>"""
TIP_OBJ = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


@pytest.fixture(scope="session")
def chain_urdf(tmp_path_factory):
    root = tmp_path_factory.mktemp("robot")
    links = "\n".join(LINK.format(i=i, p=i - 1, axis="1 0 0" if i % 2 else "0 1 0") for i in range(1, 6))
    (root / "chain.urdf").write_text(CHAIN_URDF.format(links=links))
    (root / "tip.obj").write_text(TIP_OBJ)
    return str(root / "chain.urdf")


@pytest.fixture
def rng(request):
    """Seeded, logged randomness (FCL_RS_TEST_SEED replays another seed)."""
    seed = int(os.environ.get("FCL_RS_TEST_SEED", "20261121"))
    print(f"[seed] {request.node.name}: FCL_RS_TEST_SEED={seed}")
    return np.random.default_rng(seed)


def random_poses(rng, n, extent):
    """(n, 4, 4) rigid transforms: uniform rotations (normalised Gaussian quaternions), uniform translations."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    poses = np.zeros((n, 4, 4))
    poses[:, 0, :3] = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=1)
    poses[:, 1, :3] = np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=1)
    poses[:, 2, :3] = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)
    poses[:, :3, 3] = rng.uniform(-extent, extent, size=(n, 3))
    poses[:, 3, 3] = 1
    return poses


def torus(big=0.6, small=0.2, rings=16, sides=8):
    """A torus about z: (vertices, triangles) arrays."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, rings, endpoint=False),
                       np.linspace(0, 2 * np.pi, sides, endpoint=False), indexing="ij")
    vertices = np.stack([(big + small * np.cos(v)) * np.cos(u), (big + small * np.cos(v)) * np.sin(u),
                         small * np.sin(v)], axis=-1).reshape(-1, 3)
    triangles = []
    for i in range(rings):
        for j in range(sides):
            a, b = i * sides + j, ((i + 1) % rings) * sides + j
            c, d = ((i + 1) % rings) * sides + (j + 1) % sides, i * sides + (j + 1) % sides
            triangles += [[a, b, c], [a, c, d]]
    return vertices, np.array(triangles)
