// Scene files and the n-body simulator: parsing and validation errors, exactly the declared effects,
// consistent pair counts (exact pairs against a brute-force oracle and inside every bounding volume's),
// and the generated sphere and k-DOP solid.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nbody/nbody.h"
#include "nbody/scene.h"
#include "fcl_rs/mesh/shapes.h"
#include "test_util.h"

namespace {

using fcl_rs::BodyPairs;
using fcl_rs::NBodySimulator;
using fcl_rs::PairTest;
using fcl_rs::Scene;

/// The shipped scene files.
const std::vector<std::string> kSceneFiles = {"mixed20", "cows20",     "ellipsoids20", "horses20", "dragons20",
                                              "hands20", "kdops20",    "diamonds20",   "spheres20"};

std::string sceneFile(const std::string& name) { return std::string(FCL_RS_SCENES_DIR) + "/" + name + ".json"; }
std::string modelsDir() { return std::string(FCL_RS_SHARED_DATA_DIR) + "/models"; }

/// A scene of generated shapes only (runs anywhere); `effects` is the JSON of the effects object.
std::string generatedScene(const std::string& effects, int count = 3, double cube = 6)
{
  return R"({"name": "generated", "cube": )" + std::to_string(cube) +
         R"(, "frames": 10, "time_step": 0.05, "seed": 7,
    "effects": )" + effects + R"(,
    "bodies": [
      {"shape": "sphere", "count": )" + std::to_string(count) + R"(, "size": 1.6},
      {"shape": "ellipsoid", "axes": [1, 0.5, 0.3], "count": )" + std::to_string(count) + R"(, "size": 2},
      {"shape": "diamond", "facets": 12, "height": 1.4, "count": )" + std::to_string(count) + R"(, "size": 1.5},
      {"shape": "kdop18", "extents": [1, 0.7, 0.5], "chamfer": 0.3, "count": )" + std::to_string(count) + R"(, "size": 1.8}
    ]})";
}

const char* kAllEffects =
    R"({"linear_motion": {"speed": [0.5, 2]}, "spin": {"rate": [0.5, 3]}, "wall_bounce": true})";

