#pragma once
// Bounding-volume hierarchy over axis-aligned boxes: which boxes overlap a
// query box, in O(log n + hits) instead of a scan over all of them.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pleat {

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-INFINITY);

  void extend(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void extend(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  void inflate(double r) {
    lo.array() -= r;
    hi.array() += r;
  }
  // Scalar with early exit: most tests fail on the first axis, and this is the
  // inner loop of every query.
  bool overlaps(const Box& b) const {
    for (int k = 0; k < 3; ++k)
      if (lo[k] > b.hi[k] || b.lo[k] > hi[k]) return false;
    return true;
  }
};

class BoxTree {
 public:
  // Builds over boxes[0..n): median splits along the longest axis of the box
  // centres, a few boxes per leaf.
  explicit BoxTree(std::vector<Box> boxes);

  // Calls visit(i) for every box i that overlaps `query` (in no set order).
  template <typename Visit>
  void query(const Box& query, Visit&& visit) const;

 private:
  struct Node {
    Box box;
    int32_t begin;  // leaf: items [begin, end); inner: children begin, end
    int32_t end;
    bool leaf;
  };
  int32_t build(int32_t begin, int32_t end, std::vector<Eigen::Vector3d>* centres);

  std::vector<Box> boxes_;
  std::vector<int32_t> items_;  // box indices, grouped by leaf
  std::vector<Node> nodes_;
};

template <typename Visit>
void BoxTree::query(const Box& query, Visit&& visit) const {
  if (nodes_.empty()) return;
  int32_t stack[64];  // depth is about log2(n / leaf size): far below 64
  int depth = 0;
  stack[depth++] = 0;
  while (depth > 0) {
    const Node& node = nodes_[stack[--depth]];
    if (!node.box.overlaps(query)) continue;
    if (node.leaf) {
      for (int32_t i = node.begin; i < node.end; ++i)
        if (boxes_[items_[i]].overlaps(query)) visit(items_[i]);
    } else {
      stack[depth++] = node.begin;
      stack[depth++] = node.end;
    }
  }
}

}  // namespace pleat
