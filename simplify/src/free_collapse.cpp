// Collapses past the half-edge mesh's topology: free_collapse.h says why.
#include "free_collapse.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace perclod::detail {

namespace {

// A candidate v0 -> v1 as it was when pushed: stale once either end has
// taken a collapse since (its quadric changed) or v0 is gone.
struct Entry {
  double cost;
  uint32_t v0, v1;
  uint32_t stamp0, stamp1;
};
// The heap's top is the cheapest, ties broken by the vertices' numbers, so
// the order depends on the mesh alone (as the half-edge loop's does).
struct Later {
  bool operator()(const Entry& a, const Entry& b) const {
    if (a.cost != b.cost) return a.cost > b.cost;
    if (a.v0 != b.v0) return a.v0 > b.v0;
    return a.v1 > b.v1;
  }
};

class FreeCollapser {
 public:
  FreeCollapser(FreeMesh& m, const Limits& lim) : m_(m), lim_(lim) {
    const size_t nv = m.points.size() / 3;
    faces_of_.resize(nv);
    stamp_.assign(nv, 0);
    for (uint32_t f = 0; f < uint32_t(m.alive.size()); ++f)
      if (m.alive[f])
        for (int k = 0; k < 3; ++k) faces_of_[m.tri[3 * size_t(f) + k]].push_back(f);
  }

  size_t run(double& max_error, int max_passes) {
    std::vector<std::pair<uint32_t, uint32_t>> edges = edges_left();
    for (auto [a, b] : edges) offer(a, b), offer(b, a);
    size_t total = 0;
    for (int pass = 0; pass < max_passes; ++pass) {
      const size_t done = drain(max_error);
      total += done;
      if (done == 0 || refused_.empty()) break;
      std::vector<std::pair<uint32_t, uint32_t>> retry;
      retry.swap(refused_);
      for (auto [a, b] : retry)
        if (!gone(a) && !gone(b) && adjacent(a, b)) offer(a, b);
    }
    return total;
  }

  // Every edge left, each direction by the first rule that refuses it.
  void count_refusals(SimplifyStats::Refused& r) const {
    for (auto [a, b] : edges_left())
      for (auto [v0, v1] : {std::pair{a, b}, std::pair{b, a}}) {
        double cost, e2, area;
        if (!evaluate(v0, v1, cost, e2)) ++r.bound_or_locked;
        else if (!legal(v0, v1, area)) ++r.shape;
        else ++r.legal;
      }
  }

 private:
  Vec point(uint32_t v) const {
    const float* p = &m_.points[3 * size_t(v)];
    return Vec(p[0], p[1], p[2]);
  }
  bool gone(uint32_t v) const { return m_.merged_into[v] != v; }
  const uint32_t* corners(uint32_t f) const { return &m_.tri[3 * size_t(f)]; }
  bool has(uint32_t f, uint32_t v) const {
    const uint32_t* c = corners(f);
    return c[0] == v || c[1] == v || c[2] == v;
  }
  bool adjacent(uint32_t a, uint32_t b) const {
    for (uint32_t f : faces_of_[a])
      if (m_.alive[f] && has(f, b)) return true;
    return false;
  }

  // Every edge of the faces alive, once, as (lower, higher) vertex.
  std::vector<std::pair<uint32_t, uint32_t>> edges_left() const {
    std::vector<std::pair<uint32_t, uint32_t>> e;
    for (uint32_t f = 0; f < uint32_t(m_.alive.size()); ++f) {
      if (!m_.alive[f]) continue;
      const uint32_t* c = corners(f);
      for (int k = 0; k < 3; ++k) e.emplace_back(std::min(c[k], c[(k + 1) % 3]), std::max(c[k], c[(k + 1) % 3]));
    }
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    return e;
  }

  // The bound and the cost of v0 -> v1, as the half-edge loop's evaluate().
  bool evaluate(uint32_t v0, uint32_t v1, double& cost, double& error2) const {
    if (m_.locked[v0]) return false;
    const Vec p1 = point(v1);
    error2 = 0;
    if (!m_.tol.empty()) {
      error2 = (m_.qd[v0] + m_.qd[v1]).eval(p1[0], p1[1], p1[2]);
      if (!root_within(error2, std::min(m_.tol[v0], m_.tol[v1]))) return false;
    }
    const double l2 = (p1 - point(v0)).sqrnorm();
    cost = (m_.qa[v0] + m_.qa[v1]).eval(p1[0], p1[1], p1[2]) + lim_.tie * l2 * l2;
    return true;
  }

