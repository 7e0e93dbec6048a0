// The Python module fcl_rs (pybind11): RS meshes, FCL shapes, collide/distance, batches and robots, in double.
// Arrays come in and go out as numpy arrays; batch inputs are read in place and outputs are handed over
// without a copy. C++ exceptions keep their messages (invalid_argument -> ValueError, runtime_error ->
// RuntimeError).
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>
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
BVType robotBVType(const std::string& name)
{
  const BVType bv = parseBVType(name);
  if (bv != BVType::kKDOP18) return bv;
  std::string names;
  for (BVType other : kRobotBVTypes)
    if (other != BVType::kKDOP18) names += std::string(names.empty() ? "" : ", ") + bvTypeName(other);
  throw std::invalid_argument("fcl_rs.Robot: bv 'KDOP18' is not supported (its trees are refitted in place per "
                              "check, so checks could not share them across threads); use one of " + names);
}

/// A robot loaded from URDF (and SRDF), with its self-collision checker.
struct Robot
{
  Robot(const std::string& urdf, const std::string& srdf, const std::string& bv)
    : model(loadUrdf(urdf)),
      checker(model, robotBVType(bv), srdf.empty() ? std::vector<DisabledCollision>{}
                                                   : loadDisabledCollisions(srdf, model))
  {
  }
  RobotModel model;
  SelfCollision<double> checker;
};

/// A configuration (dof,) or configurations (N, dof) of a robot with `dof` variables: real numbers, finite.
Doubles configurationsOf(const py::handle& obj, int dof, bool batch, const std::string& api)
{
  const py::array a = realArray(obj, api, "q");
  if (batch)
    requireShape(a, {-1, dof}, api, "q", "(N, " + std::to_string(dof) + ")");
  else
    requireShape(a, {dof}, api, "q", "(" + std::to_string(dof) + ",)");
  Doubles values = doublesOf(a);
  requireFinite(values, api, "q");
  return values;
}

}  // namespace
}  // namespace fcl_rs

PYBIND11_MODULE(fcl_rs, m)
{
  using namespace fcl_rs;
  m.doc() = "RS bounding-volume trees for FCL: collision and distance queries, batches on every core, robots.";
  m.attr("__version__") = FCL_RS_VERSION;

  py::class_<Geometry, GeometryPtr>(m, "Geometry", "Any collision geometry: an RS mesh or an FCL shape.");

  py::class_<fcl::BVHModel<RSd>, Geometry, std::shared_ptr<fcl::BVHModel<RSd>>>(
      m, "Mesh", "A triangle mesh with an RS bounding-volume tree (surface-area splits).")
      .def(py::init([](const py::handle& vertices_arg, const py::handle& triangles_arg) {
             const char* api = "fcl_rs.Mesh";
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
             return buildModel<RSd>(mesh);
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

  py::class_<Robot>(m, "Robot", "A URDF robot (SRDF disabled pairs optional) with a self-collision checker.")
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
}
