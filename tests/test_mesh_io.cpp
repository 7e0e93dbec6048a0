// Mesh loading and validation: real files load, bad files and bad meshes get errors that name the problem.
#include <cstdio>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"
#include "test_util.h"

namespace fcl_rs {
namespace {

std::string messageOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return "";
}

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
  if (rob.empty()) GTEST_SKIP() << "../shared/data is not beside the repository";
  const auto mesh = loadMesh<double>(rob);
  EXPECT_EQ(mesh.triangles.size(), 216u);  // as SOURCES.md counts with assimp
  const auto link = loadMesh<double>(test::sharedData("robots/panda/meshes/collision/link1.stl"));
  EXPECT_EQ(link.triangles.size(), 300u);
}

TEST(MeshIo, UnreadableFilesNameTheFile)
{
  const std::string missing = "/nonexistent/dir/mesh.obj";
  EXPECT_THROW(loadMesh<double>(missing), std::runtime_error);
  EXPECT_NE(messageOf([&] { loadMesh<double>(missing); }).find(missing), std::string::npos);

  const std::string corrupt = ::testing::TempDir() + "fcl_rs_corrupt.stl";
  {
    std::ofstream out(corrupt, std::ios::binary);
    out << "solid broken\n facet normal 0 0 nonsense\n";
  }
  EXPECT_NE(messageOf([&] { loadMesh<double>(corrupt); }).find(corrupt), std::string::npos);
  std::remove(corrupt.c_str());

  const std::string points = test::assimpModel("OBJ/testpoints.obj");
  ASSERT_FALSE(points.empty());
  EXPECT_NE(messageOf([&] { loadMesh<double>(points); }).find("no triangles"), std::string::npos);
}

TEST(MeshIo, BadMeshesAreRejectedWithTheirIndex)
{
  const auto box = makeBox<double>(1, 1, 1);
  auto nan = box;
  nan.vertices[5].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(messageOf([&] { buildModel<RS<double>>(nan); }).find("vertex 5"), std::string::npos);
  auto inf = box;
  inf.vertices[2].z() = -std::numeric_limits<double>::infinity();
  EXPECT_NE(messageOf([&] { buildModel<RS<double>>(inf); }).find("vertex 2"), std::string::npos);
  auto out_of_range = box;
  out_of_range.triangles[7] = fcl::Triangle(0, 1, 8);
  EXPECT_NE(messageOf([&] { buildModel<RS<double>>(out_of_range); }).find("triangle 7"), std::string::npos);
  EXPECT_NE(messageOf([&] { buildModel<RS<double>>(TriangleMesh<double>()); }).find("empty mesh"), std::string::npos);
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
