#include <algorithm>
#include <cmath>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>

#include "marsyn/core/planning/routes.hpp"

// The visibility-graph route in the plane, apart from the agents' ways (routes.cpp): the loader
// reads a heading's winding from it too (problem/periodic_fields.cpp).
namespace marsyn::planning {

namespace {

// Whether the segment a-b passes through the interior of the convex polygon (Cyrus-Beck
// clipping against the edges' inner half-planes): touching an edge or a vertex is not crossing,
// so routes may run along the grown obstacles' edges and through their corners.
bool crosses(const Polygon& poly, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  double t0 = 0.0, t1 = 1.0;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % n] - poly[i];
    const Eigen::Vector2d out(e.y(), -e.x());  // outward normal of a counter-clockwise edge
    const double num = out.dot(poly[i] - a), den = out.dot(d);
    // Inside this edge's half-plane: out . (a + t d - v) < 0, i.e. t den < num.
    if (den == 0.0) {
      if (num <= 0.0) return false;  // the segment's line stays out (or on the edge)
    } else if (den > 0.0) {
      t1 = std::min(t1, num / den);
    } else {
      t0 = std::max(t0, num / den);
    }
  }
  const double scale = 1.0 + d.norm();
  return t1 - t0 > 1e-9 * scale;
}

bool strictly_inside(const Polygon& poly, const Eigen::Vector2d& p) {
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % n] - poly[i];
    if (Eigen::Vector2d(e.y(), -e.x()).dot(p - poly[i]) >= -1e-12 * (1.0 + e.norm())) return false;
  }
  return n >= 3;
}

bool visible(const std::vector<Polygon>& polygons, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::none_of(polygons.begin(), polygons.end(), [&](const Polygon& p) { return crosses(p, a, b); });
}

}  // namespace

std::vector<Eigen::Vector2d> shortest_route(const std::vector<Polygon>& polygons, const Eigen::Vector2d& from,
                                            const Eigen::Vector2d& to, bool* found) {
  if (found) *found = false;
  for (const auto& p : polygons)
    if (strictly_inside(p, from) || strictly_inside(p, to)) return {};
  if (visible(polygons, from, to)) {
    if (found) *found = true;
    return {};
  }
  // Nodes: the two ends, then every vertex that is not inside another polygon.
  std::vector<Eigen::Vector2d> nodes{from, to};
  for (const auto& p : polygons)
    for (const auto& v : p)
      if (std::none_of(polygons.begin(), polygons.end(), [&](const Polygon& q) { return strictly_inside(q, v); }))
        nodes.push_back(v);
  using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS, boost::no_property,
                                      boost::property<boost::edge_weight_t, double>>;
  Graph g(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    for (size_t j = i + 1; j < nodes.size(); ++j)
      if (visible(polygons, nodes[i], nodes[j])) boost::add_edge(i, j, (nodes[i] - nodes[j]).norm(), g);
  std::vector<size_t> pred(nodes.size());
  std::vector<double> dist(nodes.size());
  boost::dijkstra_shortest_paths(g, 0, boost::predecessor_map(pred.data()).distance_map(dist.data()));
  if (!std::isfinite(dist[1]) || pred[1] == 1) return {};
  std::vector<Eigen::Vector2d> corners;
  for (size_t v = pred[1]; v != 0; v = pred[v]) corners.push_back(nodes[v]);
  std::reverse(corners.begin(), corners.end());
  if (found) *found = true;
  return corners;
}

}  // namespace marsyn::planning
