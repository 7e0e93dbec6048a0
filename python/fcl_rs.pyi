"""RS bounding-volume trees for FCL: collision and distance queries, batches on every core, robots, robots among
obstacles (environments: self and world collision, clearance, exact motion checks).

Poses are 4x4 homogeneous matrices: rigid transforms (finite, rotation orthonormal within 256 eps and proper,
last row [0, 0, 0, 1]). Batch calls take (N, 4, 4) poses or (N, dof) configurations and return numpy arrays;
num_threads=0 uses every core, 1 the calling thread only, and the results never depend on it.

Arrays may be float64, float32 or integers (widened to float64; a float32 pose is checked at float32's
tolerance, 256 float32 eps, then made exactly orthonormal in double); triangle indices must be integers. Every
argument is checked: a bad value, shape or dtype raises ValueError naming the function and the argument (for
example "fcl_rs.collide: pose_a is not a rigid transform: entry (0, 3) is nan"), a wrong Python type TypeError.
Unreadable files raise RuntimeError with the library's message.

Environment queries, motion checks and their batches run without the GIL; obstacle edits and OcTree.insert wait
for those running in other threads, so no query sees half an edit.
"""
from typing import Dict, List, Optional, Tuple, Union

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

class Plane(Geometry):
    """FCL plane {x : normal . x = offset}, normal and offset divided by the normal's length."""
    def __init__(self, normal: ArrayLike, offset: float) -> None: ...
    @property
    def normal(self) -> np.ndarray: ...
    @property
    def offset(self) -> float: ...

class Halfspace(Geometry):
    """FCL halfspace {x : normal . x <= offset}, normal and offset divided by the normal's length."""
    def __init__(self, normal: ArrayLike, offset: float) -> None: ...
    @property
    def normal(self) -> np.ndarray: ...
    @property
    def offset(self) -> float: ...

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

class Solid:
    """A closed mesh whose interior counts: containment and a vertex penetration depth (docs/solid.md)."""
    def __init__(self, mesh: Mesh) -> None:
        """Raises ValueError naming the first edge not run by exactly two triangles in opposite directions."""
    @property
    def mesh(self) -> Mesh: ...
    def classify(self, point: ArrayLike) -> str:
        """'inside', 'outside' or 'on_surface' (within rounding of the surface), mesh coordinates."""
    def contains(self, point: ArrayLike) -> bool:
        """Whether the point (mesh coordinates) is inside or on the surface."""
    def distance_to_surface(self, point: ArrayLike) -> Tuple[float, npt.NDArray[np.float64]]:
        """(distance, nearest point) from the point to the surface, mesh coordinates."""

def collide_solids(a: Solid, pose_a: ArrayLike, b: Solid, pose_b: ArrayLike, containment: bool = True,
                   penetration_depth: bool = False) -> Dict[str, object]:
    """Keys: collision, contact ('none', 'surfaces_intersect', 'first_inside_second', 'second_inside_first'),
    penetration_depth (None unless asked and colliding), deepest_mesh (0 or 1), deepest_vertex and
    nearest_on_other (world coordinates; None when no vertex is inside the other solid)."""

class Robot:
    """A URDF robot (SRDF disabled pairs and planning groups optional) with a self-collision checker."""
    def __init__(self, urdf: str, srdf: str = "", bv: str = "RS") -> None:
        """Loads the URDF and its collision meshes; bv is one of RS, OBBRSS, OBB, RSS (OBB: no minimum_distance).
        KDOP18 raises ValueError: its trees are refitted in place per check, so checks could not share them."""
    @property
    def groups(self) -> Dict[str, List[int]]:
        """The SRDF's planning groups: {name: the configuration indices the group moves, ascending} (empty
        without an SRDF; read on first use, RuntimeError naming the file and line on a bad group)."""
    @property
    def default_configuration(self) -> npt.NDArray[np.float64]:
        """MoveIt's default positions: 0 where the limits allow it, else the nearer limit."""
    def group_state(self, name: str, group: str = "") -> npt.NDArray[np.float64]:
        """The configuration of the SRDF's <group_state> name (of group, needed when several groups have a
        state of that name): default_configuration with the state's values."""
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

# (link, other, other_is_link): a link and another link (a self pair) or an obstacle, by name.
BodyPair = Tuple[str, str, bool]

class OcTree:
    """An octomap (occupancy octree) for Environment.add_octree (absent when FCL was built without octomap)."""
    def __init__(self, points: ArrayLike, resolution: float) -> None:
        """A map with cells of edge `resolution` (positive, finite) in which every (N, 3) point's cell is occupied
        (one observation each). Points beyond octomap's reach (32768 cells from the origin per axis) raise
        ValueError."""
    @staticmethod
    def from_file(path: str) -> OcTree:
        """Reads .bt (binary: occupied or free per cell) or .ot (an OcTree) files; ValueError for another
        extension, RuntimeError for an unreadable file."""
    def save(self, path: str) -> None:
        """Writes .bt (each cell occupied or free by the map's threshold) or .ot (full occupancy)."""
    def insert(self, points: ArrayLike, sensor_origin: Optional[ArrayLike] = None) -> None:
        """Adds (N, 3) points as occupied observations; with a sensor_origin (3,), as a scan from there (the cells
        along each ray observed free, the end cells occupied). Environments holding the map read its cells again
        before their next query."""
    @property
    def resolution(self) -> float: ...
    @property
    def num_occupied(self) -> int:
        """The number of occupied leaf cells (FCL's occupancy threshold)."""
    def occupied_cells(self) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """The occupied leaf cells collision and distance queries meet: centres (K, 3) and edge lengths (K,), in
        the map's frame."""

