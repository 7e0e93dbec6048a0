// The Python module fcl_rs (pybind11): RS meshes, FCL shapes, collide/distance, batches, robots and robots among
// obstacles (environments, octomaps), in double.
// Arrays come in and go out as numpy arrays; batch inputs are read in place and outputs are handed over
// without a copy. C++ exceptions keep their messages (invalid_argument -> ValueError, runtime_error ->
// RuntimeError).
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <shared_mutex>
#include <string>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/halfspace.h>
#include <fcl/geometry/shape/plane.h>
#include <fcl/geometry/shape/sphere.h>
#if FCL_HAVE_OCTOMAP
#include <fcl/geometry/octree/octree.h>
#include <octomap/OcTree.h>
#endif
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "fcl_rs/batch.h"
#include "fcl_rs/bvh/build_model.h"
#include "fcl_rs/collide.h"
#include "fcl_rs/distance.h"
#include "fcl_rs/mesh/load_mesh.h"
#include "fcl_rs/robot.h"
#include "fcl_rs/robot/batch_environment.h"
#include "fcl_rs/solid.h"
#include "fcl_rs/robot/batch_self_collision.h"
#include "fcl_rs/validate.h"
#include "fcl_rs/version.h"

namespace py = pybind11;

namespace fcl_rs {
namespace {

using Geometry = fcl::CollisionGeometryd;
using GeometryPtr = std::shared_ptr<Geometry>;
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A numpy array that owns `values` (moved, not copied).
template <typename T, typename Out = T>
py::array_t<Out> handOver(std::vector<T>&& values, std::vector<py::ssize_t> shape)
{
  static_assert(sizeof(T) == sizeof(Out), "the numpy dtype must have the vector's layout");
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<Out>(shape, reinterpret_cast<const Out*>(owned->data()), free_when_done);
}

// ---- Arguments: every one is checked here, and a ValueError names it ("fcl_rs.collide: pose_a ..."). ----

[[noreturn]] void badArgument(const std::string& api, const std::string& argument, const std::string& what)
{
  throw std::invalid_argument(api + ": " + argument + " " + what);
}

std::string shapeText(const py::array& a)
{
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

/// obj as a numpy array of real numbers: a floating dtype up to float64, or integers. Bool, complex, longdouble
/// (which would lose digits), object and string arrays are refused.
py::array realArray(const py::handle& obj, const std::string& api, const std::string& argument)
{
  py::array a = py::array::ensure(obj);
  if (!a) badArgument(api, argument, "must be an array of numbers");
  const char kind = a.dtype().kind();
  if (!((kind == 'f' && a.itemsize() <= 8) || kind == 'i' || kind == 'u'))
    badArgument(api, argument, "must hold real numbers (float64, float32 or integers), got dtype " +
                                   std::string(py::str(a.dtype())));
  return a;
}

/// Refuses any shape but `shape` (-1: any size in that dimension).
void requireShape(const py::array& a, std::vector<py::ssize_t> shape, const std::string& api,
                  const std::string& argument, const std::string& expected)
{
  bool ok = a.ndim() == py::ssize_t(shape.size());
  for (std::size_t d = 0; ok && d < shape.size(); ++d) ok = shape[d] < 0 || a.shape(py::ssize_t(d)) == shape[d];
  if (!ok) badArgument(api, argument, "must have shape " + expected + ", got " + shapeText(a));
}

/// The array's values as C-ordered doubles (float32 and integers widened; float64 read in place when it can be).
Doubles doublesOf(const py::array& a)
{
  return Doubles::ensure(a);
}

/// Refuses NaN and infinite values, naming the first one's index.
void requireFinite(const Doubles& a, const std::string& api, const std::string& argument)
{
  const double* v = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(v[i]))
    {
      std::string index;
      py::ssize_t rest = i;
      for (py::ssize_t d = a.ndim() - 1; d >= 0; --d)
      {
        index = std::to_string(rest % a.shape(d)) + (index.empty() ? "" : ", ") + index;
        rest /= a.shape(d);
      }
      badArgument(api, argument + "[" + index + "]", "is not finite: " + std::to_string(v[i]));
    }
}

/// A float32 rotation is orthonormal only to float32's precision: it is checked at float32's tolerance and then
/// made exactly orthonormal in double (Gram-Schmidt moves it by about that much), so that the double queries
/// behind every call accept it.
bool singlePrecision(const py::array& a)
{
  return a.dtype().kind() == 'f' && a.itemsize() <= 4;
}

/// The pose of a row-major 4x4 block, validated as fcl_rs validates poses (fcl_rs/validate.h).
fcl::Transform3d poseAt(const double* m, bool single, const std::string& api, const std::string& argument)
{
  fcl::Transform3d tf;
  // numpy is row-major, Eigen's transform storage column-major.
  tf.matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m);
  const double tolerance = single ? double(rigidTransformTolerance<float>()) : rigidTransformTolerance<double>();
  if (!isRigidTransform(tf, tolerance))
    throw std::invalid_argument(detail::notRigidMessage(tf, tolerance, api.c_str(), argument));
  if (single)
  {
    const fcl::Matrix3d R = tf.linear();
    const fcl::Vector3d x = R.col(0).normalized();
    const fcl::Vector3d y = (R.col(1) - x.dot(R.col(1)) * x).normalized();
    tf.linear() << x, y, x.cross(y);
  }
  return tf;
}

fcl::Transform3d poseOf(const py::handle& obj, const std::string& api, const std::string& argument)
{
  const py::array a = realArray(obj, api, argument);
  requireShape(a, {4, 4}, api, argument, "(4, 4)");
  return poseAt(doublesOf(a).data(), singlePrecision(a), api, argument);
}

/// (N, 4, 4) poses, each validated once here (the batch behind the call validates the array once more).
std::vector<fcl::Transform3d> posesOf(const py::handle& obj, const std::string& api, const std::string& argument)
{
  const py::array a = realArray(obj, api, argument);
  requireShape(a, {-1, 4, 4}, api, argument, "(N, 4, 4)");
  const Doubles values = doublesOf(a);
  const bool single = singlePrecision(a);
  std::vector<fcl::Transform3d> poses(std::size_t(a.shape(0)));
  for (std::size_t i = 0; i < poses.size(); ++i)
    poses[i] = poseAt(values.data() + 16 * i, single, api, argument + "[" + std::to_string(i) + "]");
  return poses;
}

/// A shape's size: positive and finite.
double sizeOf(double value, const char* api, const char* argument)
{
  if (!(value > 0 && std::isfinite(value)))
    badArgument(api, argument, "must be positive and finite, got " + std::to_string(value));
  return value;
}

/// Three finite numbers.
fcl::Vector3d pointOf(const py::handle& obj, const char* api, const char* argument)
{
  const py::array a = realArray(obj, api, argument);
  requireShape(a, {3}, api, argument, "(3,)");
  const Doubles values = doublesOf(a);
  requireFinite(values, api, argument);
  return fcl::Vector3d(values.data()[0], values.data()[1], values.data()[2]);
}

/// A plane's or halfspace's normal: three finite numbers, not all zero, whose length is finite (FCL's constructors
/// divide by it, and take a zero normal as the x axis silently).
fcl::Vector3d normalOf(const py::handle& obj, const char* api)
{
  const fcl::Vector3d n = pointOf(obj, api, "normal");
  if (!(n.norm() > 0 && std::isfinite(n.norm())))
    badArgument(api, "normal", "must have a non-zero finite length, got (" + std::to_string(n.x()) + ", " +
                                   std::to_string(n.y()) + ", " + std::to_string(n.z()) + ")");
  return n;
}

double offsetOf(double value, const char* api)
{
  if (!std::isfinite(value)) badArgument(api, "offset", "must be finite, got " + std::to_string(value));
  return value;
}

/// A thread count: 0 (every core) or more.
int threadsOf(int num_threads, const char* api)
{
  if (num_threads < 0)
    badArgument(api, "num_threads", "must be >= 0 (0: every core, 1: the calling thread), got " +
                                        std::to_string(num_threads));
  return num_threads;
}

py::array_t<double> vector3(const fcl::Vector3d& v)
{
  return py::array_t<double>(3, v.data());
}

/// The BV type of a Robot: every type SelfCollision::query (behind all of Robot's checks) accepts. KDOP18 is
/// refused here rather than at the first check: its trees are refitted in place in the world frame per check,
/// so they cannot be shared by the batch's threads or Python threads.
BVType robotBVType(const std::string& name, const std::string& api)
{
  const BVType bv = parseBVType(name);
  if (bv != BVType::kKDOP18) return bv;
  std::string names;
  for (BVType other : kRobotBVTypes)
    if (other != BVType::kKDOP18) names += std::string(names.empty() ? "" : ", ") + bvTypeName(other);
  throw std::invalid_argument(api + ": bv 'KDOP18' is not supported (its trees are refitted in place per "
                              "check, so checks could not share them across threads); use one of " + names);
}

/// A triangle mesh from (V, 3) finite real vertices and (F, 3) integer vertex indices in [0, V).
TriangleMesh<double> meshOf(const py::handle& vertices_arg, const py::handle& triangles_arg, const std::string& api)
{
  const py::array vertices_array = realArray(vertices_arg, api, "vertices");
  requireShape(vertices_array, {-1, 3}, api, "vertices", "(V, 3)");
  const Doubles vertices = doublesOf(vertices_array);
  requireFinite(vertices, api, "vertices");
  py::array triangles_array = py::array::ensure(triangles_arg);
  const char kind = triangles_array ? triangles_array.dtype().kind() : 'O';
  if (kind != 'i' && kind != 'u')
    badArgument(api, "triangles", "must be an array of integers (vertex indices), got " +
                                      (triangles_array ? "dtype " + std::string(py::str(triangles_array.dtype()))
                                                       : std::string("no array")));
  requireShape(triangles_array, {-1, 3}, api, "triangles", "(F, 3)");
  // Unsigned 64-bit indices beyond int64's range are out of range anyway: they wrap to negatives.
  const auto triangles =
      py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(triangles_array);
  TriangleMesh<double> mesh;
  const py::ssize_t num_vertices = vertices.shape(0);
  for (py::ssize_t i = 0; i < num_vertices; ++i)
    mesh.vertices.emplace_back(vertices.at(i, 0), vertices.at(i, 1), vertices.at(i, 2));
  for (py::ssize_t i = 0; i < triangles.shape(0); ++i)
  {
    for (int k = 0; k < 3; ++k)
      if (triangles.at(i, k) < 0 || triangles.at(i, k) >= num_vertices)
        badArgument(api, "triangles[" + std::to_string(i) + ", " + std::to_string(k) + "]",
                    "is " + std::to_string(triangles.at(i, k)) + ", not a vertex index in [0, " +
                        std::to_string(num_vertices) + ")");
    mesh.triangles.emplace_back(std::size_t(triangles.at(i, 0)), std::size_t(triangles.at(i, 1)),
                                std::size_t(triangles.at(i, 2)));
  }
  return mesh;
}

/// The pairs an SRDF disables for the robot (none without an SRDF).
std::vector<DisabledCollision> disabledCollisionsOf(const std::string& srdf, const RobotModel& model)
{
  return srdf.empty() ? std::vector<DisabledCollision>{} : loadDisabledCollisions(srdf, model);
}

/// The SRDF's planning groups, read when first asked for: an SRDF used only for its disabled pairs needs none.
class LazyGroups
{
public:
  explicit LazyGroups(std::string srdf) : srdf_(std::move(srdf)) {}
  const PlanningGroups& of(const RobotModel& model)
  {
    if (!groups_) groups_ = srdf_.empty() ? PlanningGroups() : loadPlanningGroups(srdf_, model);
    return *groups_;
  }

private:
  std::string srdf_;
  std::optional<PlanningGroups> groups_;
};

/// A robot loaded from URDF (and SRDF), with its self-collision checker.
struct Robot
{
  Robot(const std::string& urdf, const std::string& srdf, const std::string& bv)
    : model(loadUrdf(urdf)),
      checker(model, robotBVType(bv, "fcl_rs.Robot"), disabledCollisionsOf(srdf, model)),
      groups(srdf)
  {
  }
  const Kinematics<double>& kinematics() const { return checker.kinematics(); }
  RobotModel model;
  SelfCollision<double> checker;
  LazyGroups groups;
};

/// The planning-group members of Robot and Environment (`Holder` has model, groups and kinematics()).
template <typename Holder>
void bindPlanningGroups(py::class_<Holder>& c, const std::string& api)
{
  c.def_property_readonly(
       "groups",
       [](Holder& h) {
         std::map<std::string, std::vector<int>> out;
         for (const PlanningGroup& g : h.groups.of(h.model).groups) out[g.name] = g.variables;
         return out;
       },
       "The SRDF's planning groups: {name: the configuration indices the group moves, ascending} (empty\n"
       "without an SRDF; read on first use, RuntimeError naming the file and line on a bad group).")
      .def_property_readonly(
          "default_configuration", [](const Holder& h) { return fcl::VectorXd(h.kinematics().defaultConfiguration()); },
          "MoveIt's default positions: 0 where the limits allow it, else the nearer limit.")
      .def(
          "group_state",
          [api](Holder& h, const std::string& name, const std::string& group) {
            const PlanningGroups& groups = h.groups.of(h.model);
            try
            {
              return fcl::VectorXd(groups.state(name, group).applyTo(h.kinematics().defaultConfiguration()));
            }
            catch (const std::invalid_argument& e)
            {
              throw py::value_error(api + ".group_state: " + e.what());
            }
          },
          py::arg("name"), py::arg("group") = "",
          "The configuration of the SRDF's <group_state> `name` (of `group`, needed when several groups have a\n"
          "state of that name): default_configuration with the state's values.");
}

/// A configuration (dof,) or configurations (rows, dof) of a robot with `dof` variables (rows -1: any number):
/// real numbers, finite.
Doubles configurationsOf(const py::handle& obj, int dof, bool batch, const std::string& api,
                         const std::string& argument = "q", py::ssize_t rows = -1)
{
  const py::array a = realArray(obj, api, argument);
  if (batch)
    requireShape(a, {rows, dof}, api, argument,
                 "(" + (rows < 0 ? std::string("N") : std::to_string(rows)) + ", " + std::to_string(dof) + ")");
  else
    requireShape(a, {dof}, api, argument, "(" + std::to_string(dof) + ",)");
  Doubles values = doublesOf(a);
  requireFinite(values, api, argument);
  return values;
}


// ---- Environments: obstacles and octree maps, which Python may change while queries run without the GIL. ----

/// The lock between what runs without the GIL and reads obstacles and maps in place (environment queries, motion
/// checks and their batches: shared) and the edits of obstacles and maps (which keep the GIL: exclusive). An edit
/// from one Python thread waits for the queries running in others, and no query reads half an edit. One lock for
/// the module: edits are short and rare next to queries.
std::shared_mutex& worldLock()
{
  static std::shared_mutex lock;
  return lock;
}

using WorldEdit = std::unique_lock<std::shared_mutex>;

py::array_t<double> poseArray(const fcl::Transform3d& tf)
{
  py::array_t<double> out({4, 4});
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) out.mutable_at(i, j) = tf.matrix()(i, j);
  return out;
}

