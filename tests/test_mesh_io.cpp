// Mesh loading, validation and refits: real files load; bad files, bad meshes and bad refits get errors that
// name the problem, and leave an already built model answering exactly as before.
#include <cstdint>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

using test::messageOf;

TEST(MeshIo, LoadsAssimpTestModels)
{
  const std::string box = test::assimpModel("OBJ/box.obj");
  ASSERT_FALSE(box.empty()) << "Debian's assimp-testmodels are required (the project's scripts install them)";
  const auto mesh = loadMesh<double>(box);
  EXPECT_EQ(mesh.triangles.size(), 12u);  // six quads, triangulated
  EXPECT_EQ(mesh.vertices.size(), 8u);    // identical vertices joined
  const auto spider = loadMesh<float>(test::assimpModel("STL/Spider_binary.stl"));
  EXPECT_GT(spider.triangles.size(), 1000u);
  validateMesh(spider.vertices, spider.triangles);
}

TEST(MeshIo, LoadsSharedModels)
{
  const std::string rob = test::sharedData("models/fcl_rob.obj");
  if (rob.empty()) FCL_RS_MISSING_SHARED_DATA("models/fcl_rob.obj");
  const auto mesh = loadMesh<double>(rob);
  EXPECT_EQ(mesh.triangles.size(), 216u);  // as SOURCES.md counts with assimp
  const auto link = loadMesh<double>(test::sharedData("robots/panda/meshes/collision/link1.stl"));
  EXPECT_EQ(link.triangles.size(), 300u);
}

std::string writeFile(const std::string& name, const std::string& content)
{
  const std::string path = ::testing::TempDir() + "fcl_rs_mesh_io_" + name;
  std::ofstream out(path, std::ios::binary);
  out << content;
  return path;
}

