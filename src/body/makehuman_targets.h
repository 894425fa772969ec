#pragma once
// MakeHuman's macro targets (targets/macrodetails of a body directory): how
// the nine macro sliders β become per-category values (BODY_NOTES.md), and
// how those weigh the targets the manifest lists. Internal to makehuman.cpp.
#include <Eigen/Core>
#include <array>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"

namespace pleat {

// Category tokens of target names ("male", "young", "maxheight", ...), in the
// order makehuman_category_values() reports them.
constexpr size_t kMakeHumanCategoryCount = 19;
extern const std::array<const char*, kMakeHumanCategoryCount> kMakeHumanCategories;

// The value of every category for β. Throws PLEAT_ERROR_INVALID_ARGUMENT
// naming the parameter for a β of the wrong size, a value outside [0, 1] or
// non-finite, or ethnic values summing to 0.
std::array<double, kMakeHumanCategoryCount> makehuman_categories(const Eigen::VectorXd& beta);

class MakeHumanTargets {
 public:
  // Parses <dir>/targets/macrodetails/MANIFEST.tsv; target files are read on
  // first use. vertex_count bounds the indices target files may name.
  MakeHumanTargets(const std::string& dir, int32_t vertex_count);

  // Non-zero weights of the manifest's targets for β, by original path.
  std::vector<std::pair<std::string, double>> weights(const Eigen::VectorXd& beta) const;

  // Adds every target, weighted for β, to `base` (decimetres, base.obj's
  // vertices). Thread-safe: files are read under a lock.
  void add_to(const Eigen::VectorXd& beta, Points3d* base);

 private:
  struct Entry {
    std::string original;         // path under macrodetails/, e.g. "height/...-maxheight.target"
    int32_t stored = -1;          // index into stored_files_
    std::vector<int32_t> tokens;  // indices into kMakeHumanCategories
  };
  struct Offsets {
    bool loaded = false;
    std::vector<int32_t> index;
    std::vector<float> offset;  // 3 per index, decimetres
  };
  const Offsets& stored(int32_t i);

  std::string folder_;
  int32_t vertex_count_ = 0;
  std::vector<Entry> manifest_;
  std::vector<std::string> stored_files_;  // relative to folder_; several targets may share one
  std::mutex mutex_;
  std::vector<Offsets> stored_;
};

}  // namespace pleat