#if FCL_HAVE_OCTOMAP
/// An octomap, the fcl::OcTree that environments hold (sharing the map) and a count of the map's changes, by which
/// an environment knows to read the occupied cells again before its next query.
struct OcTreeMap
{
  explicit OcTreeMap(std::shared_ptr<octomap::OcTree> m)
    : geometry(std::make_shared<fcl::OcTreed>(m)), map(std::move(m))
  {
  }
  std::shared_ptr<fcl::OcTreed> geometry;
  std::shared_ptr<octomap::OcTree> map;
  std::uint64_t version = 0;
};

/// A point inside the map's reach: octomap's 16-bit keys cover [-32768, 32768) cells about the origin on each axis,
/// and octomap drops a point beyond them without a word.
octomap::point3d pointIn(const octomap::OcTree& map, const double* xyz, const std::string& api,
                         const std::string& argument)
{
  const double reach = map.getResolution() * 32768;
  const octomap::point3d p{float(xyz[0]), float(xyz[1]), float(xyz[2])};
  octomap::OcTreeKey key;
  // Far points first: octomap converts the scaled coordinate to int before its range check.
  const bool near = std::abs(xyz[0]) < 2 * reach && std::abs(xyz[1]) < 2 * reach && std::abs(xyz[2]) < 2 * reach;
  if (!near || !map.coordToKeyChecked(p, key))
  {
    badArgument(api, argument,
                "(" + std::to_string(xyz[0]) + ", " + std::to_string(xyz[1]) + ", " + std::to_string(xyz[2]) +
                    ") is outside the map: octomap reaches [-" + std::to_string(reach) + ", " + std::to_string(reach) +
                    ") on each axis at resolution " + std::to_string(map.getResolution()));
  }
  return p;
}