const char* const kPlyHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(MeshIo, BadFilesNameTheFileAndTheProblem)
{
  struct Case
  {
    std::string path;
    std::string problem;  // must appear in the message, beside the path
  };
  std::vector<Case> cases = {
      {"/nonexistent/dir/mesh.obj", "Unable to open"},
      {::testing::TempDir(), "cannot read"},  // a directory
      {writeFile("empty.obj", ""), "cannot read"},
      {writeFile("empty.stl", ""), "cannot read"},
      {writeFile("corrupt.stl", "solid broken\n facet normal 0 0 nonsense\n"), "cannot read"},
      {writeFile("garbage.ply", std::string("ply\nformat binary_little_endian 1.0\nelement vertex 99999\n") +
                                    "property float x\nend_header\n\x01\x02\x03"),
       "cannot read"},
      // Headers declaring more elements than the file has bytes: assimp would allocate them first (fuzz_mesh_load
      // found a 310-byte OFF file that took 16 GB).
      {writeFile("huge.off", "OFF\n353535235358 6 0\n-0.5 -0.5 0.5\n0.5 -0.5 0.5\n"), "declares 353535235358 vertices"},
      {writeFile("huge_faces.off", "COFF\n# a comment\n3 4000000000 0\n0 0 0\n1 0 0\n0 1 0\n"), "declares 4000000000 faces"},
      {writeFile("huge.ply", std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n") +
                                 "element face 100000000000\nproperty list uchar int vertex_indices\nend_header\n"),
       "declares 100000000000 'face' elements but the file has only"},
      // A PLY header without end_header: assimp's reader would loop forever (found by fuzz_mesh_load).
      {writeFile("unended.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproper 0.0 0 1\n"
                                "0\n1\n2\n"),
       "its PLY header has no end_header line"},
      // Non-triangle faces: points and lines only (polygons are triangulated, see below).
      {writeFile("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n"), "no triangles (0 point and 2 line"},
      {writeFile("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1\np 2 3\n"), "no triangles (3 point and 0 line"},
      {test::assimpModel("OBJ/testline.obj"), "no triangles"},
      {test::assimpModel("OBJ/testpoints.obj"), "no triangles"},
      {test::assimpModel("OBJ/point_cloud.obj"), "no faces"},
      // Face indices out of range: the OBJ parser and assimp's validation of any format.
      {writeFile("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"), "index out of range"},
      {writeFile("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9\n"), "index out of range"},
      {writeFile("index.ply", std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"), "mIndices[2] is out of range"},
      // Non-finite coordinates, named by vertex (joining identical vertices would otherwise swallow a NaN).
      {writeFile("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"), "vertex 2 of mesh 0 has a non-finite"},
      {writeFile("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -inf\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"), "vertex 2 of mesh 0 has a non-finite"},
      {writeFile("nan.ply", std::string(kPlyHeader) + "0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"), "vertex 2 of mesh 0 has a non-finite"},
      {writeFile("nan.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 nan\n"
                            "endloop\nendfacet\nendsolid x\n"),
       "vertex 2 of mesh 0 has a non-finite"},
  };
  {
    // Binary STL whose header promises 1000 triangles but holds one.
    std::string stl(80, ' ');
    const std::uint32_t count = 1000;
    stl.append(reinterpret_cast<const char*>(&count), 4);
    stl.append(50, '\0');
    cases.push_back({writeFile("truncated.stl", stl), "cannot read"});
  }
  for (const auto& c : cases)
  {
    ASSERT_FALSE(c.path.empty()) << "a Debian assimp-testmodels file is missing (the project's scripts install them)";
    const std::string msg = messageOf([&] {
      try
      {
        loadMesh<double>(c.path);
      }
      catch (const std::runtime_error&)
      {
        throw;
      }
      catch (...)
      {
        ADD_FAILURE() << c.path << ": not a std::runtime_error";
      }
    });
    EXPECT_NE(msg.find("'" + c.path + "'"), std::string::npos) << "message '" << msg << "' does not name " << c.path;
    EXPECT_NE(msg.find(c.problem), std::string::npos) << "message '" << msg << "' lacks '" << c.problem << "'";
  }
}

TEST(MeshIo, PolygonsAreTriangulatedAndStrayLinesDropped)
{
  const auto poly = loadMesh<double>(writeFile("polygon.obj", "v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.6 0\nv -0.5 1 0\n"
                                                              "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 2 3 4 5\nf 6 7 8 9\n"));
  EXPECT_EQ(poly.triangles.size(), 5u);  // a pentagon and a quad
  validateMesh(poly.vertices, poly.triangles);
  const auto mixed = loadMesh<float>(writeFile("mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nl 1 4\np 4\n"));
  EXPECT_EQ(mixed.triangles.size(), 1u);
  validateMesh(mixed.vertices, mixed.triangles);
  // One PLY mesh mixing a point face with a quad and a triangle (assimp's SortByPType step crashed on this; found
  // by fuzz_mesh_load).
  const auto points_and_polygons = loadMesh<double>(writeFile(
      "points_and_polygons.ply", std::string("ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty ") +
                                     "float y\nproperty float z\nelement face 3\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 4\n4 0 1 2 3\n3 0 1 4\n"));
  EXPECT_EQ(points_and_polygons.triangles.size(), 3u);
  validateMesh(points_and_polygons.vertices, points_and_polygons.triangles);
}

/// A one-triangle Collada file with the given up axis, in millimetres.
std::string colladaTriangle(const std::string& up_axis)
{
  return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>)" +
         up_axis + R"(</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="a" count="9">0 0 0 1000 0 0 0 0 2000</float_array>
      <technique_common><accessor source="#a" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
}

TEST(MeshIo, ColladaKeepsItsAxesAndAppliesItsUnit)
{
  // As ROS reads a URDF's meshes: the file's coordinates whatever its up axis (assimp alone turns Z_UP and X_UP
  // files to Y up), scaled from millimetres to metres.
  for (const char* up_axis : {"Z_UP", "Y_UP", "X_UP"})
  {
    const std::string file = writeFile(std::string("triangle_") + up_axis + ".dae", colladaTriangle(up_axis));
    const auto mesh = loadMesh<double>(file);
    ASSERT_EQ(mesh.triangles.size(), 1u) << up_axis;
    const std::vector<fcl::Vector3d> expected = {{0, 0, 0}, {1, 0, 0}, {0, 0, 2}};
    for (int k = 0; k < 3; ++k)
      EXPECT_LT((mesh.vertices[mesh.triangles[0][k]] - expected[std::size_t(k)]).norm(), 1e-12)
          << up_axis << " vertex " << k << ": " << mesh.vertices[mesh.triangles[0][k]].transpose();
  }
}

template <typename S>
class BadMeshes : public ::testing::Test
{
};
TYPED_TEST_SUITE(BadMeshes, test::Scalars);

/// The nodes of a model, bit for bit (all members of BVNode).
template <typename BV>
bool sameNodes(const fcl::BVHModel<BV>& m, const std::vector<fcl::BVNode<BV>>& nodes)
{
  if (std::size_t(m.getNumBVs()) != nodes.size()) return false;
  for (int i = 0; i < m.getNumBVs(); ++i)
  {
    const auto &a = m.getBV(i), &b = nodes[std::size_t(i)];
    if (a.bv.axis != b.bv.axis || a.bv.origin != b.bv.origin || a.bv.lo != b.bv.lo || a.bv.hi != b.bv.hi ||
        a.first_child != b.first_child || a.first_primitive != b.first_primitive || a.num_primitives != b.num_primitives)
      return false;
  }
  return true;
}

template <typename BV>
std::vector<fcl::BVNode<BV>> nodesOf(const fcl::BVHModel<BV>& m)
{
  std::vector<fcl::BVNode<BV>> nodes;
  for (int i = 0; i < m.getNumBVs(); ++i) nodes.push_back(m.getBV(i));
  return nodes;
}

/// A built model and its answers to seeded queries against a torus, to compare after failed builds and refits.
template <typename S>
struct Reference
{
  std::shared_ptr<fcl::BVHModel<RS<S>>> model = buildModel<RS<S>>(makeSphere<S>(S(0.5), 10, 20));
  std::shared_ptr<fcl::BVHModel<RS<S>>> torus = buildModel<RS<S>>(makeTorus<S>(S(0.6), S(0.2), 16, 8));
  std::vector<fcl::Transform3<S>> poses;
  std::vector<test::TrianglePairs> answers;
  std::vector<fcl::Vector3<S>> vertices = std::vector<fcl::Vector3<S>>(model->vertices, model->vertices + model->num_vertices);
  std::vector<fcl::BVNode<RS<S>>> nodes = nodesOf(*model);

  explicit Reference(const std::string& what)
  {
    auto rng = test::seededRng(what);
    for (int i = 0; i < 40; ++i)
    {
      poses.push_back(test::randomPose<S>(rng, S(0.8)));
      answers.push_back(query(i));
    }
    int colliding = 0;
    for (const auto& a : answers) colliding += !a.empty();
    EXPECT_GT(colliding, 10) << "guards the comparison: enough poses collide";
  }
  test::TrianglePairs query(int i) const
  {
    fcl::CollisionResult<S> r;
    fcl_rs::collide<S>(model.get(), fcl::Transform3<S>::Identity(), torus.get(), poses[std::size_t(i)],
               fcl::CollisionRequest<S>(100000, false), r);
    return test::contactPairs(r);
  }
  /// The model is bit for bit as built and answers every query as before.
  void expectUnchanged(const std::string& what) const
  {
    EXPECT_EQ(model->build_state, fcl::BVH_BUILD_STATE_PROCESSED) << what;
    EXPECT_TRUE(std::equal(vertices.begin(), vertices.end(), model->vertices)) << what << ": vertices changed";
    EXPECT_TRUE(sameNodes(*model, nodes)) << what << ": tree changed";
    for (std::size_t i = 0; i < poses.size(); ++i) EXPECT_EQ(query(int(i)), answers[i]) << what << ", pose " << i;
  }
};

TYPED_TEST(BadMeshes, RejectedWithTheirIndexAndBuiltModelsStayUnchanged)
{
  using S = TypeParam;
  const Reference<S> ref("mesh_io/bad-meshes");
  const S nan = std::numeric_limits<S>::quiet_NaN(), snan = std::numeric_limits<S>::signaling_NaN(),
          inf = std::numeric_limits<S>::infinity();
  const TriangleMesh<S> good = makeSphere<S>(S(0.5), 6, 8);
  struct Bad
  {
    std::string what;
    TriangleMesh<S> mesh;
    std::string message;  // must appear in the exception's message
  };
  std::vector<Bad> bad;
  for (const auto& [value, name] : {std::make_pair(nan, "NaN"), std::make_pair(snan, "signaling NaN"),
                                    std::make_pair(inf, "+Inf"), std::make_pair(-inf, "-Inf")})
    for (int c = 0; c < 3; ++c)
    {
      Bad b{std::string(name) + " in coordinate " + std::to_string(c), good, "vertex 17 has a non-finite coordinate"};
      b.mesh.vertices[17][c] = value;
      bad.push_back(b);
    }
  {
    Bad b{"last vertex NaN", good, "vertex " + std::to_string(good.vertices.size() - 1) + " has"};
    b.mesh.vertices.back().x() = nan;
    bad.push_back(b);
  }
  for (std::size_t index : {good.vertices.size(), good.vertices.size() + 1, std::size_t(-1)})
  {
    Bad b{"index " + std::to_string(index), good,
          "triangle 5 refers to vertex " + std::to_string(index) + " but the mesh has " +
              std::to_string(good.vertices.size()) + " vertices"};
    b.mesh.triangles[5][1] = index;
    bad.push_back(b);
  }
  bad.push_back({"no vertices, no triangles", TriangleMesh<S>(), "empty mesh (0 vertices, 0 triangles)"});
  {
    Bad b{"vertices but no triangles", good, "empty mesh"};
    b.mesh.triangles.clear();
    bad.push_back(b);
  }
  {
    Bad b{"triangles but no vertices", good, "empty mesh"};
    b.mesh.vertices.clear();
    bad.push_back(b);
  }
  for (const auto& b : bad)
  {
    std::shared_ptr<fcl::BVHModel<RS<S>>> result;
    const std::string msg = messageOf([&] { result = buildModel<RS<S>>(b.mesh); });
    EXPECT_NE(msg.find(b.message), std::string::npos) << b.what << ": message '" << msg << "' lacks '" << b.message << "'";
    EXPECT_THROW(buildModel<RS<S>>(b.mesh), std::invalid_argument) << b.what;
    EXPECT_THROW(buildModel<fcl::OBBRSS<S>>(b.mesh), std::invalid_argument) << b.what;  // any BV type
    EXPECT_EQ(result, nullptr) << b.what;
  }
  ref.expectUnchanged("after failed builds");

  // FCL's own API with a NaN vertex (no validation in front): the RS fitter throws rather than build a tree of
  // NaNs, and fcl_rs::collide then refuses the half-built model instead of traversing it.
  TriangleMesh<S> m = good;
  m.vertices[3].y() = nan;
  fcl::BVHModel<RS<S>> raw;
  raw.beginModel();
  raw.addSubModel(m.vertices, m.triangles);
  EXPECT_ANY_THROW(raw.endModel());
  fcl::CollisionResult<S> res;
  const auto identity = fcl::Transform3<S>::Identity();
  const std::string refused = messageOf([&] {
    fcl_rs::collide<S>(&raw, identity, ref.model.get(), identity, fcl::CollisionRequest<S>(1, false), res);
  });
  EXPECT_NE(refused.find("not built"), std::string::npos) << refused;
  EXPECT_FALSE(res.isCollision());
}

TYPED_TEST(BadMeshes, FailedRefitsLeaveTheModelUnchanged)
{
  using S = TypeParam;
  Reference<S> ref("mesh_io/refit");
  std::vector<fcl::Vector3<S>> moved = ref.vertices;
  const std::size_t n = moved.size();

  // Rejected before anything is touched: wrong count (FCL would write past its array), NaN / Inf vertex.
  moved.push_back(moved.front());
  EXPECT_NE(messageOf([&] { refitModel(*ref.model, moved); }).find(std::to_string(n + 1) + " vertices given for a model of " +
                                                               std::to_string(n)),
            std::string::npos);
  moved.pop_back();
  moved.pop_back();
  EXPECT_THROW(refitModel(*ref.model, moved), std::invalid_argument);
  moved.push_back(ref.vertices.back());
  for (S value : {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity()})
  {
    std::vector<fcl::Vector3<S>> bad = moved;
    bad[7].z() = value;
    for (bool bottomup : {true, false})
      EXPECT_NE(messageOf([&] { refitModel(*ref.model, bad, bottomup); }).find("vertex 7 has a non-finite"), std::string::npos);
  }
  ref.expectUnchanged("after rejected refits");

  // A refit that throws halfway (here: the fitter of a top-down refit, on its 20th node) is rolled back.
  struct ThrowingFitter : fcl::detail::BVFitter<RS<S>>
  {
    int calls = 0;
    RS<S> fit(unsigned int* primitive_indices, int num_primitives) override
    {
      if (++calls == 20) throw std::runtime_error("fitter failed");
      return fcl::detail::BVFitter<RS<S>>::fit(primitive_indices, num_primitives);
    }
  };
  const auto fitter = ref.model->bv_fitter;
  ref.model->bv_fitter = std::make_shared<ThrowingFitter>();
  std::vector<fcl::Vector3<S>> shifted = ref.vertices;
  for (auto& v : shifted) v += fcl::Vector3<S>(S(0.25), 0, 0);
  EXPECT_THROW(refitModel(*ref.model, shifted, false), std::runtime_error);
  ref.model->bv_fitter = fitter;
  ref.expectUnchanged("after a refit that threw halfway");

  // An unbuilt model is refused.
  fcl::BVHModel<RS<S>> unbuilt;
  EXPECT_NE(messageOf([&] { refitModel(unbuilt, shifted); }).find("not in FCL's built state"), std::string::npos);

  // Successful refits: the root contains every moved vertex, and queries equal brute force.
  for (bool bottomup : {true, false})
  {
    refitModel(*ref.model, shifted, bottomup);
    EXPECT_TRUE(std::equal(shifted.begin(), shifted.end(), ref.model->vertices));
    for (const auto& v : shifted) EXPECT_TRUE(ref.model->getBV(0).bv.contain(v));
    TriangleMesh<S> sphere{shifted, std::vector<fcl::Triangle>(ref.model->tri_indices, ref.model->tri_indices + ref.model->num_tris)};
    const TriangleMesh<S> torus{std::vector<fcl::Vector3<S>>(ref.torus->vertices, ref.torus->vertices + ref.torus->num_vertices),
                                std::vector<fcl::Triangle>(ref.torus->tri_indices, ref.torus->tri_indices + ref.torus->num_tris)};
    for (std::size_t i = 0; i < ref.poses.size(); ++i)
      EXPECT_EQ(ref.query(int(i)), test::bruteForcePairs(sphere, fcl::Transform3<S>::Identity(), torus, ref.poses[i]))
          << "refit " << (bottomup ? "bottom-up" : "top-down") << ", pose " << i;
    for (auto& v : shifted) v -= fcl::Vector3<S>(S(0.25), 0, 0);
  }
}

TEST(MeshIo, BuildsEveryBvType)
{
  const auto mesh = makeSphere<double>(1, 8, 12);
  const int nodes = 2 * int(mesh.triangles.size()) - 1;
  EXPECT_EQ(buildModel<RS<double>>(mesh)->getNumBVs(), nodes);
  EXPECT_EQ(buildModel<RS<float>>(makeSphere<float>(1, 8, 12))->getNumBVs(), nodes);
  EXPECT_EQ(buildModel<fcl::OBBRSS<double>>(mesh)->getNumBVs(), nodes);
  EXPECT_EQ((buildModel<fcl::KDOP<double, 18>>(mesh)->getNumBVs()), nodes);
}

TEST(Shapes, GeneratedMeshesAreClosed)
{
  // Every edge of a closed surface is shared by exactly two triangles.
  auto closed = [](const TriangleMesh<double>& m) {
    std::map<std::pair<std::size_t, std::size_t>, int> edges;
    for (const auto& t : m.triangles)
      for (int i = 0; i < 3; ++i)
        edges[std::minmax(t[i], t[(i + 1) % 3])]++;
    for (const auto& e : edges)
      if (e.second != 2) return false;
    return true;
  };
  EXPECT_TRUE(closed(makeSphere<double>(1)));
  EXPECT_EQ(makeSphere<double>(1).triangles.size(), 960u);
  EXPECT_TRUE(closed(makeEllipsoid<double>(1, 2, 3)));
  EXPECT_TRUE(closed(makeBox<double>(1, 2, 3)));
  EXPECT_TRUE(closed(makeTorus<double>(2, 0.5)));
  EXPECT_TRUE(closed(makeDiamond<double>(1, 1)));
}

}  // namespace
}  // namespace fcl_rs
