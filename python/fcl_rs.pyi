"""RS bounding-volume trees for FCL: collision and distance queries, batches on every core, robots.

Poses are 4x4 homogeneous matrices: rigid transforms (finite, rotation orthonormal within 256 eps and proper,
last row [0, 0, 0, 1]). Batch calls take (N, 4, 4) poses or (N, dof) configurations and return numpy arrays;
num_threads=0 uses every core, 1 the calling thread only, and the results never depend on it.

Arrays may be float64, float32 or integers (widened to float64; a float32 pose is checked at float32's
tolerance, 256 float32 eps, then made exactly orthonormal in double); triangle indices must be integers. Every
argument is checked: a bad value, shape or dtype raises ValueError naming the function and the argument (for
example "fcl_rs.collide: pose_a is not a rigid transform: entry (0, 3) is nan"), a wrong Python type TypeError.
Unreadable files raise RuntimeError with the library's message.
"""
from typing import Dict, List, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike

class Geometry:
    """Any collision geometry: an RS mesh or an FCL shape."""

class Mesh(Geometry):
    """A triangle mesh with an RS bounding-volume tree (surface-area splits)."""
    def __init__(self, vertices: ArrayLike, triangles: ArrayLike) -> None:
        """Builds the tree over (V, 3) finite vertices and (F, 3) integer vertex indices in [0, V)."""
    @staticmethod
    def from_file(path: str) -> Mesh:
        """Loads every mesh of a file assimp reads (OBJ, STL, PLY, DAE, ...) into one tree."""
    @property
    def num_vertices(self) -> int: ...
    @property
    def num_triangles(self) -> int: ...

# Every size is positive and finite (ValueError otherwise).
class Box(Geometry):
    def __init__(self, x: float, y: float, z: float) -> None: ...

class Sphere(Geometry):
    def __init__(self, radius: float) -> None: ...

class Ellipsoid(Geometry):
    def __init__(self, a: float, b: float, c: float) -> None: ...

class Capsule(Geometry):
    def __init__(self, radius: float, length: float) -> None: ...

class Cylinder(Geometry):
    def __init__(self, radius: float, length: float) -> None: ...

class Cone(Geometry):
    def __init__(self, radius: float, length: float) -> None: ...

class Contact:
    """One contact, as in python-fcl."""
    b1: int
    b2: int
    penetration_depth: float
    @property
    def pos(self) -> npt.NDArray[np.float64]: ...
    @property
    def normal(self) -> npt.NDArray[np.float64]: ...

class CollisionRequest:
    num_max_contacts: int  # at least 1
    enable_contact: bool
    def __init__(self, num_max_contacts: int = 1, enable_contact: bool = False) -> None: ...

class CollisionResult:
    @property
    def is_collision(self) -> bool: ...
    @property
    def contacts(self) -> List[Contact]: ...

class DistanceRequest:
    enable_nearest_points: bool
    enable_signed_distance: bool
    rel_err: float  # non-negative and finite, as abs_err
    abs_err: float
    def __init__(self, enable_nearest_points: bool = False, enable_signed_distance: bool = False,
                 rel_err: float = 0.0, abs_err: float = 0.0) -> None: ...

class DistanceResult:
    min_distance: float
    b1: int
    b2: int
    @property
    def nearest_points(self) -> npt.NDArray[np.float64]:
        """(2, 3) world-frame points, with DistanceRequest(enable_nearest_points=True)."""

def collide(a: Geometry, pose_a: ArrayLike, b: Geometry, pose_b: ArrayLike,
            request: CollisionRequest = ...) -> CollisionResult:
    """fcl_rs::collide of two geometries at 4x4 poses."""

def distance(a: Geometry, pose_a: ArrayLike, b: Geometry, pose_b: ArrayLike,
             request: DistanceRequest = ...) -> DistanceResult:
    """fcl_rs::distance of two geometries at 4x4 poses (0 when colliding)."""

def collide_batch(a: Geometry, poses_a: ArrayLike, b: Geometry, poses_b: ArrayLike,
                  num_threads: int = 0) -> npt.NDArray[np.bool_]:
    """Whether a at poses_a[i] and b at poses_b[i] collide, for (N, 4, 4) pose arrays."""

def distance_batch(a: Geometry, poses_a: ArrayLike, b: Geometry, poses_b: ArrayLike,
                   num_threads: int = 0) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Distances (N,) and world-frame nearest points (N, 2, 3)."""

class Robot:
    """A URDF robot (SRDF disabled pairs optional) with a self-collision checker."""
    def __init__(self, urdf: str, srdf: str = "", bv: str = "RS") -> None:
        """Loads the URDF and its collision meshes; bv is one of RS, OBBRSS, OBB, RSS (OBB: no minimum_distance).
        KDOP18 raises ValueError: its trees are refitted in place per check, so checks could not share them."""
    @property
    def name(self) -> str: ...
    @property
    def link_names(self) -> List[str]: ...
    @property
    def joint_names(self) -> List[str]:
        """The joint of each configuration variable."""
    @property
    def dof(self) -> int: ...
    @property
    def lower(self) -> npt.NDArray[np.float64]:
        """Lower joint limits ([-pi, pi] for continuous joints)."""
    @property
    def upper(self) -> npt.NDArray[np.float64]: ...
    @property
    def pairs(self) -> List[Tuple[int, int]]:
        """The link index pairs every check tests."""
    def random_configurations(self, n: int, seed: int) -> npt.NDArray[np.float64]:
        """(n, dof) configurations uniform within the limits, from a seed (n >= 0)."""
    def check(self, q: ArrayLike) -> List[Tuple[int, int]]:
        """The colliding link index pairs at configuration q (dof,), finite."""
    def minimum_distance(self, q: ArrayLike) -> float:
        """The smallest distance between two checked links at q (0 when colliding)."""
    def check_batch(self, q: ArrayLike, pairs: bool = False, minimum_distance: bool = False,
                    num_threads: int = 0) -> Dict[str, Union[npt.NDArray, List[npt.NDArray]]]:
        """Self-collision of every row of q (N, dof): 'colliding' (N,) bool; with pairs=True 'pairs', a list of
        (k, 2) link index arrays; with minimum_distance=True 'minimum_distance' (N,)."""