/// (N, 3) finite points inside the map's reach.
octomap::Pointcloud pointsIn(const octomap::OcTree& map, const py::handle& obj, const std::string& api,
                             const std::string& argument)
{
  const py::array a = realArray(obj, api, argument);
  requireShape(a, {-1, 3}, api, argument, "(N, 3)");
  const Doubles values = doublesOf(a);
  requireFinite(values, api, argument);
  octomap::Pointcloud points;
  points.reserve(std::size_t(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    points.push_back(pointIn(map, values.data() + 3 * i, api, argument + "[" + std::to_string(i) + "]"));
  return points;
}

/// The leaf cells FCL counts as occupied (fcl::OcTree::isNodeOccupied, the map's threshold), as octomap iterates
/// them: their centres and edge lengths. The inner nodes above an occupied leaf are occupied too (octomap keeps
/// each the largest occupancy of its children), so these are the cells FCL's traversals reach.
void occupiedCells(const OcTreeMap& o, std::vector<double>& centres, std::vector<double>& sizes)
{
  for (auto it = o.map->begin_leafs(), end = o.map->end_leafs(); it != end; ++it)
    if (o.geometry->isNodeOccupied(&*it))
    {
      centres.insert(centres.end(), {it.getX(), it.getY(), it.getZ()});
      sizes.push_back(it.getSize());
    }
}

/// The file's octomap format from its name: ".bt" (binary, occupied or free per cell) or ".ot" (full occupancy).
bool binaryOcTreeFile(const std::string& path, const std::string& api)
{
  const auto endsWith = [&path](const char* suffix) {
    const std::string s(suffix);
    return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0;
  };
  if (endsWith(".bt")) return true;
  if (endsWith(".ot")) return false;
  badArgument(api, "path '" + path + "'", "must end in .bt (binary octomap) or .ot (full octomap)");
}
#endif

/// A robot loaded from URDF (and SRDF) among named obstacles.
struct PyEnvironment
{
  PyEnvironment(const std::string& urdf, const std::string& srdf, const std::string& bv)
    : model(loadUrdf(urdf)),
      env(model, robotBVType(bv, "fcl_rs.Environment"), disabledCollisionsOf(srdf, model)),
      groups(srdf)
  {
  }
  const Kinematics<double>& kinematics() const { return env.kinematics(); }
  RobotModel model;
  Environment<double> env;
  LazyGroups groups;
#if FCL_HAVE_OCTOMAP
  /// The octree obstacles by name, each with the map version the environment last read.
  std::map<std::string, std::pair<std::shared_ptr<OcTreeMap>, std::uint64_t>> octrees;
#endif

  bool mapsChanged() const
  {
#if FCL_HAVE_OCTOMAP
    for (const auto& held : octrees)
      if (held.second.second != held.second.first->version) return true;
#endif
    return false;
  }

  /// Runs `query` without the GIL, holding the world lock shared, after reading again the occupied cells of every
  /// map changed since the environment last read it (again if a map changed between that and taking the lock).
  template <typename Query>
  auto reading(Query&& query)
  {
    for (;;)
    {
#if FCL_HAVE_OCTOMAP
      if (mapsChanged())
      {
        const WorldEdit edit(worldLock());
        for (auto& held : octrees)
          if (held.second.second != held.second.first->version)
          {
            env.refreshOcTree(held.first);
            held.second.second = held.second.first->version;
          }
      }
#endif
      py::gil_scoped_release release;
      const std::shared_lock<std::shared_mutex> lock(worldLock());
      if (!mapsChanged()) return query();
    }
  }
};

void requireNewName(const PyEnvironment& e, const std::string& name, const std::string& api)
{
  if (name.empty()) badArgument(api, "name", "must not be empty");
  if (e.env.contains(name)) badArgument(api, "name '" + name + "'", "is taken (obstacle names are unique)");
}

void requireObstacle(const PyEnvironment& e, const std::string& name, const std::string& api)
{
  if (!e.env.contains(name)) badArgument(api, "name '" + name + "'", "names no obstacle");
}

int dofOf(const PyEnvironment& e)
{
  return e.env.kinematics().numVariables();
}

EnvironmentRequest environmentRequest(const PyEnvironment& e, bool pairs, bool minimum_distance, const std::string& api)
{
  if (minimum_distance && e.env.bvType() == BVType::kOBB)
    badArgument(api, "minimum_distance", "needs a distance query, which FCL lacks for OBB trees (bv 'OBB'); use an "
                                         "environment of bv RS, OBBRSS or RSS");
  EnvironmentRequest request;
  request.colliding_pairs = pairs;
  request.minimum_distance = minimum_distance;
  return request;
}

MotionRequest<double> motionRequest(const PyEnvironment& e, bool earliest, double tolerance, const std::string& api)
{
  if (e.env.bvType() == BVType::kOBB)
    throw std::invalid_argument(api + ": motion checks need a distance query, which FCL lacks for OBB trees (bv "
                                      "'OBB'); use an environment of bv RS, OBBRSS or RSS");
  if (!(tolerance > 0 && tolerance <= 1))
    badArgument(api, "tolerance", "must be in (0, 1] (a fraction of the segment), got " + std::to_string(tolerance));
  MotionRequest<double> request;
  request.earliest = earliest;
  request.tolerance = tolerance;
  return request;
}

py::tuple pairTuple(const BodyPair& p)
{
  return py::make_tuple(p.link, p.other, p.other_is_link);
}

py::list pairList(const std::vector<BodyPair>& pairs)
{
  py::list out;
  for (const BodyPair& p : pairs) out.append(pairTuple(p));
  return out;
}

py::dict motionDict(const MotionResult<double>& r)
{
  py::dict out;
  out["colliding"] = r.colliding;
  out["parameter"] = r.parameter;
  out["free_until"] = r.free_until;
  out["configurations_checked"] = r.configurations_checked;
  out["distance_queries"] = r.distance_queries;
  return out;
}

}  // namespace
}  // namespace fcl_rs

