// Generated triangle meshes (sphere, ellipsoid, box, torus, diamond, k-DOP solid) for tests, benchmarks and scenes.
#ifndef FCL_RS_SHAPES_H
#define FCL_RS_SHAPES_H

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "fcl_rs/mesh/triangle_mesh.h"

namespace fcl_rs {

/// UV sphere with `stacks` rings and `slices` segments: (stacks-1)*slices+2 vertices,
/// 2*slices*(stacks-1) triangles. The defaults (16, 32) give 482 vertices / 960 triangles.
template <typename S>
TriangleMesh<S> makeSphere(S radius, int stacks = 16, int slices = 32)
{
  if (stacks < 2 || slices < 3) throw std::invalid_argument("fcl_rs::makeSphere: need stacks >= 2, slices >= 3");
  TriangleMesh<S> m;
  m.vertices.emplace_back(0, 0, radius);
  for (int i = 1; i < stacks; ++i)
  {
    const S theta = S(M_PI) * S(i) / S(stacks);
    for (int j = 0; j < slices; ++j)
    {
      const S phi = S(2 * M_PI) * S(j) / S(slices);
      m.vertices.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::sin(theta) * std::sin(phi),
                              radius * std::cos(theta));
    }
  }
  m.vertices.emplace_back(0, 0, -radius);
  const auto ring = [slices](int i, int j) { return std::size_t(1 + (i - 1) * slices + (j % slices)); };
  const std::size_t bottom = m.vertices.size() - 1;
  for (int j = 0; j < slices; ++j)
  {
    m.triangles.emplace_back(0, ring(1, j), ring(1, j + 1));
    m.triangles.emplace_back(bottom, ring(stacks - 1, j + 1), ring(stacks - 1, j));
  }
  for (int i = 1; i + 1 < stacks; ++i)
    for (int j = 0; j < slices; ++j)
    {
      m.triangles.emplace_back(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      m.triangles.emplace_back(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  return m;
}

/// Ellipsoid with semi-axes (a, b, c): a scaled sphere.
template <typename S>
TriangleMesh<S> makeEllipsoid(S a, S b, S c, int stacks = 16, int slices = 32)
{
  TriangleMesh<S> m = makeSphere<S>(1, stacks, slices);
  for (auto& v : m.vertices) v = v.cwiseProduct(fcl::Vector3<S>(a, b, c));
  return m;
}

/// Axis-aligned box centred at the origin with the given side lengths: 8 vertices, 12 triangles.
template <typename S>
TriangleMesh<S> makeBox(S x, S y, S z)
{
  TriangleMesh<S> m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back((i & 1 ? x : -x) / 2, (i & 2 ? y : -y) / 2, (i & 4 ? z : -z) / 2);
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces)
  {
    m.triangles.emplace_back(f[0], f[1], f[2]);
    m.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return m;
}

/// Torus about z with tube centre radius R and tube radius r.
template <typename S>
TriangleMesh<S> makeTorus(S R, S r, int rings = 24, int sides = 12)
{
  if (rings < 3 || sides < 3) throw std::invalid_argument("fcl_rs::makeTorus: need rings, sides >= 3");
  TriangleMesh<S> m;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j)
    {
      const S u = S(2 * M_PI) * S(i) / S(rings), v = S(2 * M_PI) * S(j) / S(sides);
      m.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  const auto at = [rings, sides](int i, int j) { return std::size_t((i % rings) * sides + (j % sides)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j)
    {
      m.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

/// Cut-gem "diamond": a `facets`-gon girdle of radius r at z = 0, a table point at h/4, a culet at -3h/4.
template <typename S>
TriangleMesh<S> makeDiamond(S r, S h, int facets = 8)
{
  if (facets < 3) throw std::invalid_argument("fcl_rs::makeDiamond: need facets >= 3");
  TriangleMesh<S> m;
  m.vertices.emplace_back(0, 0, h / 4);  // table
  for (int j = 0; j < facets; ++j)
  {
    const S phi = S(2 * M_PI) * S(j) / S(facets);
    m.vertices.emplace_back(r * std::cos(phi), r * std::sin(phi), 0);
  }
  m.vertices.emplace_back(0, 0, -3 * h / 4);  // culet
  const std::size_t culet = m.vertices.size() - 1;
  for (int j = 0; j < facets; ++j)
  {
    const std::size_t a = std::size_t(1 + j), b = std::size_t(1 + (j + 1) % facets);
    m.triangles.emplace_back(0, a, b);
    m.triangles.emplace_back(culet, b, a);
  }
  return m;
}

/// The paper's sphere (section 5: 467 vertices, 992 faces). A closed genus-0 triangle mesh has
/// F = 2V - 4, so no such mesh has 467 vertices and 992 faces; the counts are those of a UV sphere
/// exported with quads at the poles, as modelling tools write it: makeSphere(radius, stacks, slices)
/// plus, for every polar quad (whose two pole corners coincide), the zero-area second triangle
/// (pole, ring vertex, pole). Those 2*slices extra triangles lie on edges of the real ones, so they
/// change neither the surface nor which meshes intersect. The defaults (16, 31) give 467 / 992.
template <typename S>
TriangleMesh<S> makePoleQuadSphere(S radius, int stacks = 16, int slices = 31)
{
  TriangleMesh<S> m = makeSphere<S>(radius, stacks, slices);
  const std::size_t bottom = m.vertices.size() - 1;
  const auto ring = [slices](int i, int j) { return std::size_t(1 + (i - 1) * slices + (j % slices)); };
  for (int j = 0; j < slices; ++j)
  {
    m.triangles.emplace_back(0, ring(1, j + 1), 0);
    m.triangles.emplace_back(bottom, ring(stacks - 1, j), bottom);
  }
  return m;
}

/// A k-DOP-shaped solid: the 18-DOP (slabs x, y, z, x+-y, x+-z, y+-z) of the box with half extents
/// (hx, hy, hz) whose 12 edges are cut off by the planes |x|+|y| = hx+hy-c (and likewise for xz, yz),
/// 0 < c < min(hx, hy, hz). Its 6 rectangles and 12 hexagons meet at 32 vertices (4 per corner, the
/// Tribox "triple point inside" configuration); 60 outward-facing triangles.
template <typename S>
TriangleMesh<S> makeKdop18Solid(S hx, S hy, S hz, S c)
{
  if (!(c > 0 && c < std::min(hx, std::min(hy, hz))))
    throw std::invalid_argument("fcl_rs::makeKdop18Solid: need 0 < chamfer < every half extent");
  const fcl::Vector3<S> h(hx, hy, hz);
  TriangleMesh<S> m;
  // Vertex (octant, kind): kind a < 3 lies on the face x_a = +-h_a, kind 3 is the chamfers' triple point.
  for (int octant = 0; octant < 8; ++octant)
    for (int kind = 0; kind < 4; ++kind)
    {
      fcl::Vector3<S> v;
      for (int a = 0; a < 3; ++a)
        v[a] = ((octant >> a) & 1 ? -1 : 1) * (kind == 3 ? h[a] - c / 2 : kind == a ? h[a] : h[a] - c);
      m.vertices.push_back(v);
    }
  const auto at = [](int sign0, int sign1, int sign2, int kind) {
    return std::size_t(4 * ((sign0 < 0) | (sign1 < 0) << 1 | (sign2 < 0) << 2) + kind);
  };
  // Signs along axes (a, b, e) written into x, y, z order.
  const auto vertex = [&at](int a, int b, int e, int sa, int sb, int se, int kind) {
    int s[3];
    s[a] = sa; s[b] = sb; s[e] = se;
    return at(s[0], s[1], s[2], kind);
  };
  std::vector<std::vector<std::size_t>> faces;
  for (int a = 0; a < 3; ++a)
  {
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    for (int sa : {1, -1})
    {
      // Rectangle on x_a = sa * h_a.
      faces.push_back({vertex(a, b, e, sa, 1, 1, a), vertex(a, b, e, sa, 1, -1, a), vertex(a, b, e, sa, -1, -1, a),
                       vertex(a, b, e, sa, -1, 1, a)});
      // Hexagon on the chamfer of the edge along e between the faces of a and b.
      for (int sb : {1, -1})
        faces.push_back({vertex(a, b, e, sa, sb, 1, a), vertex(a, b, e, sa, sb, 1, 3), vertex(a, b, e, sa, sb, 1, b),
                         vertex(a, b, e, sa, sb, -1, b), vertex(a, b, e, sa, sb, -1, 3), vertex(a, b, e, sa, sb, -1, a)});
    }
  }
  // Fan triangulation; the solid is convex about the origin, so outward means normal . centroid > 0.
  for (const auto& f : faces)
    for (std::size_t i = 1; i + 1 < f.size(); ++i)
    {
      const fcl::Vector3<S>&p = m.vertices[f[0]], &q = m.vertices[f[i]], &r = m.vertices[f[i + 1]];
      if ((q - p).cross(r - p).dot(p + q + r) > 0)
        m.triangles.emplace_back(f[0], f[i], f[i + 1]);
      else
        m.triangles.emplace_back(f[0], f[i + 1], f[i]);
    }
  return m;
}

/// Applies a rigid transform to every vertex (to place generated shapes).
template <typename S>
TriangleMesh<S> transformed(TriangleMesh<S> m, const fcl::Transform3<S>& tf)
{
  for (auto& v : m.vertices) v = tf * v;
  return m;
}

}  // namespace fcl_rs

#endif
