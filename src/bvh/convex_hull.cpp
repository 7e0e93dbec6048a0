// fcl_rs::convexHull: qhull's convex hull of a point set, triangulated, with its volume.
#include <algorithm>
#include <cstdio>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "fcl_rs/bvh/frame_fit.h"

namespace fcl_rs {
namespace {

/// qhull reports flat input (a normal case here: every leaf is one triangle) on its error stream.
FILE* qhullMessages()
{
  static FILE* const sink = std::fopen("/dev/null", "w");
  return sink;
}

void keepDistinct(std::vector<Eigen::Vector3d>& points)
{
  const auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(points.begin(), points.end(), less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
}

}  // namespace

ConvexHull convexHull(std::vector<Eigen::Vector3d> points)
{
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite())
      throw std::domain_error("fcl_rs::convexHull: point " + std::to_string(i) + " is not finite");
  keepDistinct(points);
  ConvexHull hull;
  if (points.size() < 4)
  {
    hull.vertices = std::move(points);
    return hull;
  }

  // Centred coordinates: qhull's precision is relative to the coordinates' magnitude.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : points) centre += p;
  centre /= double(points.size());
  std::vector<coordT> coords;
  coords.reserve(3 * points.size());
  for (const auto& p : points) coords.insert(coords.end(), {p.x() - centre.x(), p.y() - centre.y(), p.z() - centre.z()});

  qhT qh_storage;
  qhT* qh = &qh_storage;
  FILE* messages = qhullMessages();
  qh_zero(qh, messages);
  char options[] = "qhull Qt";
  const int failed = qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, options, nullptr, messages);
  if (!failed)
  {
    qh_getarea(qh, qh->facet_list);
    hull.volume = qh->totvol;
    std::vector<int> index(points.size(), -1);
    vertexT* vertex;
    FORALLvertices
    {
      const int id = qh_pointid(qh, vertex->point);
      if (id < 0 || std::size_t(id) >= points.size()) continue;  // not an input point (none expected)
      index[std::size_t(id)] = int(hull.vertices.size());
      hull.vertices.push_back(points[std::size_t(id)]);
    }
    facetT* facet;
    FORALLfacets
    {
      std::array<int, 3> t{};
      int c = 0;
      vertexT** vertexp;
      FOREACHvertex_(facet->vertices)
      {
        const int id = qh_pointid(qh, vertex->point);
        if (c < 3) t[std::size_t(c)] = id < 0 || std::size_t(id) >= points.size() ? -1 : index[std::size_t(id)];
        ++c;
      }
      if (c == 3 && std::min({t[0], t[1], t[2]}) >= 0) hull.triangles.push_back(t);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);

  if (hull.triangles.empty() || !(hull.volume > 0))
  {
    hull = ConvexHull();
    hull.vertices = std::move(points);
  }
  return hull;
}

}  // namespace fcl_rs