PYBIND11_MODULE(fcl_rs, m)
{
  using namespace fcl_rs;
  m.doc() = "RS bounding-volume trees for FCL: collision and distance queries, batches on every core, robots, robots "
            "among obstacles.";
  m.attr("__version__") = FCL_RS_VERSION;

  py::class_<Geometry, GeometryPtr>(m, "Geometry", "Any collision geometry: an RS mesh or an FCL shape.");

  py::class_<fcl::BVHModel<RSd>, Geometry, std::shared_ptr<fcl::BVHModel<RSd>>>(
      m, "Mesh", "A triangle mesh with an RS bounding-volume tree (surface-area splits).")
      .def(py::init([](const py::handle& vertices, const py::handle& triangles) {
             return buildModel<RSd>(meshOf(vertices, triangles, "fcl_rs.Mesh"));
           }),
           py::arg("vertices"), py::arg("triangles"),
           "Builds the tree over (V, 3) vertices (float64, float32 or integers) and (F, 3) integer vertex indices.\n"
           "Raises ValueError naming the argument for an empty mesh, a wrong shape or dtype, a non-finite vertex or\n"
           "an index out of range.")
      .def_static(
          "from_file", [](const std::string& path) { return buildModel<RSd>(loadMesh<double>(path)); },
          py::arg("path"), "Loads every mesh of a file assimp reads (OBJ, STL, PLY, DAE, ...) into one tree.")
      .def_property_readonly("num_vertices", [](const fcl::BVHModel<RSd>& b) { return b.num_vertices; })
      .def_property_readonly("num_triangles", [](const fcl::BVHModel<RSd>& b) { return b.num_tris; });

  // Sizes are positive and finite: FCL takes a negative or NaN size and answers for it (or aborts in libccd).
  py::class_<fcl::Boxd, Geometry, std::shared_ptr<fcl::Boxd>>(m, "Box", "FCL box centred at its origin.")
      .def(py::init([](double x, double y, double z) {
             return fcl::Boxd(sizeOf(x, "fcl_rs.Box", "x"), sizeOf(y, "fcl_rs.Box", "y"), sizeOf(z, "fcl_rs.Box", "z"));
           }),
           py::arg("x"), py::arg("y"), py::arg("z"));
  py::class_<fcl::Sphered, Geometry, std::shared_ptr<fcl::Sphered>>(m, "Sphere", "FCL sphere.")
      .def(py::init([](double radius) { return fcl::Sphered(sizeOf(radius, "fcl_rs.Sphere", "radius")); }),
           py::arg("radius"));
  py::class_<fcl::Ellipsoidd, Geometry, std::shared_ptr<fcl::Ellipsoidd>>(m, "Ellipsoid", "FCL ellipsoid.")
      .def(py::init([](double a, double b, double c) {
             return fcl::Ellipsoidd(sizeOf(a, "fcl_rs.Ellipsoid", "a"), sizeOf(b, "fcl_rs.Ellipsoid", "b"),
                                    sizeOf(c, "fcl_rs.Ellipsoid", "c"));
           }),
           py::arg("a"), py::arg("b"), py::arg("c"));
  py::class_<fcl::Capsuled, Geometry, std::shared_ptr<fcl::Capsuled>>(m, "Capsule", "FCL capsule along z.")
      .def(py::init([](double radius, double length) {
             return fcl::Capsuled(sizeOf(radius, "fcl_rs.Capsule", "radius"), sizeOf(length, "fcl_rs.Capsule", "length"));
           }),
           py::arg("radius"), py::arg("length"));
  py::class_<fcl::Cylinderd, Geometry, std::shared_ptr<fcl::Cylinderd>>(m, "Cylinder", "FCL cylinder along z.")
      .def(py::init([](double radius, double length) {
             return fcl::Cylinderd(sizeOf(radius, "fcl_rs.Cylinder", "radius"),
                                   sizeOf(length, "fcl_rs.Cylinder", "length"));
           }),
           py::arg("radius"), py::arg("length"));
  py::class_<fcl::Coned, Geometry, std::shared_ptr<fcl::Coned>>(m, "Cone", "FCL cone along z.")
      .def(py::init([](double radius, double length) {
             return fcl::Coned(sizeOf(radius, "fcl_rs.Cone", "radius"), sizeOf(length, "fcl_rs.Cone", "length"));
           }),
           py::arg("radius"), py::arg("length"));

  py::class_<fcl::Planed, Geometry, std::shared_ptr<fcl::Planed>>(
      m, "Plane", "FCL plane {x : normal . x = offset}, normal and offset divided by the normal's length.")
      .def(py::init([](const py::handle& normal, double offset) {
             return fcl::Planed(normalOf(normal, "fcl_rs.Plane"), offsetOf(offset, "fcl_rs.Plane"));
           }),
           py::arg("normal"), py::arg("offset"))
      .def_property_readonly("normal", [](const fcl::Planed& p) { return fcl::Vector3d(p.n); })
      .def_property_readonly("offset", [](const fcl::Planed& p) { return p.d; });
  py::class_<fcl::Halfspaced, Geometry, std::shared_ptr<fcl::Halfspaced>>(
      m, "Halfspace", "FCL halfspace {x : normal . x <= offset}, normal and offset divided by the normal's length.")
      .def(py::init([](const py::handle& normal, double offset) {
             return fcl::Halfspaced(normalOf(normal, "fcl_rs.Halfspace"), offsetOf(offset, "fcl_rs.Halfspace"));
           }),
           py::arg("normal"), py::arg("offset"))
      .def_property_readonly("normal", [](const fcl::Halfspaced& h) { return fcl::Vector3d(h.n); })
      .def_property_readonly("offset", [](const fcl::Halfspaced& h) { return h.d; });

  py::class_<fcl::Contactd>(m, "Contact", "One contact, as in python-fcl.")
      .def_readonly("b1", &fcl::Contactd::b1, "triangle of the first geometry (meshes), else -1")
      .def_readonly("b2", &fcl::Contactd::b2, "triangle of the second geometry (meshes), else -1")
      .def_property_readonly("pos", [](const fcl::Contactd& c) { return vector3(c.pos); }, "world-frame point")
      .def_property_readonly("normal", [](const fcl::Contactd& c) { return vector3(c.normal); },
                             "world-frame normal, from the first geometry to the second")
      .def_readonly("penetration_depth", &fcl::Contactd::penetration_depth);

  // Request fields are checked where they are set, constructor and attribute alike.
  const auto contacts = [](long long n) {
    if (n < 1) badArgument("fcl_rs.CollisionRequest", "num_max_contacts", "must be at least 1, got " + std::to_string(n));
    return std::size_t(n);
  };
  py::class_<fcl::CollisionRequestd>(m, "CollisionRequest", "fcl::CollisionRequest: contact count and geometry.")
      .def(py::init([contacts](long long num_max_contacts, bool enable_contact) {
             return fcl::CollisionRequestd(contacts(num_max_contacts), enable_contact);
           }),
           py::arg("num_max_contacts") = 1, py::arg("enable_contact").noconvert() = false)
      .def_property(
          "num_max_contacts", [](const fcl::CollisionRequestd& r) { return r.num_max_contacts; },
          [contacts](fcl::CollisionRequestd& r, long long n) { r.num_max_contacts = contacts(n); })
      .def_readwrite("enable_contact", &fcl::CollisionRequestd::enable_contact);

  py::class_<fcl::CollisionResultd>(m, "CollisionResult", "fcl::CollisionResult.")
      .def_property_readonly("is_collision", &fcl::CollisionResultd::isCollision)
      .def_property_readonly("contacts", [](const fcl::CollisionResultd& r) {
        std::vector<fcl::Contactd> contacts;
        for (std::size_t i = 0; i < r.numContacts(); ++i) contacts.push_back(r.getContact(i));
        return contacts;
      });

  const auto error = [](const char* field, double value) {
    if (!(value >= 0 && std::isfinite(value)))
      badArgument("fcl_rs.DistanceRequest", field, "must be non-negative and finite, got " + std::to_string(value));
    return value;
  };
  py::class_<fcl::DistanceRequestd>(m, "DistanceRequest", "fcl::DistanceRequest.")
      .def(py::init([error](bool enable_nearest_points, bool enable_signed_distance, double rel_err, double abs_err) {
             return fcl::DistanceRequestd(enable_nearest_points, enable_signed_distance, error("rel_err", rel_err),
                                          error("abs_err", abs_err));
           }),
           py::arg("enable_nearest_points").noconvert() = false, py::arg("enable_signed_distance").noconvert() = false,
           py::arg("rel_err") = 0.0, py::arg("abs_err") = 0.0)
      .def_readwrite("enable_nearest_points", &fcl::DistanceRequestd::enable_nearest_points)
      .def_readwrite("enable_signed_distance", &fcl::DistanceRequestd::enable_signed_distance)
      .def_property(
          "rel_err", [](const fcl::DistanceRequestd& r) { return r.rel_err; },
          [error](fcl::DistanceRequestd& r, double v) { r.rel_err = error("rel_err", v); })
      .def_property(
          "abs_err", [](const fcl::DistanceRequestd& r) { return r.abs_err; },
          [error](fcl::DistanceRequestd& r, double v) { r.abs_err = error("abs_err", v); });

  py::class_<fcl::DistanceResultd>(m, "DistanceResult", "fcl::DistanceResult.")
      .def_readonly("min_distance", &fcl::DistanceResultd::min_distance)
      .def_readonly("b1", &fcl::DistanceResultd::b1)
      .def_readonly("b2", &fcl::DistanceResultd::b2)
      .def_property_readonly("nearest_points", [](const fcl::DistanceResultd& r) {
        py::array_t<double> points({2, 3});
        for (int i = 0; i < 2; ++i)
          for (int k = 0; k < 3; ++k) points.mutable_at(i, k) = r.nearest_points[i][k];
        return points;
      }, "(2, 3) world-frame points, with DistanceRequest(enable_nearest_points=True)");

  m.def(
      "collide",
      [](const GeometryPtr& a, const py::handle& pose_a, const GeometryPtr& b, const py::handle& pose_b,
         const fcl::CollisionRequestd& request) {
        fcl::CollisionResultd result;
        fcl_rs::collide(a.get(), poseOf(pose_a, "fcl_rs.collide", "pose_a"), b.get(),
                        poseOf(pose_b, "fcl_rs.collide", "pose_b"), request, result);
        return result;
      },
      py::arg("a").none(false), py::arg("pose_a"), py::arg("b").none(false), py::arg("pose_b"),
      py::arg("request") = fcl::CollisionRequestd(),
      "fcl_rs::collide of two geometries at 4x4 poses; returns a CollisionResult.");
  m.def(
      "distance",
      [](const GeometryPtr& a, const py::handle& pose_a, const GeometryPtr& b, const py::handle& pose_b,
         const fcl::DistanceRequestd& request) {
        fcl::DistanceResultd result;
        fcl_rs::distance(a.get(), poseOf(pose_a, "fcl_rs.distance", "pose_a"), b.get(),
                         poseOf(pose_b, "fcl_rs.distance", "pose_b"), request, result);
        return result;
      },
      py::arg("a").none(false), py::arg("pose_a"), py::arg("b").none(false), py::arg("pose_b"),
      py::arg("request") = fcl::DistanceRequestd(),
      "fcl_rs::distance of two geometries at 4x4 poses; returns a DistanceResult (0 when colliding).");

  m.def(
      "collide_batch",
      [](const GeometryPtr& a, const py::handle& poses_a, const GeometryPtr& b, const py::handle& poses_b,
         int num_threads) {
        const char* api = "fcl_rs.collide_batch";
        const auto pa = posesOf(poses_a, api, "poses_a"), pb = posesOf(poses_b, api, "poses_b");
        threadsOf(num_threads, api);
        std::vector<std::uint8_t> colliding(pa.size());
        {
          py::gil_scoped_release release;
          const fcl::CollisionRequestd request;
          const auto results = collideBatch(*a, pa, *b, pb, request, {num_threads});
          for (std::size_t i = 0; i < results.size(); ++i) colliding[i] = results[i].isCollision();
        }
        const py::ssize_t n = py::ssize_t(colliding.size());
        return handOver<std::uint8_t, bool>(std::move(colliding), {n});
      },
      py::arg("a").none(false), py::arg("poses_a"), py::arg("b").none(false), py::arg("poses_b"),
      py::arg("num_threads") = 0,
      "Whether a at poses_a[i] and b at poses_b[i] collide, for (N, 4, 4) pose arrays; a bool array (N,).\n"
      "num_threads: 0 every core, 1 the calling thread only. Results do not depend on it.");
  m.def(
      "distance_batch",
      [](const GeometryPtr& a, const py::handle& poses_a, const GeometryPtr& b, const py::handle& poses_b,
         int num_threads) {
        const char* api = "fcl_rs.distance_batch";
        const auto pa = posesOf(poses_a, api, "poses_a"), pb = posesOf(poses_b, api, "poses_b");
        threadsOf(num_threads, api);
        std::vector<double> distances(pa.size()), points(6 * pa.size());
        {
          py::gil_scoped_release release;
          fcl::DistanceRequestd request;
          request.enable_nearest_points = true;
          const auto results = distanceBatch(*a, pa, *b, pb, request, {num_threads});
          for (std::size_t i = 0; i < results.size(); ++i)
          {
            distances[i] = results[i].min_distance;
            for (int k = 0; k < 2; ++k)
              for (int d = 0; d < 3; ++d) points[6 * i + 3 * std::size_t(k) + std::size_t(d)] = results[i].nearest_points[k][d];
          }
        }
        const py::ssize_t n = py::ssize_t(distances.size());
        return py::make_tuple(handOver(std::move(distances), {n}), handOver(std::move(points), {n, 2, 3}));
      },
      py::arg("a").none(false), py::arg("poses_a"), py::arg("b").none(false), py::arg("poses_b"),
      py::arg("num_threads") = 0,
      "Distances (N,) and world-frame nearest points (N, 2, 3) of a at poses_a[i] and b at poses_b[i].");

  py::class_<SolidMesh<double>>(m, "Solid",
                                "A closed mesh whose interior counts: containment and a vertex penetration depth "
                                "(docs/solid.md).")
      .def(py::init([](const std::shared_ptr<fcl::BVHModel<RSd>>& mesh) { return SolidMesh<double>(mesh); }),
           py::arg("mesh").none(false),
           "Raises ValueError naming the first edge not run by exactly two triangles in opposite directions.")
      .def_property_readonly(
          "mesh", [](const SolidMesh<double>& s) { return std::const_pointer_cast<fcl::BVHModel<RSd>>(s.modelPtr()); })
      .def(
          "classify",
          [](const SolidMesh<double>& s, const py::handle& point) {
            switch (s.classify(pointOf(point, "fcl_rs.Solid.classify", "point")))
            {
              case SolidSide::kInside: return "inside";
              case SolidSide::kOutside: return "outside";
              case SolidSide::kOnSurface: break;
            }
            return "on_surface";
          },
          py::arg("point"),
          "'inside', 'outside' or 'on_surface' (within rounding of the surface) for a point in the mesh's "
          "coordinates.")
      .def(
          "contains",
          [](const SolidMesh<double>& s, const py::handle& point) {
            return s.contains(pointOf(point, "fcl_rs.Solid.contains", "point"));
          },
          py::arg("point"), "Whether the point (mesh coordinates) is inside or on the surface.")
      .def(
          "distance_to_surface",
          [](const SolidMesh<double>& s, const py::handle& point) {
            fcl::Vector3d nearest;
            const double d = s.distanceToSurface(pointOf(point, "fcl_rs.Solid.distance_to_surface", "point"), &nearest);
            return py::make_tuple(d, nearest);
          },
          py::arg("point"), "(distance, nearest point) from the point to the surface, mesh coordinates.");

  m.def(
      "collide_solids",
      [](const SolidMesh<double>& a, const py::handle& pose_a, const SolidMesh<double>& b, const py::handle& pose_b,
         bool containment, bool penetration_depth) {
        const char* api = "fcl_rs.collide_solids";
        SolidCollisionRequest request;
        request.containment = containment;
        request.penetration_depth = penetration_depth;
        const SolidCollisionResult<double> r =
            collideSolids(a, poseOf(pose_a, api, "pose_a"), b, poseOf(pose_b, api, "pose_b"), request);
        const char* contact = "none";
        switch (r.contact)
        {
          case SolidContact::kNone: break;
          case SolidContact::kSurfacesIntersect: contact = "surfaces_intersect"; break;
          case SolidContact::kFirstInsideSecond: contact = "first_inside_second"; break;
          case SolidContact::kSecondInsideFirst: contact = "second_inside_first"; break;
        }
        py::dict out;
        out["collision"] = r.collision;
        out["contact"] = contact;
        out["penetration_depth"] = r.has_penetration_depth ? py::object(py::float_(r.penetration_depth)) : py::none();
        const bool deepest = r.deepest_mesh >= 0;
        out["deepest_mesh"] = deepest ? py::object(py::int_(r.deepest_mesh)) : py::none();
        out["deepest_vertex"] = deepest ? py::cast(r.deepest_vertex) : py::none();
        out["nearest_on_other"] = deepest ? py::cast(r.nearest_on_other) : py::none();
        return out;
      },
      py::arg("a").none(false), py::arg("pose_a"), py::arg("b").none(false), py::arg("pose_b"),
      py::arg("containment") = true, py::arg("penetration_depth") = false,
      "fcl_rs::collideSolids at 4x4 poses: a dict with collision, contact ('none', 'surfaces_intersect',\n"
      "'first_inside_second', 'second_inside_first'), penetration_depth (None unless asked and colliding),\n"
      "deepest_mesh (0 or 1), deepest_vertex and nearest_on_other (world coordinates; None without a vertex inside).");

  py::class_<Robot> robot_class(m, "Robot",
                                "A URDF robot (SRDF disabled pairs and planning groups optional) with a "
                                "self-collision checker.");
  bindPlanningGroups(robot_class, "fcl_rs.Robot");
  robot_class
      .def(py::init<const std::string&, const std::string&, const std::string&>(), py::arg("urdf"),
           py::arg("srdf") = "", py::arg("bv") = "RS",
           "Loads the URDF and its collision meshes; bv is one of RS, OBBRSS, OBB, RSS (OBB: no minimum_distance).")
      .def_property_readonly("name", [](const Robot& r) { return r.model.name; })
      .def_property_readonly("link_names", [](const Robot& r) { return r.checker.linkNames(); })
      .def_property_readonly("joint_names", [](const Robot& r) {
        std::vector<std::string> names;
        for (int j : r.model.variable_joints) names.push_back(r.model.joints[std::size_t(j)].name);
        return names;
      }, "the joint of each configuration variable")
      .def_property_readonly("dof", [](const Robot& r) { return r.checker.kinematics().numVariables(); })
      .def_property_readonly("lower", [](const Robot& r) { return fcl::VectorXd(r.checker.kinematics().lower()); },
                             "lower joint limits ([-pi, pi] for continuous joints)")
      .def_property_readonly("upper", [](const Robot& r) { return fcl::VectorXd(r.checker.kinematics().upper()); })
      .def_property_readonly("pairs", [](const Robot& r) { return r.checker.pairs(); },
                             "the link index pairs every check tests")
      .def(
          "random_configurations",
          [](const Robot& r, long long n, std::uint64_t seed) {
            if (n < 0) badArgument("fcl_rs.Robot.random_configurations", "n", "must be >= 0, got " + std::to_string(n));
            std::mt19937_64 rng(seed);
            const Kinematics<double>& k = r.checker.kinematics();
            std::vector<double> q;
            q.reserve(std::size_t(n) * std::size_t(k.numVariables()));
            for (int i = 0; i < n; ++i)
            {
              const fcl::VectorXd qi = k.randomConfiguration(rng);
              q.insert(q.end(), qi.data(), qi.data() + qi.size());
            }
            return handOver(std::move(q), {py::ssize_t(n), k.numVariables()});
          },
          py::arg("n"), py::arg("seed"), "(n, dof) configurations uniform within the limits, from a seed.")
      .def(
          "check",
          [](const Robot& r, const py::handle& q) {
            SelfCheckRequest request;
            request.colliding_pairs = true;
            const Doubles values = configurationsOf(q, r.checker.kinematics().numVariables(), false, "fcl_rs.Robot.check");
            return r.checker.query(Eigen::Map<const fcl::VectorXd>(values.data(), values.size()), request).pairs;
          },
          py::arg("q"), "The colliding link index pairs at configuration q (dof,).")
      .def(
          "minimum_distance",
          [](const Robot& r, const py::handle& q) {
            SelfCheckRequest request;
            request.minimum_distance = true;
            const Doubles values =
                configurationsOf(q, r.checker.kinematics().numVariables(), false, "fcl_rs.Robot.minimum_distance");
            return r.checker.query(Eigen::Map<const fcl::VectorXd>(values.data(), values.size()), request)
                .minimum_distance;
          },
          py::arg("q"), "The smallest distance between two checked links at q (0 when colliding).")
      .def(
          "check_batch",
          [](const Robot& r, const py::handle& q, bool pairs, bool minimum_distance, int num_threads) {
            const char* api = "fcl_rs.Robot.check_batch";
            SelfCheckRequest request;
            request.colliding_pairs = pairs;
            request.minimum_distance = minimum_distance;
            const Doubles values = configurationsOf(q, r.checker.kinematics().numVariables(), true, api);
            threadsOf(num_threads, api);
            const Eigen::Map<const Configurations<double>> rows(values.data(), values.shape(0), values.shape(1));
            SelfCollisionBatchResult<double> result;
            {
              py::gil_scoped_release release;
              result = selfCollisionBatch(r.checker, rows, request, {num_threads});
            }
            const py::ssize_t n = py::ssize_t(result.colliding.size());
            py::dict out;
            out["colliding"] = handOver<std::uint8_t, bool>(std::move(result.colliding), {n});
            if (minimum_distance) out["minimum_distance"] = handOver(std::move(result.minimum_distance), {n});
            if (pairs)
            {
              py::list per_row;
              for (auto& p : result.pairs)
              {
                std::vector<int> flat;
                for (const LinkPair& lp : p) flat.insert(flat.end(), {lp.first, lp.second});
                per_row.append(handOver(std::move(flat), {py::ssize_t(p.size()), 2}));
              }
              out["pairs"] = per_row;
            }
            return out;
          },
          py::arg("q"), py::arg("pairs").noconvert() = false, py::arg("minimum_distance").noconvert() = false,
          py::arg("num_threads") = 0,
          "Self-collision of every row of q (N, dof), read in place. Returns a dict: 'colliding' (N,) bool; with\n"
          "pairs=True 'pairs', a list of (k, 2) link index arrays; with minimum_distance=True 'minimum_distance' (N,).\n"
          "num_threads: 0 every core, 1 the calling thread only. Results do not depend on it.");

#if FCL_HAVE_OCTOMAP
  py::class_<OcTreeMap, std::shared_ptr<OcTreeMap>>(
      m, "OcTree",
      "An octomap (occupancy octree) for Environment.add_octree: from (N, 3) occupied points and a resolution, or\n"
      "from a .bt/.ot file. insert() adds sensor data; environments holding the map read it again before their\n"
      "next query.")
      .def(py::init([](const py::handle& points, double resolution) {
             const char* api = "fcl_rs.OcTree";
             auto map = std::make_shared<octomap::OcTree>(sizeOf(resolution, api, "resolution"));
             for (const octomap::point3d& p : pointsIn(*map, points, api, "points")) map->updateNode(p, true);
             return std::make_shared<OcTreeMap>(std::move(map));
           }),
           py::arg("points"), py::arg("resolution"),
           "A map with cells of edge `resolution` in which every (N, 3) point's cell is occupied (one observation\n"
           "each, octomap's updateNode).")
      .def_static(
          "from_file",
          [](const std::string& path) {
            const char* api = "fcl_rs.OcTree.from_file";
            std::shared_ptr<octomap::OcTree> map;
            if (binaryOcTreeFile(path, api))
            {
              map = std::make_shared<octomap::OcTree>(0.1);  // readBinary sets the file's resolution
              if (!map->readBinary(path)) throw std::runtime_error(std::string(api) + ": cannot read '" + path + "'");
            }
            else
            {
              std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(path));
              if (!tree) throw std::runtime_error(std::string(api) + ": cannot read '" + path + "'");
              if (!dynamic_cast<octomap::OcTree*>(tree.get()))
                throw std::runtime_error(std::string(api) + ": '" + path + "' holds a " + tree->getTreeType() +
                                         ", not an OcTree");
              map.reset(static_cast<octomap::OcTree*>(tree.release()));
            }
            return std::make_shared<OcTreeMap>(std::move(map));
          },
          py::arg("path"), "Reads an octomap file: .bt (binary: occupied or free per cell) or .ot (an OcTree).")
      .def(
          "save",
          [](const OcTreeMap& o, const std::string& path) {
            const char* api = "fcl_rs.OcTree.save";
            const bool written = binaryOcTreeFile(path, api) ? o.map->writeBinaryConst(path) : o.map->write(path);
            if (!written) throw std::runtime_error(std::string(api) + ": cannot write '" + path + "'");
          },
          py::arg("path"),
          "Writes the map: .bt (binary, each cell occupied or free by the map's threshold) or .ot (full occupancy).")
      .def(
          "insert",
          [](OcTreeMap& o, const py::handle& points, const py::handle& sensor_origin) {
            const char* api = "fcl_rs.OcTree.insert";
            const octomap::Pointcloud cloud = pointsIn(*o.map, points, api, "points");
            std::optional<octomap::point3d> origin;
            if (!sensor_origin.is_none())
            {
              const fcl::Vector3d xyz = pointOf(sensor_origin, api, "sensor_origin");
              origin = pointIn(*o.map, xyz.data(), api, "sensor_origin");
            }
            const WorldEdit edit(worldLock());
            if (origin)
              o.map->insertPointCloud(cloud, *origin);
            else
              for (const octomap::point3d& p : cloud) o.map->updateNode(p, true);
            ++o.version;
          },
          py::arg("points"), py::arg("sensor_origin") = py::none(),
          "Adds (N, 3) points as occupied observations; with a sensor_origin (3,), as a scan from there\n"
          "(octomap's insertPointCloud: the cells along each ray are observed free, the end cells occupied).\n"
          "Environments holding the map read its cells again before their next query.")
      .def_property_readonly("resolution", [](const OcTreeMap& o) { return o.map->getResolution(); })
      .def_property_readonly(
          "num_occupied",
          [](const OcTreeMap& o) {
            std::vector<double> centres, sizes;
            occupiedCells(o, centres, sizes);
            return sizes.size();
          },
          "the number of occupied leaf cells (FCL's occupancy threshold)")
      .def(
          "occupied_cells",
          [](const OcTreeMap& o) {
            std::vector<double> centres, sizes;
            occupiedCells(o, centres, sizes);
            const py::ssize_t n = py::ssize_t(sizes.size());
            return py::make_tuple(handOver(std::move(centres), {n, py::ssize_t(3)}), handOver(std::move(sizes), {n}));
          },
          "The occupied leaf cells (the ones collision and distance queries meet): centres (K, 3) and edge\n"
          "lengths (K,), in the map's frame.");
