#include "core/box_tree.h"

#include <algorithm>

namespace pleat {

constexpr int32_t kLeafSize = 4;

BoxTree::BoxTree(std::vector<Box> boxes) : boxes_(std::move(boxes)) {
  if (boxes_.empty()) return;
  std::vector<Eigen::Vector3d> centres(boxes_.size());
  for (size_t i = 0; i < boxes_.size(); ++i) centres[i] = 0.5 * (boxes_[i].lo + boxes_[i].hi);
  items_.resize(boxes_.size());
  for (size_t i = 0; i < items_.size(); ++i) items_[i] = static_cast<int32_t>(i);
  nodes_.reserve(2 * boxes_.size() / kLeafSize + 1);
  build(0, static_cast<int32_t>(items_.size()), &centres);
}

int32_t BoxTree::build(int32_t begin, int32_t end, std::vector<Eigen::Vector3d>* centres) {
  int32_t id = static_cast<int32_t>(nodes_.size());
  nodes_.push_back({Box(), begin, end, true});
  Box box, centre_box;
  for (int32_t i = begin; i < end; ++i) {
    box.extend(boxes_[items_[i]]);
    centre_box.extend((*centres)[items_[i]]);
  }
  nodes_[id].box = box;
  if (end - begin <= kLeafSize) return id;
  // Median split: balanced depth whatever the distribution of the boxes.
  int axis;
  (centre_box.hi - centre_box.lo).maxCoeff(&axis);
  int32_t mid = begin + (end - begin) / 2;
  std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                   [&](int32_t a, int32_t b) { return (*centres)[a][axis] < (*centres)[b][axis]; });
  int32_t left = build(begin, mid, centres);
  int32_t right = build(mid, end, centres);
  nodes_[id] = {box, left, right, false};
  return id;
}

}  // namespace pleat
