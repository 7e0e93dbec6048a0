// The Python module fcl_rs (pybind11): RS meshes, FCL shapes, collide/distance, batches and robots, in double.
// Arrays come in and go out as numpy arrays; batch inputs are read in place and outputs are handed over
// without a copy. C++ exceptions keep their messages (invalid_argument -> ValueError, runtime_error ->
// RuntimeError).
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
#include "fcl_rs/robot/batch_environment.h"
#include "fcl_rs/robot/batch_self_collision.h"
#include "fcl_rs/version.h"

namespace py = pybind11;

namespace fcl_rs {
namespace {

using Geometry = fcl::CollisionGeometryd;
using GeometryPtr = std::shared_ptr<Geometry>;
using Poses = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A numpy array that owns `values` (moved, not copied).
template <typename T, typename Out = T>
py::array_t<Out> handOver(std::vector<T>&& values, std::vector<py::ssize_t> shape)
{
  static_assert(sizeof(T) == sizeof(Out), "the numpy dtype must have the vector's layout");
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<Out>(shape, reinterpret_cast<const Out*>(owned->data()), free_when_done);
}

fcl::Transform3d poseOf(const Poses& m, const char* name)
{
  if (m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4)
    throw std::invalid_argument(std::string("fcl_rs: ") + name + " must be a 4x4 matrix");
  fcl::Transform3d tf;
  // numpy is row-major, Eigen's transform storage column-major.
  tf.matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m.data());
  return tf;
}

std::vector<fcl::Transform3d> posesOf(const Poses& m, const char* name)
{
  if (m.ndim() != 3 || m.shape(1) != 4 || m.shape(2) != 4)
    throw std::invalid_argument(std::string("fcl_rs: ") + name + " must have shape (N, 4, 4), got ndim " +
                                std::to_string(m.ndim()));
  std::vector<fcl::Transform3d> poses(std::size_t(m.shape(0)));
  for (std::size_t i = 0; i < poses.size(); ++i)
    poses[i].matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m.data() + 16 * i);
  return poses;
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

/// A robot loaded from URDF (and SRDF) among named obstacles.
struct PyEnvironment
{
  PyEnvironment(const std::string& urdf, const std::string& srdf, const std::string& bv)
    : model(loadUrdf(urdf)),
      env(model, robotBVType(bv), srdf.empty() ? std::vector<DisabledCollision>{} : loadDisabledCollisions(srdf, model))
  {
  }
  RobotModel model;
  Environment<double> env;
};

py::tuple pairTuple(const BodyPair& p)
{
  return py::make_tuple(p.link, p.other, p.other_is_link);
}

using ConfigurationArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

Eigen::Map<const Configurations<double>> configurationsOf(const ConfigurationArray& q)
{
  if (q.ndim() != 2) throw std::invalid_argument("fcl_rs: configurations must have shape (N, dof)");
  return {q.data(), q.shape(0), q.shape(1)};
}

fcl::VectorXd configurationOf(const ConfigurationArray& q)
{
  if (q.ndim() != 1) throw std::invalid_argument("fcl_rs: a configuration must have shape (dof,)");
  return Eigen::Map<const fcl::VectorXd>(q.data(), q.shape(0));
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
      .def(py::init([](const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
                       const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& triangles) {
             if (vertices.ndim() != 2 || vertices.shape(1) != 3)
               throw std::invalid_argument("fcl_rs.Mesh: vertices must have shape (V, 3)");
             if (triangles.ndim() != 2 || triangles.shape(1) != 3)
               throw std::invalid_argument("fcl_rs.Mesh: triangles must have shape (F, 3)");
             TriangleMesh<double> mesh;
             for (py::ssize_t i = 0; i < vertices.shape(0); ++i)
               mesh.vertices.emplace_back(vertices.at(i, 0), vertices.at(i, 1), vertices.at(i, 2));
             for (py::ssize_t i = 0; i < triangles.shape(0); ++i)
             {
               for (int k = 0; k < 3; ++k)
                 if (triangles.at(i, k) < 0 || triangles.at(i, k) > std::int64_t(INT32_MAX))
                   throw std::invalid_argument("fcl_rs.Mesh: triangle " + std::to_string(i) +
                                               " has a negative or too large index " +
                                               std::to_string(triangles.at(i, k)));
               mesh.triangles.emplace_back(std::size_t(triangles.at(i, 0)), std::size_t(triangles.at(i, 1)),
                                           std::size_t(triangles.at(i, 2)));
             }
             return buildModel<RSd>(mesh);
           }),
           py::arg("vertices"), py::arg("triangles"),
           "Builds the tree over (V, 3) vertices and (F, 3) vertex indices. Raises ValueError for an empty mesh, "
           "a non-finite vertex or an index out of range.")
      .def_static(
          "from_file", [](const std::string& path) { return buildModel<RSd>(loadMesh<double>(path)); },
          py::arg("path"), "Loads every mesh of a file assimp reads (OBJ, STL, PLY, DAE, ...) into one tree.")
      .def_property_readonly("num_vertices", [](const fcl::BVHModel<RSd>& b) { return b.num_vertices; })
      .def_property_readonly("num_triangles", [](const fcl::BVHModel<RSd>& b) { return b.num_tris; });

  py::class_<fcl::Boxd, Geometry, std::shared_ptr<fcl::Boxd>>(m, "Box", "FCL box centred at its origin.")
      .def(py::init<double, double, double>(), py::arg("x"), py::arg("y"), py::arg("z"));
  py::class_<fcl::Sphered, Geometry, std::shared_ptr<fcl::Sphered>>(m, "Sphere", "FCL sphere.")
      .def(py::init<double>(), py::arg("radius"));
  py::class_<fcl::Ellipsoidd, Geometry, std::shared_ptr<fcl::Ellipsoidd>>(m, "Ellipsoid", "FCL ellipsoid.")
      .def(py::init<double, double, double>(), py::arg("a"), py::arg("b"), py::arg("c"));
  py::class_<fcl::Capsuled, Geometry, std::shared_ptr<fcl::Capsuled>>(m, "Capsule", "FCL capsule along z.")
      .def(py::init<double, double>(), py::arg("radius"), py::arg("length"));
  py::class_<fcl::Cylinderd, Geometry, std::shared_ptr<fcl::Cylinderd>>(m, "Cylinder", "FCL cylinder along z.")
      .def(py::init<double, double>(), py::arg("radius"), py::arg("length"));
  py::class_<fcl::Coned, Geometry, std::shared_ptr<fcl::Coned>>(m, "Cone", "FCL cone along z.")
      .def(py::init<double, double>(), py::arg("radius"), py::arg("length"));

  py::class_<fcl::Contactd>(m, "Contact", "One contact, as in python-fcl.")
      .def_readonly("b1", &fcl::Contactd::b1, "triangle of the first geometry (meshes), else -1")
      .def_readonly("b2", &fcl::Contactd::b2, "triangle of the second geometry (meshes), else -1")
      .def_property_readonly("pos", [](const fcl::Contactd& c) { return vector3(c.pos); }, "world-frame point")
      .def_property_readonly("normal", [](const fcl::Contactd& c) { return vector3(c.normal); },
                             "world-frame normal, from the first geometry to the second")
      .def_readonly("penetration_depth", &fcl::Contactd::penetration_depth);

  py::class_<fcl::CollisionRequestd>(m, "CollisionRequest", "fcl::CollisionRequest: contact count and geometry.")
      .def(py::init([](std::size_t num_max_contacts, bool enable_contact) {
             return fcl::CollisionRequestd(num_max_contacts, enable_contact);
           }),
           py::arg("num_max_contacts") = 1, py::arg("enable_contact") = false)
      .def_readwrite("num_max_contacts", &fcl::CollisionRequestd::num_max_contacts)
      .def_readwrite("enable_contact", &fcl::CollisionRequestd::enable_contact);

  py::class_<fcl::CollisionResultd>(m, "CollisionResult", "fcl::CollisionResult.")
      .def_property_readonly("is_collision", &fcl::CollisionResultd::isCollision)
      .def_property_readonly("contacts", [](const fcl::CollisionResultd& r) {
        std::vector<fcl::Contactd> contacts;
        for (std::size_t i = 0; i < r.numContacts(); ++i) contacts.push_back(r.getContact(i));
        return contacts;
      });

  py::class_<fcl::DistanceRequestd>(m, "DistanceRequest", "fcl::DistanceRequest.")
      .def(py::init([](bool enable_nearest_points, bool enable_signed_distance, double rel_err, double abs_err) {
             fcl::DistanceRequestd r(enable_nearest_points, enable_signed_distance, rel_err, abs_err);
             return r;
           }),
           py::arg("enable_nearest_points") = false, py::arg("enable_signed_distance") = false,
           py::arg("rel_err") = 0.0, py::arg("abs_err") = 0.0)
      .def_readwrite("enable_nearest_points", &fcl::DistanceRequestd::enable_nearest_points)
      .def_readwrite("enable_signed_distance", &fcl::DistanceRequestd::enable_signed_distance)
      .def_readwrite("rel_err", &fcl::DistanceRequestd::rel_err)
      .def_readwrite("abs_err", &fcl::DistanceRequestd::abs_err);

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
      [](const GeometryPtr& a, const Poses& pose_a, const GeometryPtr& b, const Poses& pose_b,
         const fcl::CollisionRequestd& request) {
        fcl::CollisionResultd result;
        fcl_rs::collide(a.get(), poseOf(pose_a, "pose_a"), b.get(), poseOf(pose_b, "pose_b"), request, result);
        return result;
      },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"),
      py::arg("request") = fcl::CollisionRequestd(),
      "fcl_rs::collide of two geometries at 4x4 poses; returns a CollisionResult.");
  m.def(
      "distance",
      [](const GeometryPtr& a, const Poses& pose_a, const GeometryPtr& b, const Poses& pose_b,
         const fcl::DistanceRequestd& request) {
        fcl::DistanceResultd result;
        fcl_rs::distance(a.get(), poseOf(pose_a, "pose_a"), b.get(), poseOf(pose_b, "pose_b"), request, result);
        return result;
      },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"),
      py::arg("request") = fcl::DistanceRequestd(),
      "fcl_rs::distance of two geometries at 4x4 poses; returns a DistanceResult (0 when colliding).");