#endif

  py::class_<PyEnvironment> environment_class(
      m, "Environment",
      "A URDF robot (SRDF disabled pairs and planning groups optional) among named obstacles in its root frame:\n"
      "self and world collision per configuration, minimum distance, and exact motion checks of straight\n"
      "joint-space segments.");
  bindPlanningGroups(environment_class, "fcl_rs.Environment");
  environment_class
      .def(py::init<const std::string&, const std::string&, const std::string&>(), py::arg("urdf"),
           py::arg("srdf") = "", py::arg("bv") = "RS",
           "bv: RS, OBBRSS, OBB or RSS (OBB: no minimum distance and no motion checks); link and obstacle meshes\n"
           "are trees of this type.")
      .def_property_readonly("name", [](const PyEnvironment& e) { return e.model.name; })
      .def_property_readonly("bv", [](const PyEnvironment& e) { return std::string(bvTypeName(e.env.bvType())); })
      .def_property_readonly("dof", [](const PyEnvironment& e) { return dofOf(e); })
      .def_property_readonly("link_names", [](const PyEnvironment& e) { return e.env.selfCollision().linkNames(); })
      .def_property_readonly("joint_names", [](const PyEnvironment& e) {
        std::vector<std::string> names;
        for (int j : e.model.variable_joints) names.push_back(e.model.joints[std::size_t(j)].name);
        return names;
      }, "the joint of each configuration variable")
      .def_property_readonly("lower", [](const PyEnvironment& e) { return fcl::VectorXd(e.env.kinematics().lower()); },
                             "lower joint limits ([-pi, pi] for continuous joints)")
      .def_property_readonly("upper", [](const PyEnvironment& e) { return fcl::VectorXd(e.env.kinematics().upper()); })
      .def_property_readonly("obstacle_names", [](const PyEnvironment& e) { return e.env.obstacleNames(); },
                             "in insertion order")
      .def("__contains__", [](const PyEnvironment& e, const std::string& name) { return e.env.contains(name); },
           py::arg("name"))
      .def(
          "add_shape",
          [](PyEnvironment& e, const std::string& name, const GeometryPtr& shape, const py::handle& pose) {
            const char* api = "fcl_rs.Environment.add_shape";
            requireNewName(e, name, api);
            const fcl::Transform3d tf = poseOf(pose, api, "pose");
            const WorldEdit edit(worldLock());
            // The shape goes through Environment::addShape's own check (the library's one shape switch); what it
            // refuses (a mesh, say) is a fault of this argument.
            try
            {
              e.env.addShape(name, shape, tf);
            }
            catch (const std::invalid_argument& error)
            {
              badArgument(api, "shape", std::string("is refused: ") + error.what());
            }
          },
          py::arg("name"), py::arg("shape").none(false), py::arg("pose"),
          "Adds a Box, Sphere, Ellipsoid, Capsule, Cylinder, Cone, Plane or Halfspace at a 4x4 pose in the robot's\n"
          "root frame (meshes go through add_mesh, octomaps through add_octree).")
      .def(
          "add_mesh",
          [](PyEnvironment& e, const std::string& name, const py::handle& vertices, const py::handle& triangles,
             const py::handle& pose) {
            const char* api = "fcl_rs.Environment.add_mesh";
            requireNewName(e, name, api);
            const TriangleMesh<double> mesh = meshOf(vertices, triangles, api);
            const fcl::Transform3d tf = poseOf(pose, api, "pose");
            const WorldEdit edit(worldLock());
            e.env.addMesh(name, mesh, tf);
          },
          py::arg("name"), py::arg("vertices"), py::arg("triangles"), py::arg("pose"),
          "Adds a mesh ((V, 3) vertices in its own frame, (F, 3) integer vertex indices) at a 4x4 pose, built once\n"
          "as a tree of the environment's BV type.")
