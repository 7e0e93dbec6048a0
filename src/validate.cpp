// fcl_rs::requireValidShape: the sizes of FCL's primitive shapes, checked through the one shape switch.
#include "fcl_rs/validate.h"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "scalars.h"
#include "fcl_rs/traversal/shape_switch.h"

namespace fcl_rs {
namespace {

template <typename S>
bool positive(S value)
{
  return value > 0 && std::isfinite(value);
}

template <typename S>
std::string text(const fcl::Vector3<S>& v)
{
  std::ostringstream out;
  out.precision(std::numeric_limits<S>::max_digits10);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

template <typename S>
std::string text(S value)
{
  return detail::valueText(value);
}

/// What is wrong with a convex shape's vertices or faces (nothing: nullopt): the face list is FCL's, for each face
/// its vertex count and then that many vertex indices.
template <typename S>
std::optional<std::string> convexDefect(const fcl::Convex<S>& c)
{
  const auto& vertices = c.getVertices();
  const auto& faces = c.getFaces();
  if (vertices.empty()) return "without vertices";
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (!vertices[i].allFinite()) return "with vertex " + std::to_string(i) + " at " + text(vertices[i]);
  if (c.getFaceCount() < 1) return "with " + std::to_string(c.getFaceCount()) + " faces (at least 1)";
  std::size_t at = 0;
  for (int f = 0; f < c.getFaceCount(); ++f)
  {
    if (at >= faces.size())
      return "whose face list (" + std::to_string(faces.size()) + " ints) ends before face " + std::to_string(f) +
             " of its " + std::to_string(c.getFaceCount());
    const int count = faces[at];
    if (count < 3) return "whose face " + std::to_string(f) + " has " + std::to_string(count) + " vertices (at least 3)";
    if (std::size_t(count) >= faces.size() - at)
      return "whose face list (" + std::to_string(faces.size()) + " ints) ends inside face " + std::to_string(f);
    for (int k = 1; k <= count; ++k)
      if (faces[at + std::size_t(k)] < 0 || std::size_t(faces[at + std::size_t(k)]) >= vertices.size())
        return "whose face " + std::to_string(f) + " has vertex index " + std::to_string(faces[at + std::size_t(k)]) +
               ", not in [0, " + std::to_string(vertices.size()) + ")";
    at += std::size_t(count) + 1;
  }
  return std::nullopt;
}

/// What is wrong with a shape's sizes, after "is an fcl::<Shape> " (nothing: nullopt, which builds no string).
template <typename Shape>
std::optional<std::string> defect(const Shape& shape)
{
  using S = typename Shape::S;
  if constexpr (std::is_same_v<Shape, fcl::Box<S>>)
  {
    if (!(positive(shape.side.x()) && positive(shape.side.y()) && positive(shape.side.z())))
      return "with side " + text(shape.side) + ": every side must be positive and finite";
  }
  else if constexpr (std::is_same_v<Shape, fcl::Sphere<S>>)
  {
    if (!positive(shape.radius)) return "with radius " + text(shape.radius) + ": it must be positive and finite";
  }
  else if constexpr (std::is_same_v<Shape, fcl::Ellipsoid<S>>)
  {
    if (!(positive(shape.radii.x()) && positive(shape.radii.y()) && positive(shape.radii.z())))
      return "with radii " + text(shape.radii) + ": every radius must be positive and finite";
  }
  else if constexpr (std::is_same_v<Shape, fcl::Capsule<S>> || std::is_same_v<Shape, fcl::Cone<S>> ||
                     std::is_same_v<Shape, fcl::Cylinder<S>>)
  {
    if (!(positive(shape.radius) && positive(shape.lz)))
      return "with radius " + text(shape.radius) + " and length lz " + text(shape.lz) +
             ": both must be positive and finite";
  }
  else if constexpr (std::is_same_v<Shape, fcl::Convex<S>>)
    return convexDefect(shape);
  else if constexpr (std::is_same_v<Shape, fcl::TriangleP<S>>)
  {
    // Zero area is valid: a segment or a point, which the mesh-mesh triangle test it runs answers exactly.
    const fcl::Vector3<S>* corners[3] = {&shape.a, &shape.b, &shape.c};
    for (int i = 0; i < 3; ++i)
      if (!corners[i]->allFinite())
        return std::string("with vertex ") + "abc"[i] + " at " + text(*corners[i]) + ": every vertex must be finite";
  }
  else
  {
    static_assert(std::is_same_v<Shape, fcl::Plane<S>> || std::is_same_v<Shape, fcl::Halfspace<S>>);
    // Plane and halfspace: the leaf tests and bounds take |n| = 1, as FCL's constructors make it.
    if (!(std::abs(shape.n.squaredNorm() - 1) <= rigidTransformTolerance<S>()))
      return "with normal " + text(shape.n) + ": it must be a finite unit vector";
    if (!std::isfinite(shape.d)) return "with offset d " + text(shape.d) + ": it must be finite";
  }
  return std::nullopt;
}

template <typename Shape>
const char* shapeName()
{
  using S = typename Shape::S;
  if constexpr (std::is_same_v<Shape, fcl::Box<S>>) return "Box";
  else if constexpr (std::is_same_v<Shape, fcl::Sphere<S>>) return "Sphere";
  else if constexpr (std::is_same_v<Shape, fcl::Ellipsoid<S>>) return "Ellipsoid";
  else if constexpr (std::is_same_v<Shape, fcl::Capsule<S>>) return "Capsule";
  else if constexpr (std::is_same_v<Shape, fcl::Cone<S>>) return "Cone";
  else if constexpr (std::is_same_v<Shape, fcl::Cylinder<S>>) return "Cylinder";
  else if constexpr (std::is_same_v<Shape, fcl::Convex<S>>) return "Convex";
  else if constexpr (std::is_same_v<Shape, fcl::Plane<S>>) return "Plane";
  else if constexpr (std::is_same_v<Shape, fcl::Halfspace<S>>) return "Halfspace";
  else return "TriangleP";
}

}  // namespace

template <typename S>
void requireValidShape(const fcl::CollisionGeometry<S>* geometry, const char* api, const char* argument)
{
  if (!geometry) return;
  detail::withShape(
      *geometry,
      [&](const auto& shape) {
        if (const std::optional<std::string> what = defect(shape))
          throw std::invalid_argument(std::string(api) + ": " + argument + " is an fcl::" +
                                      shapeName<std::decay_t<decltype(shape)>>() + " " + *what);
      },
      [] {});
}

#define FCL_RS_INSTANTIATE_SHAPE_CHECK(S) \
  template void requireValidShape<S>(const fcl::CollisionGeometry<S>*, const char*, const char*);
FCL_RS_FOR_EACH_SCALAR(FCL_RS_INSTANTIATE_SHAPE_CHECK)
#undef FCL_RS_INSTANTIATE_SHAPE_CHECK

}  // namespace fcl_rs
