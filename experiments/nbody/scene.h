// Scene files of the n-body experiment (paper section 5): bodies, cube, time step, seed and motion effects.
#ifndef FCL_RS_SCENE_H
#define FCL_RS_SCENE_H

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace fcl_rs {

/// One kind of body in a scene: a mesh file or a generated shape, how many copies, and how big.
/// Every body is centred on its bounding-box centre, which is also the point it spins about.
struct SceneBody
{
  std::string name;       ///< label; defaults to the mesh file's stem or the shape's name
  std::string mesh;       ///< mesh file as the scene writes it (relative to the data directory, or absolute)
  std::string mesh_path;  ///< the file to read (loadScene resolves it against the data directory)
  /// Generated shape when mesh is empty: "sphere" (the paper's 467-vertex / 992-face sphere),
  /// "ellipsoid", "diamond" or "kdop18" (see fcl_rs/mesh/shapes.h).
  std::string shape;
  std::array<double, 3> axes{{1, 1, 1}};     ///< ellipsoid: semi-axes
  int facets = 8;                            ///< diamond: girdle facets (girdle radius 1)
  double height = 1.5;                       ///< diamond: total height
  std::array<double, 3> extents{{1, 1, 1}};  ///< kdop18: half extents of the box
  double chamfer = 0.5;                      ///< kdop18: how far the edge cuts reach into the box
  int count = 1;
  /// Exactly one of size and scale is positive: size is the diameter of the bounding ball (about the
  /// box centre) after scaling; scale multiplies the shape's own coordinates.
  double size = 0;
  double scale = 0;
};

/// The effects a scene declares; the simulator applies these and nothing else.
struct SceneEffects
{
  /// Constant velocity, uniform random direction, speed uniform in [speed_min, speed_max].
  bool linear_motion = false;
  double speed_min = 0, speed_max = 0;
  /// Constant angular velocity about the body's centre, uniform random axis, rate in [rate_min, rate_max] rad/s.
  bool spin = false;
  double rate_min = 0, rate_max = 0;
  /// Bodies' bounding balls reflect off the cube's walls (velocity component reversed).
  bool wall_bounce = false;
  /// Bodies whose meshes intersect and approach each other exchange their velocity components along
  /// the line of centres (elastic, equal masses).
  bool collision_response = false;
};

/// The paper's figures for a scene, converted to the two measures of the summary table (NaN: not given).
struct PaperFigures
{
  double rs_fewer_than_obb = std::numeric_limits<double>::quiet_NaN();    ///< 100 (OBB - RS) / OBB
  double kdop18_more_than_rs = std::numeric_limits<double>::quiet_NaN();  ///< 100 (KDOP18 - RS) / RS
  std::string note;                                                       ///< what the paper says, verbatim-ish
};

struct Scene
{
  std::string name;
  std::string source;  ///< the file (or label) the scene was read from, for messages
  double cube = 0;     ///< side of the cube [-cube/2, cube/2]^3 the bodies start in (and bounce in)
  int frames = 0;
  double time_step = 0;
  std::uint64_t seed = 0;
  SceneEffects effects;
  std::vector<SceneBody> bodies;
  PaperFigures paper;

  int numBodies() const;
};

/// Parses and validates a scene from JSON text. Throws std::invalid_argument naming `source` and the
/// offending key (e.g. "bodies[2].size") for syntax errors, unknown keys, wrong types and bad values.
/// Mesh files are not looked at (mesh_path = mesh).
Scene parseScene(const std::string& json_text, const std::string& source);

/// Reads and parses a scene file, then resolves every mesh against data_dir (absolute paths are kept).
/// A missing scene file or mesh file throws std::runtime_error naming the file and the key.
Scene loadScene(const std::string& path, const std::string& data_dir);

}  // namespace fcl_rs

#endif