/// Expects parseScene to throw std::invalid_argument whose message contains every part.
void expectError(const std::string& json, const std::vector<std::string>& parts)
{
  try
  {
    fcl_rs::parseScene(json, "bad.json");
    ADD_FAILURE() << "no error for: " << json;
  }
  catch (const std::invalid_argument& e)
  {
    for (const auto& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

/// The scene text with one substring replaced (the original must contain it).
std::string edited(std::string text, const std::string& from, const std::string& to)
{
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(SceneParse, ReadsEveryField)
{
  const Scene s = fcl_rs::parseScene(generatedScene(kAllEffects), "gen.json");
  EXPECT_EQ(s.name, "generated");
  EXPECT_EQ(s.source, "gen.json");
  EXPECT_EQ(s.cube, 6);
  EXPECT_EQ(s.frames, 10);
  EXPECT_EQ(s.time_step, 0.05);
  EXPECT_EQ(s.seed, 7u);
  EXPECT_TRUE(s.effects.linear_motion && s.effects.spin && s.effects.wall_bounce);
  EXPECT_FALSE(s.effects.collision_response);
  EXPECT_EQ(s.effects.speed_min, 0.5);
  EXPECT_EQ(s.effects.rate_max, 3);
  ASSERT_EQ(s.bodies.size(), 4u);
  EXPECT_EQ(s.numBodies(), 12);
  EXPECT_EQ(s.bodies[1].shape, "ellipsoid");
  EXPECT_EQ(s.bodies[1].axes[2], 0.3);
  EXPECT_EQ(s.bodies[2].facets, 12);
  EXPECT_EQ(s.bodies[3].chamfer, 0.3);
  EXPECT_EQ(s.bodies[0].size, 1.6);
  EXPECT_EQ(s.bodies[0].scale, 0);
  EXPECT_TRUE(std::isnan(s.paper.rs_fewer_than_obb));

  const Scene none = fcl_rs::parseScene(generatedScene("{}"), "gen.json");
  EXPECT_FALSE(none.effects.linear_motion || none.effects.spin || none.effects.wall_bounce ||
               none.effects.collision_response);
}

TEST(SceneParse, ErrorsNameTheFileAndKey)
{
  const std::string good = generatedScene(kAllEffects);
  expectError("{ \"cube\": 1,", {"bad.json", "not valid JSON"});
  expectError("[1, 2]", {"bad.json", "top level", "must be an object"});
  expectError(edited(good, "\"frames\"", "\"frame\""), {"bad.json", "unknown key 'frame'"});
  expectError(edited(good, "\"frames\": 10,", ""), {"missing key 'frames'"});
  expectError(edited(good, "\"frames\": 10", "\"frames\": 0"), {"frames", "at least 1"});
  expectError(edited(good, "\"frames\": 10", "\"frames\": 2.5"), {"frames", "integer"});
  expectError(edited(good, "\"cube\": 6", "\"cube\": -6"), {"cube", "positive"});
  expectError(edited(good, "\"time_step\": 0.05", "\"time_step\": \"fast\""), {"time_step", "number"});
  expectError(edited(good, "\"seed\": 7", "\"seed\": -1"), {"seed"});
  expectError(edited(good, "\"speed\": [0.5, 2]", "\"speed\": [2, 0.5]"), {"effects.linear_motion.speed", "min <= max"});
  expectError(edited(good, "\"rate\"", "\"rates\""), {"effects.spin", "unknown key 'rates'"});
  expectError(edited(good, "\"wall_bounce\": true", "\"wall_bounce\": 1"), {"effects.wall_bounce", "true or false"});
  expectError(edited(good, "\"wall_bounce\"", "\"gravity\""), {"effects", "unknown key 'gravity'"});
  expectError(edited(good, "\"size\": 1.6", "\"sise\": 1.6"), {"bodies[0]", "unknown key 'sise'"});
  expectError(edited(good, "\"size\": 1.6", "\"size\": 1.6, \"scale\": 2"), {"bodies[0]", "exactly one of 'size'"});
  expectError(edited(good, "\"size\": 2}", "\"size\": -2}"), {"bodies[1].size", "positive"});
  expectError(edited(good, "\"size\": 2}", "\"size\": 7}"), {"bodies[1].size", "fit in the cube"});
  expectError(edited(good, "\"shape\": \"diamond\"", "\"shape\": \"santa\""), {"bodies[2].shape", "unknown shape 'santa'"});
  expectError(edited(good, "\"facets\": 12", "\"facets\": 2"), {"bodies[2].facets", "at least 3"});
  expectError(edited(good, "\"shape\": \"sphere\",", "\"shape\": \"sphere\", \"axes\": [1, 1, 1],"),
              {"bodies[0].axes", "shape 'ellipsoid' only"});
  expectError(edited(good, "\"chamfer\": 0.3", "\"chamfer\": 0.6"), {"bodies[3].chamfer", "smaller than every half extent"});
  expectError(edited(good, "\"axes\": [1, 0.5, 0.3]", "\"axes\": [1, 0.5]"), {"bodies[1].axes", "3 positive"});
  expectError(edited(good, "{\"shape\": \"sphere\",", "{\"mesh\": \"a.obj\", \"shape\": \"sphere\","),
              {"bodies[0]", "exactly one of 'mesh'"});
  expectError(edited(good, "\"count\": 3, \"size\": 1.6", "\"count\": 0, \"size\": 1.6"), {"bodies[0].count", "at least 1"});
  expectError(edited(good, "\"bodies\": [", "\"bodies\": [], \"x\": ["), {"unknown key 'x'"});
}

TEST(SceneLoad, MissingFilesAreNamed)
{
  const auto dir = std::filesystem::temp_directory_path() / "fcl_rs_test_scene";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "scene.json").string();
  {
    std::ofstream out(path);
    out << edited(generatedScene("{}"), "{\"shape\": \"diamond\", \"facets\": 12, \"height\": 1.4,",
                  "{\"mesh\": \"no_such_model.obj\",");
  }
  try
  {
    fcl_rs::loadScene(path, dir.string());
    ADD_FAILURE() << "missing mesh file accepted";
  }
  catch (const std::runtime_error& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("bodies[2].mesh"), std::string::npos) << msg;
    EXPECT_NE(msg.find((dir / "no_such_model.obj").string()), std::string::npos) << msg;
  }
  EXPECT_THROW(fcl_rs::loadScene((dir / "absent.json").string(), dir.string()), std::runtime_error);

  // A mesh file assimp cannot read: the simulator names the scene and the body.
  {
    std::ofstream(dir / "no_such_model.obj") << "this is not a mesh\n";
  }
  const Scene scene = fcl_rs::loadScene(path, dir.string());
  try
  {
    NBodySimulator<double> sim(scene);
    ADD_FAILURE() << "corrupt mesh accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("bodies[2] ('no_such_model')"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(SceneFiles, ShippedScenesParse)
{
  const bool have_data = std::filesystem::is_directory(modelsDir());
  if (!have_data)
  {
    ASSERT_FALSE(fcl_rs::test::sharedDataRequired()) << modelsDir() << " is missing; CI=true requires it";
    std::cout << "[note] " << modelsDir() << " is absent: mesh files are not checked\n";
  }
  for (const auto& name : kSceneFiles)
  {
    SCOPED_TRACE(name);
    std::ifstream in(sceneFile(name));
    ASSERT_TRUE(in) << sceneFile(name);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const Scene s = have_data ? fcl_rs::loadScene(sceneFile(name), modelsDir()) : fcl_rs::parseScene(text, name);
    EXPECT_EQ(s.numBodies(), 20);
    EXPECT_TRUE(s.effects.linear_motion && s.effects.spin && s.effects.wall_bounce);
  }
}

// ---------------------------------------------------------------------------------------------------------
// Generated shapes

TEST(Shapes, PaperSphereHasThePapersCounts)
{
  const auto m = fcl_rs::makePoleQuadSphere<double>(1);
  EXPECT_EQ(m.vertices.size(), 467u);
  EXPECT_EQ(m.triangles.size(), 992u);
  int zero_area = 0;
  for (const auto& t : m.triangles)
  {
    const double area = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
    if (area == 0)
    {
      ++zero_area;
      EXPECT_TRUE(t[0] == t[2]) << "only the pole quads' second triangles are degenerate";
    }
  }
  EXPECT_EQ(zero_area, 62);
  for (const auto& v : m.vertices) EXPECT_NEAR(v.norm(), 1, 1e-12);
}

/// Edge -> number of triangles using it.
std::map<std::pair<std::size_t, std::size_t>, int> edgeUse(const fcl_rs::TriangleMesh<double>& m)
{
  std::map<std::pair<std::size_t, std::size_t>, int> use;
  for (const auto& t : m.triangles)
    for (int c = 0; c < 3; ++c)
      ++use[std::minmax(t[c], t[(c + 1) % 3])];
  return use;
}

TEST(Shapes, Kdop18SolidIsAClosedOutward18Dop)
{
  const double hx = 1, hy = 0.7, hz = 0.5, c = 0.3;
  const auto m = fcl_rs::makeKdop18Solid<double>(hx, hy, hz, c);
  ASSERT_EQ(m.vertices.size(), 32u);
  ASSERT_EQ(m.triangles.size(), 60u);
  for (const auto& [edge, n] : edgeUse(m)) EXPECT_EQ(n, 2) << edge.first << "-" << edge.second;
  // The 18 halfspaces |x| <= hx, ..., |x| + |y| <= hx + hy - c, ...
  const fcl::Vector3d h(hx, hy, hz);
  const auto inside = [&](const fcl::Vector3d& p) {
    const fcl::Vector3d a = p.cwiseAbs();
    const double e = 1e-12;
    return a.x() <= hx + e && a.y() <= hy + e && a.z() <= hz + e && a.x() + a.y() <= hx + hy - c + e &&
           a.x() + a.z() <= hx + hz - c + e && a.y() + a.z() <= hy + hz - c + e;
  };
  double volume = 0;
  for (const auto& v : m.vertices) EXPECT_TRUE(inside(v)) << v.transpose();
  for (const auto& t : m.triangles)
  {
    const fcl::Vector3d &p = m.vertices[t[0]], &q = m.vertices[t[1]], &r = m.vertices[t[2]];
    const fcl::Vector3d n = (q - p).cross(r - p);
    EXPECT_GT(n.dot(p + q + r), 0) << "inward triangle";
    EXPECT_GT(n.norm(), 1e-6) << "degenerate triangle";
    EXPECT_TRUE(inside((p + q + r) / 3 + 1e-3 * n.normalized() * -1));
    EXPECT_FALSE(inside((p + q + r) / 3 + 1e-3 * n.normalized())) << "face not on the boundary";
    volume += p.dot(q.cross(r)) / 6;
  }
  // The box minus the 12 edge wedges (cross-section c^2/2 along the whole edge), corrected by inclusion-
  // exclusion at each corner: the 3 wedge pairs overlap in c^3/3 each, all three in c^3/4.
  const double box = 8 * hx * hy * hz, wedges = c * c / 2 * 4 * (2 * hx + 2 * hy + 2 * hz);
  EXPECT_NEAR(volume, box - wedges + 8 * (3 * c * c * c / 3 - c * c * c / 4), 1e-12);
}

// ---------------------------------------------------------------------------------------------------------
// The simulator

template <typename S>
class SimulatorTest : public ::testing::Test
{
};
TYPED_TEST_SUITE(SimulatorTest, fcl_rs::test::Scalars);

template <typename S>
S tolerance()
{
  return 64 * std::numeric_limits<S>::epsilon();
}

TYPED_TEST(SimulatorTest, NoEffectsNothingMoves)
{
  using S = TypeParam;
  NBodySimulator<S> sim(fcl_rs::parseScene(generatedScene("{}"), "none"));
  ASSERT_EQ(sim.numBodies(), 12);
  std::vector<fcl_rs::BodyState<S>> start;
  for (int i = 0; i < sim.numBodies(); ++i) start.push_back(sim.state(i));
  for (int f = 0; f < 20; ++f) sim.step();
  EXPECT_EQ(sim.frame(), 20);
  for (int i = 0; i < sim.numBodies(); ++i)
  {
    EXPECT_EQ(sim.state(i).position, start[std::size_t(i)].position);
    EXPECT_EQ(sim.state(i).orientation.coeffs(), start[std::size_t(i)].orientation.coeffs());
    EXPECT_EQ(sim.state(i).velocity, fcl::Vector3<S>::Zero());
    EXPECT_EQ(sim.state(i).angular_velocity, fcl::Vector3<S>::Zero());
  }
}

TYPED_TEST(SimulatorTest, EffectsDoNotChangeTheStart)
{
  using S = TypeParam;
  NBodySimulator<S> still(fcl_rs::parseScene(generatedScene("{}"), "none"));
  NBodySimulator<S> moving(fcl_rs::parseScene(generatedScene(kAllEffects), "all"));
  for (int i = 0; i < still.numBodies(); ++i)
  {
    EXPECT_EQ(still.state(i).position, moving.state(i).position);
    EXPECT_EQ(still.state(i).orientation.coeffs(), moving.state(i).orientation.coeffs());
    // Every bounding ball starts inside the cube.
    EXPECT_LE(still.state(i).position.cwiseAbs().maxCoeff() + still.radius(i), S(3) * (1 + tolerance<S>()));
  }
}

TYPED_TEST(SimulatorTest, LinearMotionIsExactAndKeepsOrientation)
{
  using S = TypeParam;
  NBodySimulator<S> sim(fcl_rs::parseScene(generatedScene(R"({"linear_motion": {"speed": [1, 2]}})"), "linear"));
  const S dt = S(0.05);
  std::vector<fcl_rs::BodyState<S>> start;
  for (int i = 0; i < sim.numBodies(); ++i) start.push_back(sim.state(i));
  const int steps = 200;  // far out of the cube: no walls declared
  for (int f = 0; f < steps; ++f) sim.step();
  for (int i = 0; i < sim.numBodies(); ++i)
  {
    const auto& s0 = start[std::size_t(i)];
    const S speed = s0.velocity.norm();
    EXPECT_GE(speed, S(1) - tolerance<S>());
    EXPECT_LE(speed, S(2) + tolerance<S>());
    EXPECT_EQ(sim.state(i).velocity, s0.velocity);
    EXPECT_EQ(sim.state(i).orientation.coeffs(), s0.orientation.coeffs()) << "no spin declared";
    const fcl::Vector3<S> expected = s0.position + S(steps) * dt * s0.velocity;
    EXPECT_LE((sim.state(i).position - expected).norm(), steps * tolerance<S>() * (1 + expected.norm()));
  }
}

TYPED_TEST(SimulatorTest, SpinRotatesAboutTheCentreAtTheDeclaredRate)
{
  using S = TypeParam;
  NBodySimulator<S> sim(fcl_rs::parseScene(generatedScene(R"({"spin": {"rate": [1, 1]}})"), "spin"));
  std::vector<fcl_rs::BodyState<S>> start;
  for (int i = 0; i < sim.numBodies(); ++i) start.push_back(sim.state(i));
  const int steps = 30;
  for (int f = 0; f < steps; ++f) sim.step();
  for (int i = 0; i < sim.numBodies(); ++i)
  {
    const auto& s0 = start[std::size_t(i)];
    EXPECT_EQ(sim.state(i).position, s0.position) << "no linear motion declared";
    EXPECT_NEAR(double(s0.angular_velocity.norm()), 1, 1e-6);
    // Orientation = rotation by |w| t about w, applied to the start.
    const Eigen::AngleAxis<S> turn(S(steps * 0.05), s0.angular_velocity.normalized());
    const fcl::Matrix3<S> expected = turn.toRotationMatrix() * s0.orientation.toRotationMatrix();
    EXPECT_LE((sim.state(i).orientation.toRotationMatrix() - expected).norm(), 1e3 * tolerance<S>());
  }
}

TYPED_TEST(SimulatorTest, WallBounceKeepsEveryVertexInTheCube)
{
  using S = TypeParam;
  NBodySimulator<S> sim(fcl_rs::parseScene(
      generatedScene(R"({"linear_motion": {"speed": [3, 6]}, "spin": {"rate": [1, 4]}, "wall_bounce": true})"), "walls"));
  std::vector<S> speed;
  for (int i = 0; i < sim.numBodies(); ++i) speed.push_back(sim.state(i).velocity.norm());
  int bounces = 0;
  for (int f = 0; f < 100; ++f)
  {
    for (int i = 0; i < sim.numBodies(); ++i)
    {
      const auto pose = sim.pose(i);
      S extent = 0;
      for (const auto& v : sim.mesh(i).vertices) extent = std::max(extent, (pose * v).cwiseAbs().maxCoeff());
      ASSERT_LE(extent, S(3) * (1 + tolerance<S>())) << "body " << i << " frame " << f;
    }
    std::vector<fcl::Vector3<S>> before;
    for (int i = 0; i < sim.numBodies(); ++i) before.push_back(sim.state(i).velocity);
    sim.step();
    for (int i = 0; i < sim.numBodies(); ++i)
    {
      const auto& v = sim.state(i).velocity;
      EXPECT_NEAR(double(v.norm()), double(speed[std::size_t(i)]), 1e-5) << "a bounce keeps the speed";
      // Components only ever change sign.
      EXPECT_EQ(v.cwiseAbs(), before[std::size_t(i)].cwiseAbs());
      bounces += v != before[std::size_t(i)];
    }
  }
  EXPECT_GT(bounces, 10) << "the test should see bodies bounce";
}

/// Pairs whose meshes intersect, by FCL's triangle test over all triangle pairs (boxes skip far pairs).
template <typename S>
BodyPairs bruteForceExact(const NBodySimulator<S>& sim)
{
  BodyPairs out;
  for (int i = 0; i < sim.numBodies(); ++i)
    for (int j = i + 1; j < sim.numBodies(); ++j)
    {
      const S reach = sim.radius(i) + sim.radius(j);
      if ((sim.state(i).position - sim.state(j).position).norm() > reach * (1 + tolerance<S>())) continue;
      if (!fcl_rs::test::bruteForcePairs(sim.mesh(i), sim.pose(i), sim.mesh(j), sim.pose(j)).empty())
        out.emplace_back(i, j);
    }
  return out;
}

bool contains(const BodyPairs& pairs, const std::pair<int, int>& p)
{
  return std::binary_search(pairs.begin(), pairs.end(), p);
}

TYPED_TEST(SimulatorTest, ExactPairsAreInsideEveryBoundingVolumesPairs)
{
  using S = TypeParam;
  // Crowded: 20 bodies in a small cube, so that many pairs touch.
  NBodySimulator<S> sim(fcl_rs::parseScene(generatedScene(kAllEffects, 5, 5), "crowded"));
  ASSERT_EQ(sim.numBodies(), 20);
  int exact_total = 0, checked_by_brute_force = 0;
  std::array<long, fcl_rs::kNumPairTests> total{};
  for (int f = 0; f < 120; ++f)
  {
    SCOPED_TRACE("frame " + std::to_string(f));
    std::array<BodyPairs, fcl_rs::kNumPairTests> pairs;
    for (std::size_t t = 0; t < pairs.size(); ++t)
    {
      pairs[t] = sim.pairs(fcl_rs::kPairTests[t]);
      ASSERT_TRUE(std::is_sorted(pairs[t].begin(), pairs[t].end()));
      total[t] += long(pairs[t].size());
    }
    const BodyPairs& exact = pairs[std::size_t(PairTest::kExact)];
    exact_total += int(exact.size());
    for (const auto& p : exact)
      for (std::size_t t = 0; t + 1 < pairs.size(); ++t)
        EXPECT_TRUE(contains(pairs[t], p)) << fcl_rs::pairTestName(fcl_rs::kPairTests[t]) << " misses intersecting pair "
                                           << p.first << "-" << p.second;
    // The two-sided RS test prunes whatever the one-sided one does; a refitted k-DOP lies inside the realigned one.
    const auto subset = [&pairs](PairTest small, PairTest large) {
      for (const auto& p : pairs[std::size_t(small)])
        EXPECT_TRUE(contains(pairs[std::size_t(large)], p)) << fcl_rs::pairTestName(large) << " misses " << p.first << "-"
                                                            << p.second << " of " << fcl_rs::pairTestName(small);
    };
    subset(PairTest::kRS, PairTest::kRSOneSided);
    subset(PairTest::kKDOP18, PairTest::kKDOP18Realigned);
    if (f % 10 == 0)
    {
      EXPECT_EQ(exact, bruteForceExact(sim));
      ++checked_by_brute_force;
    }
    const fcl_rs::FrameRecord r = sim.record();
    for (std::size_t t = 0; t < pairs.size(); ++t) EXPECT_EQ(r.count[t], int(pairs[t].size()));
    sim.step();
  }
  EXPECT_GT(exact_total, 100) << "the scene should be crowded enough to test something";
  EXPECT_EQ(checked_by_brute_force, 12);
  // The volumes' pair counts are ordered as their tightness suggests (sums over the run).
  const auto at = [&total](PairTest t) { return total[std::size_t(t)]; };
  EXPECT_GE(at(PairTest::kSphere), at(PairTest::kExact));
  EXPECT_GE(at(PairTest::kOBB), at(PairTest::kRS)) << "RS is the OBB's box with the edges cut, in the same kind of frame";
  std::cout << "[counts] 120 frames:";
  for (std::size_t t = 0; t < total.size(); ++t) std::cout << ' ' << fcl_rs::pairTestName(fcl_rs::kPairTests[t]) << '=' << total[t];
  std::cout << "\n";
}

TYPED_TEST(SimulatorTest, CollisionResponseOnlyAtContactsAndConservesMomentum)
{
  using S = TypeParam;
  const std::string fx = R"({"linear_motion": {"speed": [1, 2]}, "collision_response": true})";
  NBodySimulator<S> sim(fcl_rs::parseScene(generatedScene(fx, 5, 5), "response"));
  int responses = 0;
  for (int f = 0; f < 60; ++f)
  {
    const BodyPairs exact = sim.pairs(PairTest::kExact);
    std::set<int> touching;
    for (const auto& p : exact) touching.insert(p.first), touching.insert(p.second);
    fcl::Vector3<S> momentum = fcl::Vector3<S>::Zero();
    S energy = 0;
    std::vector<fcl::Vector3<S>> before;
    for (int i = 0; i < sim.numBodies(); ++i)
    {
      before.push_back(sim.state(i).velocity);
      momentum += before.back();
      energy += before.back().squaredNorm();
    }
    sim.step();
    fcl::Vector3<S> momentum_after = fcl::Vector3<S>::Zero();
    S energy_after = 0;
    for (int i = 0; i < sim.numBodies(); ++i)
    {
      const auto& v = sim.state(i).velocity;
      momentum_after += v;
      energy_after += v.squaredNorm();
      if (!touching.count(i)) {
        EXPECT_EQ(v, before[std::size_t(i)]) << "body " << i << " changed without contact";
      }
      responses += v != before[std::size_t(i)];
    }
    EXPECT_LE((momentum_after - momentum).norm(), 1e3 * tolerance<S>());
    EXPECT_NEAR(double(energy_after), double(energy), 1e3 * double(tolerance<S>()) * double(energy));
  }
  EXPECT_GT(responses, 0) << "the test should see a collision response";

  // Same scene without the effect: velocities never change (no walls either).
  NBodySimulator<S> plain(fcl_rs::parseScene(generatedScene(R"({"linear_motion": {"speed": [1, 2]}})", 5, 5), "plain"));
  std::vector<fcl::Vector3<S>> start;
  for (int i = 0; i < plain.numBodies(); ++i) start.push_back(plain.state(i).velocity);
  for (int f = 0; f < 60; ++f) plain.step();
  for (int i = 0; i < plain.numBodies(); ++i) EXPECT_EQ(plain.state(i).velocity, start[std::size_t(i)]);
}

TEST(Simulator, DegeneratePoleTrianglesChangeNoExactResult)
{
  // The paper's sphere = the closed UV sphere plus zero-area triangles on its edges: identical results.
  auto rng = fcl_rs::test::seededRng("DegeneratePoleTriangles");
  const auto paper = fcl_rs::makePoleQuadSphere<double>(1);
  const auto closed = fcl_rs::makeSphere<double>(1, 16, 31);
  int touching = 0;
  for (int k = 0; k < 100; ++k)
  {
    const fcl::Transform3d a = fcl_rs::test::randomPose<double>(rng, 0.1), b = fcl_rs::test::randomPose<double>(rng, 2);
    const bool p = !fcl_rs::test::bruteForcePairs(paper, a, paper, b).empty();
    const bool c = !fcl_rs::test::bruteForcePairs(closed, a, closed, b).empty();
    EXPECT_EQ(p, c) << "pose " << k;
    touching += c;
  }
  EXPECT_GT(touching, 20);
  EXPECT_LT(touching, 90);
}

TEST(Simulator, DeterministicForASeed)
{
  const Scene scene = fcl_rs::parseScene(generatedScene(kAllEffects), "det");
  NBodySimulator<double> a(scene), b(scene);
  for (int f = 0; f < 15; ++f)
  {
    EXPECT_EQ(a.pairs(PairTest::kExact), b.pairs(PairTest::kExact));
    a.step();
    b.step();
  }
  for (int i = 0; i < a.numBodies(); ++i) EXPECT_EQ(a.state(i).position, b.state(i).position);
}

TEST(Simulator, MixedSceneOnRealMeshes)
{
  if (!std::filesystem::is_directory(modelsDir())) FCL_RS_MISSING_SHARED_DATA("models");
  Scene scene = fcl_rs::loadScene(sceneFile("mixed20"), modelsDir());
  // The sanitizer build follows the first frames only and takes the low-resolution versions of the meshes where the
  // data has them (CI's budget: building the full-resolution trees takes most of its time there).
  if (fcl_rs::test::kSanitized)
    for (auto& body : scene.bodies)
    {
      if (body.mesh_path.empty()) continue;
      const std::filesystem::path full = body.mesh_path;
      const auto low = full.parent_path() / (full.stem().string() + "_lowres" + full.extension().string());
      if (std::filesystem::exists(low)) body.mesh_path = low.string();
    }
  NBodySimulator<double> sim(scene);
  ASSERT_EQ(sim.numBodies(), 20);
  long exact_total = 0;
  const int frames = fcl_rs::test::kSanitized ? 10 : 40;
  for (int f = 0; f < frames; ++f)
  {
    std::array<BodyPairs, fcl_rs::kNumPairTests> pairs;
    for (std::size_t t = 0; t < pairs.size(); ++t) pairs[t] = sim.pairs(fcl_rs::kPairTests[t]);
    for (const auto& p : pairs.back())
      for (std::size_t t = 0; t + 1 < pairs.size(); ++t)
        EXPECT_TRUE(contains(pairs[t], p)) << "frame " << f << ": " << fcl_rs::pairTestName(fcl_rs::kPairTests[t])
                                           << " misses " << sim.name(p.first) << "-" << sim.name(p.second);
    exact_total += long(pairs.back().size());
    sim.step();
  }
  std::cout << "[counts] mixed20, " << frames << " frames: " << exact_total << " intersecting pairs\n";
}

TEST(Summary, PercentagesFromTotals)
{
  std::vector<fcl_rs::FrameRecord> records(2);
  // sphere, aabb, obb, kdop18, rs, kdop18_realigned, rs_one_sided, exact
  records[0].count = {{10, 8, 8, 5, 4, 9, 6, 2}};
  records[1].count = {{6, 4, 2, 3, 2, 3, 2, 0}};
  records[0].seconds = {{1, 1, 1, 1, 1, 1, 1, 3}};
  records[1].seconds = {{1, 1, 1, 1, 1, 1, 1, 1}};
  const fcl_rs::SceneSummary s = fcl_rs::summarize(records);
  EXPECT_EQ(s.frames, 2);
  EXPECT_DOUBLE_EQ(s.mean_count[std::size_t(PairTest::kOBB)], 5);
  EXPECT_DOUBLE_EQ(s.mean_seconds[std::size_t(PairTest::kExact)], 2);
  EXPECT_DOUBLE_EQ(s.rs_fewer_than_obb, 100.0 * (10 - 6) / 10);
  EXPECT_DOUBLE_EQ(s.kdop18_more_than_rs, 100.0 * (8 - 6) / 6);
  EXPECT_DOUBLE_EQ(s.percentMore(PairTest::kKDOP18Realigned, PairTest::kRSOneSided), 100.0 * (12 - 8) / 8);
  EXPECT_DOUBLE_EQ(s.false_positive_rate[std::size_t(PairTest::kSphere)], 1 - 2.0 / 16);
  EXPECT_DOUBLE_EQ(s.false_positive_rate[std::size_t(PairTest::kExact)], 0);
  EXPECT_TRUE(std::isnan(fcl_rs::summarize({}).rs_fewer_than_obb));
}

}  // namespace
