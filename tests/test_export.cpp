// fcl_rs/export: exact solids of every BV type (bv_polytope.h) and the files of tree levels (export_volumes.h).
#include <map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "fcl_rs/export/export_volumes.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

template <typename S>
class ExportTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(ExportTest, test::Scalars);

/// Whether p is inside the convex solid bounded by the outward triangles, up to tol. Slivers (twice the area
/// below min_area) are skipped: rounding the corners of a tiny triangle turns its plane arbitrarily.
bool insideTriangles(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& triangles,
                     const Eigen::Vector3d& p, double tol, double min_area = 0)
{
  for (const auto& t : triangles)
  {
    const Eigen::Vector3d& a = vertices[std::size_t(t[0])];
    const Eigen::Vector3d n = (vertices[std::size_t(t[1])] - a).cross(vertices[std::size_t(t[2])] - a);
    if (n.norm() > min_area && n.normalized().dot(p - a) > tol) return false;
  }
  return true;
}

std::vector<std::array<int, 3>> trianglesOf(const Polytope& poly)
{
  std::vector<std::array<int, 3>> out;
  for (const auto& t : poly.triangles().triangles) out.push_back({int(t[0]), int(t[1]), int(t[2])});
  return out;
}

std::string tempPath(const std::string& name)
{
  return (std::filesystem::temp_directory_path() / ("fcl_rs_test_export_" + name)).string();
}

TYPED_TEST(ExportTest, RSPolytopeIsTheExactVolumeAndContainsItsPoints)
{
  using S = TypeParam;
  auto rng = test::seededRng("RSPolytopeIsTheExactVolumeAndContainsItsPoints");
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<fcl::Vector3<S>> points;
    const fcl::Vector3<S> scale(S(1 + 3 * std::abs(g(rng))), S(1 + std::abs(g(rng))), S(0.2 + std::abs(g(rng))));
    for (int i = 0; i < 4 + trial % 40; ++i)
      points.push_back(fcl::Vector3<S>(S(g(rng)), S(g(rng)), S(g(rng))).cwiseProduct(scale) +
                       fcl::Vector3<S>::Constant(S(10)));
    const RS<S> bv = fitPoints<S>(points.data(), int(points.size()));
    const Polytope poly = bvPolytope(bv);
    ASSERT_FALSE(poly.empty());
    EXPECT_LE(poly.vertices.size(), 32u);
    // The solid is built in double from the volume's numbers; RS<float>::volume() rounds in float.
    const double tol = std::is_same<S, double>::value ? 1e-9 : 1e-4;
    EXPECT_NEAR(poly.volume(), double(bv.volume()), tol * double(bv.volume())) << "trial " << trial;
    // Slabs are stored in float, each rounded outward on its own: a chamfer can cut within a float ulp of a
    // box corner and leave a facet with edges of ~1e-7, whose normal double rounding fixes only to ~1e-8;
    // such facets (cross product below 1e-4) are skipped, their neighbours' planes bound the points there.
    for (const auto& p : points)
      EXPECT_TRUE(insideTriangles(poly.vertices, trianglesOf(poly), p.template cast<double>(), 1e-9, 1e-4))
          << "trial " << trial;
  }
}

TEST(BVPolytope, RoundVolumesAreCircumscribedWithinTheStatedOvershoot)
{
  // An RSS of a point is a ball: the polytope's farthest points are vertices, so they bound the overshoot.
  fcl::RSS<double> ball;
  ball.axis.setIdentity();
  ball.To = Eigen::Vector3d(1, 2, 3);
  ball.l[0] = ball.l[1] = 0;
  ball.r = 2;
  const Polytope poly = bvPolytope(ball);
  double farthest = 0, nearest = 1e9;
  for (const auto& v : poly.vertices)
  {
    farthest = std::max(farthest, (v - ball.To).norm());
    nearest = std::min(nearest, (v - ball.To).norm());
  }
  EXPECT_LE(farthest, kRoundOvershoot * ball.r);
  EXPECT_GE(nearest, ball.r * (1 - 1e-12));

  // A swept rectangle: at least its exact volume, and no vertex farther from the rectangle than the overshoot.
  fcl::RSS<double> rss;
  rss.axis = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  rss.To = Eigen::Vector3d(-1, 0, 4);
  rss.l[0] = 3;
  rss.l[1] = 1;
  rss.r = 0.5;
  const auto swept = [&](double r) {
    return 2 * r * rss.l[0] * rss.l[1] + M_PI * r * r * (rss.l[0] + rss.l[1]) + 4 * M_PI * r * r * r / 3;
  };
  const Polytope swept_poly = bvPolytope(rss);
  EXPECT_GE(swept_poly.volume(), swept(rss.r));
  for (const auto& v : swept_poly.vertices)
  {
    const Eigen::Vector3d y = rss.axis.transpose() * (v - rss.To);
    const Eigen::Vector3d nearest(std::clamp(y[0], 0.0, rss.l[0]), std::clamp(y[1], 0.0, rss.l[1]), 0);
    EXPECT_LE((y - nearest).norm(), kSweptOvershoot * rss.r);
  }
}

