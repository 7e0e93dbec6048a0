// Compile-time checks: RS<S> has every member FCL's BVHModel, fitter, splitter and traversal templates use.
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <type_traits>

#include <fcl/geometry/bvh/BVH_model.h>
#include <gtest/gtest.h>

#include "fcl_rs/fcl_rs.h"

namespace {

template <typename S>
struct RSInterface
{
  using BV = fcl_rs::RS<S>;
  static_assert(std::is_same<typename BV::S, S>::value, "BV::S names the scalar");
  static_assert(std::is_default_constructible<BV>::value, "BVHModel allocates nodes with new BVNode<BV>[n]");
  static_assert(std::is_copy_constructible<BV>::value && std::is_copy_assignable<BV>::value, "nodes are copied");
  static_assert(std::is_same<decltype(std::declval<BV&>() += std::declval<const fcl::Vector3<S>&>()), BV&>::value,
                "generic fit adds points");
  static_assert(std::is_same<decltype(std::declval<const BV&>() + std::declval<const BV&>()), BV>::value,
                "bottom-up refit merges children");
  static_assert(std::is_same<decltype(std::declval<const BV&>().overlap(std::declval<const BV&>())), bool>::value,
                "BVNode::overlap");
  static_assert(std::is_same<decltype(std::declval<const BV&>().contain(std::declval<const fcl::Vector3<S>&>())),
                             bool>::value, "contain");
  static_assert(std::is_same<decltype(std::declval<const BV&>().distance(std::declval<const BV&>())), S>::value,
                "BVNode::distance");
  static_assert(std::is_same<decltype(std::declval<const BV&>().distance(
                                 std::declval<const BV&>(), std::declval<fcl::Vector3<S>*>(),
                                 std::declval<fcl::Vector3<S>*>())), S>::value,
                "distance with witness points (conservative advancement)");
  static_assert(std::is_same<decltype(std::declval<const BV&>().center()), fcl::Vector3<S>>::value, "center");
  static_assert(std::is_same<decltype(std::declval<const BV&>().width()), S>::value, "width");
  static_assert(std::is_same<decltype(std::declval<const BV&>().height()), S>::value, "height");
  static_assert(std::is_same<decltype(std::declval<const BV&>().depth()), S>::value, "depth");
  static_assert(std::is_same<decltype(std::declval<const BV&>().volume()), S>::value, "volume");
  static_assert(std::is_same<decltype(std::declval<const BV&>().size()), S>::value, "traversal order");
  static_assert(std::is_same<decltype(std::declval<const BV&>().axes()), fcl::Matrix3<S>>::value,
                "the frame in S (FCL's computeSplitVector reads it through ComputeSplitVectorImpl)");
  static_assert(std::is_same<decltype(fcl_rs::overlap(std::declval<const fcl::Matrix3<S>&>(),
                                                      std::declval<const fcl::Vector3<S>&>(), std::declval<const BV&>(),
                                                      std::declval<const BV&>())), bool>::value,
                "oriented traversal: overlap(R, T, b1, b2)");
  static_assert(std::is_same<decltype(fcl_rs::distance(std::declval<const fcl::Matrix3<S>&>(),
                                                       std::declval<const fcl::Vector3<S>&>(),
                                                       std::declval<const BV&>(), std::declval<const BV&>())), S>::value,
                "oriented distance lower bound");
  static_assert(std::is_base_of<fcl::detail::MeshCollisionTraversalNode<BV>, fcl_rs::MeshCollisionTraversalNodeRS<S>>::value,
                "the RS node runs in FCL's traversal");

  // Instantiating these compiles FCL's fitter, splitter and refit code for RS.
  static void build()
  {
    fcl::BVHModel<BV> model;
    model.beginModel();
    model.endModel();
    model.beginUpdateModel();
    model.endUpdateModel(true, true);
    fcl::Plane<S> plane;
    fcl::Halfspace<S> halfspace;
    BV bv;
    fcl::computeBV(plane, fcl::Transform3<S>::Identity(), bv);
    fcl::computeBV(halfspace, fcl::Transform3<S>::Identity(), bv);
    fcl::computeBV(fcl::Box<S>(1, 1, 1), fcl::Transform3<S>::Identity(), bv);
  }
};

template struct RSInterface<float>;
template struct RSInterface<double>;

TEST(Interface, NodeTypeIsUnknownToFcl)
{
  // FCL's closed NODE_TYPE enum has no slot for RS: this is why fcl_rs::collide exists.
  EXPECT_EQ(fcl::BVHModel<fcl_rs::RSd>().getNodeType(), fcl::BV_UNKNOWN);
  EXPECT_EQ(fcl::BVHModel<fcl_rs::RSf>().getNodeType(), fcl::BV_UNKNOWN);
}

TEST(Interface, VersionComesFromPackageXml)
{
  EXPECT_STRNE(FCL_RS_VERSION, "");
  EXPECT_GE(FCL_RS_VERSION_MAJOR * 10000 + FCL_RS_VERSION_MINOR * 100 + FCL_RS_VERSION_PATCH, 1);
}

std::string readSource(const std::string& relative)
{
  std::ifstream in(std::string(FCL_RS_SOURCE_DIR) + "/" + relative);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Docs, ReadmeDirectionTableIsTheCodesTable)
{
  const std::string readme = readSource("README.md");
  const std::regex row(R"(\|\s*(\d)\s*\|\s*(u[0-2](?:[+-]u[0-2])?)\s*\|)");
  int rows = 0;
  for (auto it = std::sregex_iterator(readme.begin(), readme.end(), row); it != std::sregex_iterator(); ++it, ++rows)
  {
    const int k = std::stoi((*it)[1]);
    ASSERT_LT(k, fcl_rs::kNumSlabs);
    EXPECT_EQ((*it)[2].str(), fcl_rs::kSlabDirections[std::size_t(k)].name) << "README row " << k;
  }
  EXPECT_EQ(rows, fcl_rs::kNumSlabs);
}

TEST(Docs, ReadmeSnippetIsTheCompiledExample)
{
  const std::string example = readSource("examples/quickstart.cpp");
  const std::string marker = "  // [quickstart]\n";
  const auto begin = example.find(marker), end = example.find("  // [quickstart]", begin + marker.size());
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  // The README shows the example's lines without their two-space function indent.
  std::istringstream lines(example.substr(begin + marker.size(), end - begin - marker.size()));
  std::string line, snippet;
  while (std::getline(lines, line)) snippet += (line.rfind("  ", 0) == 0 ? line.substr(2) : line) + "\n";
  EXPECT_NE(readSource("README.md").find(snippet), std::string::npos) << "README.md must show:\n" << snippet;
}

}  // namespace