  m.def(
      "collide_batch",
      [](const GeometryPtr& a, const Poses& poses_a, const GeometryPtr& b, const Poses& poses_b, int num_threads) {
        const auto pa = posesOf(poses_a, "poses_a"), pb = posesOf(poses_b, "poses_b");
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
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("num_threads") = 0,
      "Whether a at poses_a[i] and b at poses_b[i] collide, for (N, 4, 4) pose arrays; a bool array (N,).\n"
      "num_threads: 0 every core, 1 the calling thread only. Results do not depend on it.");
  m.def(
      "distance_batch",
      [](const GeometryPtr& a, const Poses& poses_a, const GeometryPtr& b, const Poses& poses_b, int num_threads) {
        const auto pa = posesOf(poses_a, "poses_a"), pb = posesOf(poses_b, "poses_b");
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
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("num_threads") = 0,
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
          [](const Robot& r, int n, std::uint64_t seed) {
            std::mt19937_64 rng(seed);
            const Kinematics<double>& k = r.checker.kinematics();
            std::vector<double> q;
            q.reserve(std::size_t(n) * std::size_t(k.numVariables()));
            for (int i = 0; i < n; ++i)
            {
              const fcl::VectorXd qi = k.randomConfiguration(rng);
              q.insert(q.end(), qi.data(), qi.data() + qi.size());
            }
            return handOver(std::move(q), {n, k.numVariables()});
          },
          py::arg("n"), py::arg("seed"), "(n, dof) configurations uniform within the limits, from a seed.")
      .def(
          "check",
          [](const Robot& r, const ConfigurationArray& q) {
            SelfCheckRequest request;
            request.colliding_pairs = true;
            return r.checker.query(configurationOf(q), request).pairs;
          },
          py::arg("q"), "The colliding link index pairs at configuration q (dof,).")
      .def(
          "minimum_distance",
          [](const Robot& r, const ConfigurationArray& q) {
            SelfCheckRequest request;
            request.minimum_distance = true;
            return r.checker.query(configurationOf(q), request).minimum_distance;
          },
          py::arg("q"), "The smallest distance between two checked links at q (0 when colliding).")
      .def(
          "check_batch",
          [](const Robot& r, const ConfigurationArray& q, bool pairs, bool minimum_distance, int num_threads) {
            SelfCheckRequest request;
            request.colliding_pairs = pairs;
            request.minimum_distance = minimum_distance;
            const auto rows = configurationsOf(q);
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
          py::arg("q"), py::arg("pairs") = false, py::arg("minimum_distance") = false, py::arg("num_threads") = 0,
          "Self-collision of every row of q (N, dof), read in place. Returns a dict: 'colliding' (N,) bool; with\n"
          "pairs=True 'pairs', a list of (k, 2) link index arrays; with minimum_distance=True 'minimum_distance' (N,).\n"
          "num_threads: 0 every core, 1 the calling thread only. Results do not depend on it.");

  py::class_<PyEnvironment>(m, "Environment",
                            "A URDF robot among named obstacles: self and world collision per configuration, minimum\n"
                            "distance, and exact motion checks of straight joint-space segments.")
      .def(py::init<const std::string&, const std::string&, const std::string&>(), py::arg("urdf"),
           py::arg("srdf") = "", py::arg("bv") = "RS",
           "bv: RS, OBBRSS, OBB or RSS (OBB: no distances and no motion checks); obstacle meshes use it too.")
      .def_property_readonly("dof", [](const PyEnvironment& e) { return e.env.kinematics().numVariables(); })
      .def_property_readonly("link_names", [](const PyEnvironment& e) { return e.env.selfCollision().linkNames(); })
      .def_property_readonly("lower", [](const PyEnvironment& e) { return fcl::VectorXd(e.env.kinematics().lower()); })
      .def_property_readonly("upper", [](const PyEnvironment& e) { return fcl::VectorXd(e.env.kinematics().upper()); })
      .def_property_readonly("obstacle_names", [](const PyEnvironment& e) { return e.env.obstacleNames(); })
      .def(
          "add_shape",
          [](PyEnvironment& e, const std::string& name, const GeometryPtr& shape, const Poses& pose) {
            e.env.addShape(name, shape, poseOf(pose, "pose"));
          },
          py::arg("name"), py::arg("shape"), py::arg("pose"),
          "Adds a Box, Sphere, Cylinder, Capsule, Cone or Ellipsoid at a 4x4 pose in the robot's root frame.")
      .def(
          "add_mesh",
          [](PyEnvironment& e, const std::string& name,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& vertices,
             const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& triangles, const Poses& pose) {
            if (vertices.ndim() != 2 || vertices.shape(1) != 3)
              throw std::invalid_argument("fcl_rs.Environment.add_mesh: vertices must have shape (V, 3)");
            if (triangles.ndim() != 2 || triangles.shape(1) != 3)
              throw std::invalid_argument("fcl_rs.Environment.add_mesh: triangles must have shape (F, 3)");
            TriangleMesh<double> mesh;
            for (py::ssize_t i = 0; i < vertices.shape(0); ++i)
              mesh.vertices.emplace_back(vertices.at(i, 0), vertices.at(i, 1), vertices.at(i, 2));
            for (py::ssize_t i = 0; i < triangles.shape(0); ++i)
            {
              for (int k = 0; k < 3; ++k)
                if (triangles.at(i, k) < 0 || triangles.at(i, k) > std::int64_t(INT32_MAX))
                  throw std::invalid_argument("fcl_rs.Environment.add_mesh: triangle " + std::to_string(i) +
                                              " has a negative or too large index");
              mesh.triangles.emplace_back(std::size_t(triangles.at(i, 0)), std::size_t(triangles.at(i, 1)),
                                          std::size_t(triangles.at(i, 2)));
            }
            e.env.addMesh(name, mesh, poseOf(pose, "pose"));
          },
          py::arg("name"), py::arg("vertices"), py::arg("triangles"), py::arg("pose"),
          "Adds a mesh ((V, 3) vertices, (F, 3) indices), built as a tree of the environment's BV type.")
      .def(
          "set_pose", [](PyEnvironment& e, const std::string& name, const Poses& pose) {
            e.env.setPose(name, poseOf(pose, "pose"));
          },
          py::arg("name"), py::arg("pose"), "Moves a named obstacle.")
      .def("remove", [](PyEnvironment& e, const std::string& name) { e.env.remove(name); }, py::arg("name"))
      .def(
          "query",
          [](const PyEnvironment& e, const ConfigurationArray& q, bool pairs, bool minimum_distance) {
            EnvironmentRequest request;
            request.colliding_pairs = pairs;
            request.minimum_distance = minimum_distance;
            const EnvironmentResult<double> r = e.env.query(configurationOf(q), request);
            py::dict out;
            out["colliding"] = r.colliding;
            if (pairs)
            {
              py::list list;
              for (const BodyPair& p : r.pairs) list.append(pairTuple(p));
              out["pairs"] = list;
            }
            if (minimum_distance)
            {
              out["minimum_distance"] = r.minimum_distance;
              out["nearest_pair"] = r.nearest_pair.link.empty() ? py::object(py::none()) : py::object(pairTuple(r.nearest_pair));
              py::array_t<double> points({2, 3});
              for (int i = 0; i < 2; ++i)
                for (int k = 0; k < 3; ++k) points.mutable_at(i, k) = r.nearest_points[i][k];
              out["nearest_points"] = points;
            }
            return out;
          },
          py::arg("q"), py::arg("pairs") = false, py::arg("minimum_distance") = false,
          "Self and world collision at q (dof,). Returns a dict: 'colliding'; with pairs=True 'pairs', a list of\n"
          "(link, other, other_is_link); with minimum_distance=True 'minimum_distance', 'nearest_pair' and\n"
          "'nearest_points' (2, 3), link first, root frame.")
      .def(
          "check_batch",
          [](const PyEnvironment& e, const ConfigurationArray& q, bool minimum_distance, int num_threads) {
            EnvironmentRequest request;
            request.minimum_distance = minimum_distance;
            const auto rows = configurationsOf(q);
            EnvironmentBatchResult<double> result;
            {
              py::gil_scoped_release release;
              result = environmentBatch(e.env, rows, request, {num_threads});
            }
            const py::ssize_t n = py::ssize_t(result.colliding.size());
            py::dict out;
            out["colliding"] = handOver<std::uint8_t, bool>(std::move(result.colliding), {n});
            if (minimum_distance) out["minimum_distance"] = handOver(std::move(result.minimum_distance), {n});
            return out;
          },
          py::arg("q"), py::arg("minimum_distance") = false, py::arg("num_threads") = 0,
          "query for every row of q (N, dof), on every core. Returns a dict: 'colliding' (N,) bool and with\n"
          "minimum_distance=True 'minimum_distance' (N,).")
      .def(
          "check_motion",
          [](const PyEnvironment& e, const ConfigurationArray& start, const ConfigurationArray& end, bool earliest,
             double tolerance) {
            MotionRequest<double> request;
            request.earliest = earliest;
            request.tolerance = tolerance;
            const MotionResult<double> r = e.env.checkMotion(configurationOf(start), configurationOf(end), request);
            py::dict out;
            out["colliding"] = r.colliding;
            out["parameter"] = r.parameter;
            out["free_until"] = r.free_until;
            return out;
          },
          py::arg("start"), py::arg("end"), py::arg("earliest") = true, py::arg("tolerance") = 1e-3,
          "Every configuration of the straight segment start -> end, exactly (no sampling resolution). Returns a\n"
          "dict: 'colliding'; 'parameter' (a colliding configuration's parameter in [0, 1]) and 'free_until'\n"
          "(everything below it is free; with earliest=True within tolerance of 'parameter').")
      .def(
          "check_path",
          [](const PyEnvironment& e, const ConfigurationArray& waypoints, bool earliest, double tolerance) {
            const auto rows = configurationsOf(waypoints);
            std::vector<fcl::VectorXd> points;
            for (Eigen::Index i = 0; i < rows.rows(); ++i) points.push_back(rows.row(i).transpose());
            MotionRequest<double> request;
            request.earliest = earliest;
            request.tolerance = tolerance;
            const MotionResult<double> r = e.env.checkPath(points, request);
            py::dict out;
            out["colliding"] = r.colliding;
            out["parameter"] = r.parameter;
            out["free_until"] = r.free_until;
            return out;
          },
          py::arg("waypoints"), py::arg("earliest") = true, py::arg("tolerance") = 1e-3,
          "check_motion along the segments through the rows of waypoints (K, dof); 'parameter' is segment index\n"
          "plus the parameter within it.")
      .def(
          "check_motion_batch",
          [](const PyEnvironment& e, const ConfigurationArray& starts, const ConfigurationArray& ends, bool earliest,
             double tolerance, int num_threads) {
            MotionRequest<double> request;
            request.earliest = earliest;
            request.tolerance = tolerance;
            const auto a = configurationsOf(starts);
            const auto b = configurationsOf(ends);
            MotionBatchResult<double> result;
            {
              py::gil_scoped_release release;
              result = motionBatch(e.env, a, b, request, {num_threads});
            }
            const py::ssize_t n = py::ssize_t(result.colliding.size());
            py::dict out;
            out["colliding"] = handOver<std::uint8_t, bool>(std::move(result.colliding), {n});
            out["parameter"] = handOver(std::move(result.parameter), {n});
            out["free_until"] = handOver(std::move(result.free_until), {n});
            return out;
          },
          py::arg("starts"), py::arg("ends"), py::arg("earliest") = false, py::arg("tolerance") = 1e-3,
          py::arg("num_threads") = 0,
          "check_motion for every row pair of starts and ends (N, dof), on every core. Returns a dict of (N,)\n"
          "arrays: 'colliding', 'parameter', 'free_until'.");
}