TEST(BVPolytope, KDOP18OfACutBoxIsThatSolid)
{
  // The 18-DOP of makeKdop18Solid's vertices is the solid itself: volume of the box minus its 12 cut prisms
  // and plus back the overlaps at the corners, checked against the solid's own triangles.
  const TriangleMesh<double> solid = makeKdop18Solid<double>(2, 1.5, 1, 0.4);
  fcl::KDOP<double, 18> kdop;
  for (const auto& v : solid.vertices) kdop += v;
  const Polytope poly = bvPolytope(kdop);
  double solid_volume = 0;
  for (const auto& t : solid.triangles)
    solid_volume += solid.vertices[t[0]].dot(solid.vertices[t[1]].cross(solid.vertices[t[2]])) / 6;
  EXPECT_NEAR(poly.volume(), solid_volume, 1e-12 * solid_volume);
  EXPECT_EQ(poly.vertices.size(), 32u);
}

struct ReadVolume
{
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Every mesh of a file, by the name of the node that holds it.
std::map<std::string, ReadVolume> readVolumes(const std::string& path)
{
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  EXPECT_NE(scene, nullptr) << importer.GetErrorString();
  std::map<std::string, ReadVolume> out;
  if (!scene) return out;
  std::vector<const aiNode*> nodes{scene->mRootNode};
  while (!nodes.empty())
  {
    const aiNode* node = nodes.back();
    nodes.pop_back();
    for (unsigned c = 0; c < node->mNumChildren; ++c) nodes.push_back(node->mChildren[c]);
    for (unsigned m = 0; m < node->mNumMeshes; ++m)
    {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
      ReadVolume& v = out[node->mName.C_Str()];
      const int base = int(v.vertices.size());
      for (unsigned i = 0; i < mesh->mNumVertices; ++i)
        v.vertices.emplace_back(mesh->mVertices[i].x, mesh->mVertices[i].y, mesh->mVertices[i].z);
      for (unsigned f = 0; f < mesh->mNumFaces; ++f)
        v.triangles.push_back({base + int(mesh->mFaces[f].mIndices[0]), base + int(mesh->mFaces[f].mIndices[1]),
                               base + int(mesh->mFaces[f].mIndices[2])});
    }
  }
  return out;
}

double volumeOf(const ReadVolume& v)
{
  double six = 0;
  for (const auto& t : v.triangles)
    six += v.vertices[std::size_t(t[0])].dot(v.vertices[std::size_t(t[1])].cross(v.vertices[std::size_t(t[2])]));
  return six / 6;
}

TYPED_TEST(ExportTest, EveryBVTypeWritesALevelThatAssimpReadsBackAndThatContainsItsTriangles)
{
  using S = TypeParam;
  const TriangleMesh<S> mesh = transformed(makeTorus<S>(S(2), S(0.6), 16, 8),
                                           fcl::Transform3<S>(Eigen::AngleAxis<S>(S(0.4), fcl::Vector3<S>::UnitX())));
  for (BVType type : allBVTypes())
  {
    SCOPED_TRACE(bvTypeName(type));
    const VolumeSet set = exportVolumes(mesh, type, NodeSelection{2, -1});
    ASSERT_GE(set.volumes.size(), 2u);
    EXPECT_GE(set.volumeRatio(), 1.0);
    const std::string path = tempPath(std::string(bvTypeName(type)) + (std::is_same<S, float>::value ? "f" : "d") + ".glb");
    writeVolumes({set}, path);
    const auto read = readVolumes(path);
    ASSERT_EQ(read.size(), set.volumes.size() + 1);  // and the mesh
    ASSERT_TRUE(read.count("mesh"));
    EXPECT_EQ(read.at("mesh").triangles.size(), mesh.triangles.size());
    std::size_t covered = 0;
    for (const ExportedVolume& v : set.volumes)
    {
      const std::string name = set.label + " node " + std::to_string(v.node);
      ASSERT_TRUE(read.count(name)) << name;
      const ReadVolume& solid = read.at(name);
      // glTF stores float coordinates: the file's solid is the exact one up to float rounding.
      const double scale = 10, tol = 1e-5 * scale;
      for (int t : v.triangles)
        for (int c = 0; c < 3; ++c)
          EXPECT_TRUE(insideTriangles(solid.vertices, solid.triangles,
                                      set.mesh.vertices[set.mesh.triangles[std::size_t(t)][c]], tol, tol))
              << name << " triangle " << t;
      EXPECT_NEAR(volumeOf(solid), v.volume, 1e-5 * v.volume) << name;
      covered += v.triangles.size();
    }
    EXPECT_EQ(covered, mesh.triangles.size());  // a level covers the mesh once
    std::filesystem::remove(path);
  }
}

TYPED_TEST(ExportTest, RSLevelVolumesAreRSVolume)
{
  using S = TypeParam;
  const TriangleMesh<S> mesh = makeEllipsoid<S>(S(3), S(1.5), S(1), 8, 16);
  auto model = buildModel<RS<S>>(mesh);
  const VolumeSet set = exportModelVolumes(*model, NodeSelection{3, -1}, "RS");
  const double tol = std::is_same<S, double>::value ? 1e-9 : 1e-4;
  for (const ExportedVolume& v : set.volumes)
    EXPECT_NEAR(v.volume, double(model->getBV(v.node).bv.volume()), tol * v.volume) << "node " << v.node;
}

TEST(ExportVolumes, ObjAndPlyLoadInAssimp)
{
  const TriangleMesh<double> mesh = makeSphere<double>(1, 8, 12);
  const VolumeSet rs = exportVolumes(mesh, BVType::kRS, NodeSelection{1, -1}, FrameFit::kTriangleArea);
  const VolumeSet obb = exportVolumes(mesh, BVType::kOBB, NodeSelection{1, -1});
  EXPECT_EQ(rs.label, "RS (area fit)");
  for (const char* ext : {".obj", ".ply"})
  {
    const std::string path = tempPath(std::string("two") + ext);
    writeVolumes({rs, obb}, path);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    ASSERT_NE(scene, nullptr) << ext << ": " << importer.GetErrorString();
    std::size_t faces = 0;
    bool coloured = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    {
      faces += scene->mMeshes[m]->mNumFaces;
      coloured |= scene->mMeshes[m]->HasVertexColors(0);
    }
    std::size_t expected = mesh.triangles.size();
    for (const VolumeSet* set : {&rs, &obb})
      for (const auto& v : set->volumes) expected += v.polytope.triangles().triangles.size();
    EXPECT_EQ(faces, expected) << ext;
    if (std::string(ext) == ".ply")
    {
      EXPECT_TRUE(coloured);
    }
    else
    {
      EXPECT_GE(scene->mNumMaterials, 1 + rs.volumes.size() + obb.volumes.size());  // and assimp's default
    }
    std::filesystem::remove(path);
    std::filesystem::remove(tempPath("two.mtl"));
  }
}

TEST(ExportVolumes, LeavesUnderANodeCoverItsTriangles)
{
  const TriangleMesh<double> mesh = makeTorus<double>(2, 0.5, 12, 6);
  auto model = buildModel<fcl::OBB<double>>(mesh);
  const int left = model->getBV(0).leftChild();
  const VolumeSet set = exportModelVolumes(*model, NodeSelection{0, left}, "OBB");
  std::size_t covered = 0;
  for (const auto& v : set.volumes)
  {
    EXPECT_TRUE(model->getBV(v.node).isLeaf());
    covered += v.triangles.size();
  }
  EXPECT_EQ(covered, std::size_t(model->getBV(left).num_primitives));
}

TEST(ExportVolumes, BadInputGetsAClearError)
{
  const TriangleMesh<double> mesh = makeBox<double>(1, 2, 3);
  try
  {
    parseBVType("sphere");
    ADD_FAILURE() << "unknown type accepted";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("unknown BV type 'sphere' (known: RS, OBB"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parseBVType("kdop18"), BVType::kKDOP18);
  try
  {
    exportVolumes(mesh, BVType::kRS, NodeSelection{40, -1});
    ADD_FAILURE() << "level 40 accepted";
  }
  catch (const std::out_of_range& e)
  {
    EXPECT_NE(std::string(e.what()).find("level 40 is beyond the tree's depth"), std::string::npos) << e.what();
  }
  EXPECT_THROW(exportVolumes(mesh, BVType::kOBB, NodeSelection{0, 1000}), std::out_of_range);
  const VolumeSet set = exportVolumes(mesh, BVType::kAABB, NodeSelection{});
  try
  {
    writeVolumes({set}, "/nonexistent/dir/volumes.glb");
    ADD_FAILURE() << "unwritable file accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("cannot write '/nonexistent/dir/volumes.glb'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(writeVolumes({set}, tempPath("volumes.xyz")), std::invalid_argument);
  EXPECT_THROW(writeVolumes({}, tempPath("volumes.glb")), std::invalid_argument);
  EXPECT_THROW(exportVolumes(TriangleMesh<double>{}, BVType::kRS, NodeSelection{}), std::invalid_argument);
}

}  // namespace
}  // namespace fcl_rs