class Environment:
    """A URDF robot (SRDF disabled pairs and planning groups optional) among named obstacles in its root frame:
    self and world collision per configuration, minimum distance, and exact motion checks of straight joint-space
    segments."""
    def __init__(self, urdf: str, srdf: str = "", bv: str = "RS") -> None:
        """bv: RS, OBBRSS, OBB or RSS (OBB: no minimum distance and no motion checks); link and obstacle meshes
        are trees of this type. KDOP18 raises ValueError."""
    @property
    def groups(self) -> Dict[str, List[int]]:
        """The SRDF's planning groups: {name: the configuration indices the group moves, ascending} (empty
        without an SRDF; read on first use, RuntimeError naming the file and line on a bad group)."""
    @property
    def default_configuration(self) -> npt.NDArray[np.float64]:
        """MoveIt's default positions: 0 where the limits allow it, else the nearer limit."""
    def group_state(self, name: str, group: str = "") -> npt.NDArray[np.float64]:
        """The configuration of the SRDF's <group_state> name (of group, needed when several groups have a
        state of that name): default_configuration with the state's values."""
    @property
    def name(self) -> str: ...
    @property
    def bv(self) -> str: ...
    @property
    def dof(self) -> int: ...
    @property
    def link_names(self) -> List[str]: ...
    @property
    def joint_names(self) -> List[str]:
        """The joint of each configuration variable."""
    @property
    def lower(self) -> npt.NDArray[np.float64]:
        """Lower joint limits ([-pi, pi] for continuous joints)."""
    @property
    def upper(self) -> npt.NDArray[np.float64]: ...
    @property
    def obstacle_names(self) -> List[str]:
        """In insertion order."""
    def __contains__(self, name: str) -> bool: ...
    # Names are unique and non-empty; an unknown name raises ValueError.
    def add_shape(self, name: str, shape: Geometry, pose: ArrayLike) -> None:
        """Adds a Box, Sphere, Ellipsoid, Capsule, Cylinder, Cone, Plane or Halfspace at a 4x4 pose in the robot's
        root frame (meshes go through add_mesh, octomaps through add_octree)."""
    def add_mesh(self, name: str, vertices: ArrayLike, triangles: ArrayLike, pose: ArrayLike) -> None:
        """Adds a mesh ((V, 3) vertices, (F, 3) integer indices) at a 4x4 pose, built as a tree of the
        environment's BV type."""
    def add_octree(self, name: str, octree: OcTree, pose: ArrayLike) -> None:
        """Adds an OcTree at a 4x4 pose; the environment shares the map and follows its inserts."""
    def set_pose(self, name: str, pose: ArrayLike) -> None: ...
    def pose(self, name: str) -> npt.NDArray[np.float64]: ...
    def remove(self, name: str) -> None: ...
    def query(self, q: ArrayLike, pairs: bool = False,
              minimum_distance: bool = False) -> Dict[str, Union[bool, float, List[BodyPair], Optional[BodyPair],
                                                                 npt.NDArray[np.float64]]]:
        """Self and world collision at q (dof,): 'colliding'; with pairs=True 'pairs', every colliding BodyPair
        (self pairs first, then links in model order x obstacles in insertion order); with minimum_distance=True
        'minimum_distance' (exact; 0 when colliding, inf with nothing to measure), 'nearest_pair' (None when
        colliding) and 'nearest_points' (2, 3), link first, root frame."""
    def check_batch(self, q: ArrayLike, pairs: bool = False, minimum_distance: bool = False,
                    num_threads: int = 0) -> Dict[str, Union[npt.NDArray, List[List[BodyPair]]]]:
        """query for every row of q (N, dof): 'colliding' (N,) bool; with pairs=True 'pairs', a list of lists of
        BodyPair; with minimum_distance=True 'minimum_distance' (N,)."""
    def check_motion(self, start: ArrayLike, end: ArrayLike, earliest: bool = True,
                     tolerance: float = 1e-3) -> Dict[str, Union[bool, float, int]]:
        """Every configuration of the straight segment start -> end, exactly: 'colliding'; when colliding
        'parameter' (a colliding configuration's, in [0, 1]) and 'free_until' (everything below is free; with
        earliest=True within tolerance, in (0, 1], of 'parameter'; earliest=False stops at any colliding
        configuration); 'configurations_checked', 'distance_queries'."""
    def check_path(self, waypoints: ArrayLike, earliest: bool = True,
                   tolerance: float = 1e-3) -> Dict[str, Union[bool, float, int]]:
        """check_motion through the rows of waypoints (K, dof), K >= 1; 'parameter' and 'free_until' are a
        segment index plus the parameter within it."""
    def check_motion_batch(self, starts: ArrayLike, ends: ArrayLike, earliest: bool = True, tolerance: float = 1e-3,
                           num_threads: int = 0) -> Dict[str, npt.NDArray]:
        """check_motion for every row pair of starts and ends (N, dof): 'colliding' (N,) bool, 'parameter' (0 for a
        free segment) and 'free_until' (1 for a free segment) (N,)."""