  // The shape rules and the area rule of moving v0 onto v1 (no topology).
  bool legal(uint32_t v0, uint32_t v1, double& area_change) const {
    const Vec p0 = point(v0), p1 = point(v1);
    double twice = 0;
    for (uint32_t f : faces_of_[v0]) {
      if (!m_.alive[f]) continue;
      const uint32_t* c = corners(f);
      const int k = c[0] == v0 ? 0 : c[1] == v0 ? 1 : 2;
      const uint32_t a = c[(k + 1) % 3], b = c[(k + 2) % 3];
      if (!face_follows(p0, p1, point(a), point(b), a == v1 || b == v1, lim_, twice)) return false;
    }
    area_change = 0.5 * twice;
    return m_.area_budget.empty() || within_area_budget(m_.area_used[v0], m_.area_used[v1], area_change,
                                                        m_.area_budget[v0], m_.area_budget[v1]);
  }

  void offer(uint32_t v0, uint32_t v1) {
    double cost, e2;
    if (evaluate(v0, v1, cost, e2)) heap_.push({cost, v0, v1, stamp_[v0], stamp_[v1]});
  }

  size_t drain(double& max_error) {
    size_t done = 0;
    while (!heap_.empty()) {
      const Entry e = heap_.top();
      heap_.pop();
      if (gone(e.v0) || gone(e.v1) || e.stamp0 != stamp_[e.v0] || e.stamp1 != stamp_[e.v1]) continue;
      double area;
      if (!legal(e.v0, e.v1, area)) {
        refused_.emplace_back(e.v0, e.v1);
        continue;
      }
      double cost, e2;
      evaluate(e.v0, e.v1, cost, e2);
      max_error = std::max(max_error, std::sqrt(e2));
      collapse(e.v0, e.v1, area);
      ++done;
    }
    return done;
  }

  void collapse(uint32_t v0, uint32_t v1, double area_change) {
    std::vector<uint32_t>& into = faces_of_[v1];
    for (uint32_t f : faces_of_[v0]) {
      if (!m_.alive[f]) continue;
      if (has(f, v1)) {
        m_.alive[f] = 0;
        --m_.faces_alive;
        continue;
      }
      uint32_t* c = &m_.tri[3 * size_t(f)];
      for (int k = 0; k < 3; ++k)
        if (c[k] == v0) c[k] = v1;
      into.push_back(f);
    }
    std::vector<uint32_t>().swap(faces_of_[v0]);
    into.erase(std::remove_if(into.begin(), into.end(), [&](uint32_t f) { return !m_.alive[f]; }), into.end());
    m_.qa[v1] += m_.qa[v0];
    if (!m_.qd.empty()) m_.qd[v1] += m_.qd[v0];
    if (!m_.tol.empty()) m_.tol[v1] = std::min(m_.tol[v1], m_.tol[v0]);
    if (!m_.area_budget.empty()) {
      m_.area_used[v1] += m_.area_used[v0] + std::fabs(area_change);
      m_.area_budget[v1] = std::min(m_.area_budget[v1], m_.area_budget[v0]);
    }
    m_.merged_into[v0] = v1;
    ++stamp_[v1];
    // v1's edges cost something else now (its quadric grew): offer them again.
    neighbours_.clear();
    for (uint32_t f : into)
      for (int k = 0; k < 3; ++k)
        if (corners(f)[k] != v1) neighbours_.push_back(corners(f)[k]);
    std::sort(neighbours_.begin(), neighbours_.end());
    neighbours_.erase(std::unique(neighbours_.begin(), neighbours_.end()), neighbours_.end());
    for (uint32_t n : neighbours_) offer(v1, n), offer(n, v1);
  }

  FreeMesh& m_;
  Limits lim_;
  std::vector<std::vector<uint32_t>> faces_of_;  // per vertex: its faces (some may be dead)
  std::vector<uint32_t> stamp_;                  // per vertex: collapses taken into it
  std::priority_queue<Entry, std::vector<Entry>, Later> heap_;
  std::vector<std::pair<uint32_t, uint32_t>> refused_;
  std::vector<uint32_t> neighbours_;  // scratch
};

}  // namespace

size_t free_collapse(FreeMesh& m, const Limits& lim, double& max_error, SimplifyStats::Refused* refused,
                     int max_passes) {
  FreeCollapser c(m, lim);
  const size_t done = c.run(max_error, max_passes);
  if (refused) c.count_refusals(*refused);
  return done;
}

}  // namespace perclod::detail