#if FCL_HAVE_OCTOMAP
      .def(
          "add_octree",
          [](PyEnvironment& e, const std::string& name, const std::shared_ptr<OcTreeMap>& octree,
             const py::handle& pose) {
            const char* api = "fcl_rs.Environment.add_octree";
            requireNewName(e, name, api);
            const fcl::Transform3d tf = poseOf(pose, api, "pose");
            const WorldEdit edit(worldLock());
            e.env.addOcTree(name, octree->geometry, tf);
            e.octrees[name] = {octree, octree->version};
          },
          py::arg("name"), py::arg("octree").none(false), py::arg("pose"),
          "Adds an OcTree at a 4x4 pose (its cells count as FCL's traversals count them). The environment shares\n"
          "the map: after OcTree.insert it reads the occupied cells again before its next query.")
#endif
      .def(
          "set_pose",
          [](PyEnvironment& e, const std::string& name, const py::handle& pose) {
            const char* api = "fcl_rs.Environment.set_pose";
            requireObstacle(e, name, api);
            const fcl::Transform3d tf = poseOf(pose, api, "pose");
            const WorldEdit edit(worldLock());
            e.env.setPose(name, tf);
          },
          py::arg("name"), py::arg("pose"), "Moves a named obstacle to a 4x4 pose.")
      .def(
          "pose",
          [](const PyEnvironment& e, const std::string& name) {
            requireObstacle(e, name, "fcl_rs.Environment.pose");
            return poseArray(e.env.pose(name));
          },
          py::arg("name"), "A named obstacle's 4x4 pose.")
      .def(
          "remove",
          [](PyEnvironment& e, const std::string& name) {
            requireObstacle(e, name, "fcl_rs.Environment.remove");
            const WorldEdit edit(worldLock());
            e.env.remove(name);
#if FCL_HAVE_OCTOMAP
            e.octrees.erase(name);
#endif
          },
          py::arg("name"), "Removes a named obstacle.")
      .def(
          "query",
          [](PyEnvironment& e, const py::handle& q, bool pairs, bool minimum_distance) {
            const char* api = "fcl_rs.Environment.query";
            const Doubles values = configurationsOf(q, dofOf(e), false, api);
            const EnvironmentRequest request = environmentRequest(e, pairs, minimum_distance, api);
            const fcl::VectorXd qv = Eigen::Map<const fcl::VectorXd>(values.data(), values.size());
            const EnvironmentResult<double> r = e.reading([&] { return e.env.query(qv, request); });
            py::dict out;
            out["colliding"] = r.colliding;
            if (pairs) out["pairs"] = pairList(r.pairs);
            if (minimum_distance)
            {
              out["minimum_distance"] = r.minimum_distance;
              out["nearest_pair"] =
                  r.nearest_pair.link.empty() ? py::object(py::none()) : py::object(pairTuple(r.nearest_pair));
              py::array_t<double> points({2, 3});
              for (int i = 0; i < 2; ++i)
                for (int k = 0; k < 3; ++k) points.mutable_at(i, k) = r.nearest_points[i][k];
              out["nearest_points"] = points;
            }
            return out;
          },
          py::arg("q"), py::arg("pairs").noconvert() = false, py::arg("minimum_distance").noconvert() = false,
          "Self and world collision at q (dof,). Returns a dict: 'colliding'; with pairs=True 'pairs', every\n"
          "colliding (link, other, other_is_link) (self pairs first, then links in model order x obstacles in\n"
          "insertion order); with minimum_distance=True 'minimum_distance' (exact; 0 when colliding, inf with\n"
          "nothing to measure), 'nearest_pair' (None when colliding) and 'nearest_points' (2, 3), link first, root\n"
          "frame.")
      .def(
          "check_batch",
          [](PyEnvironment& e, const py::handle& q, bool pairs, bool minimum_distance, int num_threads) {
            const char* api = "fcl_rs.Environment.check_batch";
            const Doubles values = configurationsOf(q, dofOf(e), true, api);
            const EnvironmentRequest request = environmentRequest(e, pairs, minimum_distance, api);
            threadsOf(num_threads, api);
            const Eigen::Map<const Configurations<double>> rows(values.data(), values.shape(0), values.shape(1));
            EnvironmentBatchResult<double> result =
                e.reading([&] { return environmentBatch(e.env, rows, request, {num_threads}); });
            const py::ssize_t n = py::ssize_t(result.colliding.size());
            py::dict out;
            out["colliding"] = handOver<std::uint8_t, bool>(std::move(result.colliding), {n});
            if (minimum_distance) out["minimum_distance"] = handOver(std::move(result.minimum_distance), {n});
            if (pairs)
            {
              py::list per_row;
              for (const auto& p : result.pairs) per_row.append(pairList(p));
              out["pairs"] = per_row;
            }
            return out;
          },
          py::arg("q"), py::arg("pairs").noconvert() = false, py::arg("minimum_distance").noconvert() = false,
          py::arg("num_threads") = 0,
          "query for every row of q (N, dof), read in place. Returns a dict: 'colliding' (N,) bool; with pairs=True\n"
          "'pairs', a list of lists of (link, other, other_is_link); with minimum_distance=True 'minimum_distance'\n"
          "(N,). num_threads: 0 every core, 1 the calling thread only. Results do not depend on it.")
      .def(
          "check_motion",
          [](PyEnvironment& e, const py::handle& start, const py::handle& end, bool earliest, double tolerance) {
            const char* api = "fcl_rs.Environment.check_motion";
            const Doubles a = configurationsOf(start, dofOf(e), false, api, "start");
            const Doubles b = configurationsOf(end, dofOf(e), false, api, "end");
            const MotionRequest<double> request = motionRequest(e, earliest, tolerance, api);
            const fcl::VectorXd from = Eigen::Map<const fcl::VectorXd>(a.data(), a.size());
            const fcl::VectorXd to = Eigen::Map<const fcl::VectorXd>(b.data(), b.size());
            return motionDict(e.reading([&] { return e.env.checkMotion(from, to, request); }));
          },
          py::arg("start"), py::arg("end"), py::arg("earliest").noconvert() = true, py::arg("tolerance") = 1e-3,
          "Every configuration of the straight segment start -> end (dof,), exactly (no sampling resolution).\n"
          "Returns a dict: 'colliding'; when colliding 'parameter' (a colliding configuration's parameter in\n"
          "[0, 1]) and 'free_until' (every parameter below it is free; with earliest=True within tolerance of\n"
          "'parameter'; earliest=False stops at any colliding configuration); 'configurations_checked' and\n"
          "'distance_queries'.")
      .def(
          "check_path",
          [](PyEnvironment& e, const py::handle& waypoints, bool earliest, double tolerance) {
            const char* api = "fcl_rs.Environment.check_path";
            const Doubles values = configurationsOf(waypoints, dofOf(e), true, api, "waypoints");
            if (values.shape(0) == 0)
              badArgument(api, "waypoints", "must have at least one row, got " + shapeText(values));
            const MotionRequest<double> request = motionRequest(e, earliest, tolerance, api);
            std::vector<fcl::VectorXd> points;
            for (py::ssize_t i = 0; i < values.shape(0); ++i)
              points.push_back(Eigen::Map<const fcl::VectorXd>(values.data() + i * values.shape(1), values.shape(1)));
            return motionDict(e.reading([&] { return e.env.checkPath(points, request); }));
          },
          py::arg("waypoints"), py::arg("earliest").noconvert() = true, py::arg("tolerance") = 1e-3,
          "check_motion along the straight segments through the rows of waypoints (K, dof), K >= 1; 'parameter' and\n"
          "'free_until' are a segment index plus the parameter within that segment.")
      .def(
          "check_motion_batch",
          [](PyEnvironment& e, const py::handle& starts, const py::handle& ends, bool earliest, double tolerance,
             int num_threads) {
            const char* api = "fcl_rs.Environment.check_motion_batch";
            const Doubles a = configurationsOf(starts, dofOf(e), true, api, "starts");
            const Doubles b = configurationsOf(ends, dofOf(e), true, api, "ends", a.shape(0));
            const MotionRequest<double> request = motionRequest(e, earliest, tolerance, api);
            threadsOf(num_threads, api);
            const Eigen::Map<const Configurations<double>> from(a.data(), a.shape(0), a.shape(1));
            const Eigen::Map<const Configurations<double>> to(b.data(), b.shape(0), b.shape(1));
            MotionBatchResult<double> result =
                e.reading([&] { return motionBatch(e.env, from, to, request, {num_threads}); });
            const py::ssize_t n = py::ssize_t(result.colliding.size());
            py::dict out;
            out["colliding"] = handOver<std::uint8_t, bool>(std::move(result.colliding), {n});
            out["parameter"] = handOver(std::move(result.parameter), {n});
            out["free_until"] = handOver(std::move(result.free_until), {n});
            return out;
          },
          py::arg("starts"), py::arg("ends"), py::arg("earliest").noconvert() = true, py::arg("tolerance") = 1e-3,
          py::arg("num_threads") = 0,
          "check_motion for every row pair of starts and ends (N, dof), read in place. Returns a dict of (N,)\n"
          "arrays: 'colliding' (bool), 'parameter' (0 for a free segment), 'free_until' (1 for a free segment).\n"
          "num_threads: 0 every core, 1 the calling thread only. Results do not depend on it.");
}
