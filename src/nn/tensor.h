#pragma once
// Shared types of the nn kernels: row-major float matrices, non-owning views,
// a grow-only scratch buffer and shape checks that throw pleat::Error.
//
// Conventions (docs/nn.md): every activation matrix is row-major with one
// row per vertex / sample; weights are stored in x out, so a layer is
// y = x W + b (PyTorch's nn.Linear weight is W transposed).
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pleat::nn {

using Index = Eigen::Index;
using MatrixRM = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowVector = Eigen::Matrix<float, 1, Eigen::Dynamic>;

// Views: bind to a MatrixRM, a Map of raw memory or a block of rows/columns
// of either, without copying (unit inner stride, any row stride). The const
// view would silently copy an incompatible (column-major) argument; pass
// row-major data only (the kernels never need a copy).
using MatrixRef = Eigen::Ref<MatrixRM, 0, Eigen::OuterStride<>>;
using ConstMatrixRef = Eigen::Ref<const MatrixRM, 0, Eigen::OuterStride<>>;
using MatrixMap = Eigen::Map<MatrixRM, 0, Eigen::OuterStride<>>;
using ConstMatrixMap = Eigen::Map<const MatrixRM, 0, Eigen::OuterStride<>>;

// Row-major view of raw memory (stride = row pitch in floats, default cols).
inline MatrixMap view(float* data, Index rows, Index cols, Index stride = -1) {
  return MatrixMap(data, rows, cols, Eigen::OuterStride<>(stride < 0 ? cols : stride));
}
inline ConstMatrixMap view(const float* data, Index rows, Index cols, Index stride = -1) {
  return ConstMatrixMap(data, rows, cols, Eigen::OuterStride<>(stride < 0 ? cols : stride));
}

// Caller-owned scratch memory: reserve() grows it (the only allocation),
// kernels only check that it is large enough and carve views out of it.
class Scratch {
 public:
  void reserve(size_t floats) {
    if (floats > buffer_.size()) buffer_.resize(floats);
  }
  size_t capacity() const { return buffer_.size(); }
  float* data() { return buffer_.data(); }
  const float* data() const { return buffer_.data(); }

 private:
  std::vector<float> buffer_;
};

// Throws pleat::Error(PLEAT_ERROR_INVALID_ARGUMENT) with
// "<kind> '<layer>': <tensor> is RxC, expected ER x EC" unless the shape
// matches. A negative expected extent matches anything.
void check_shape(const char* kind, const std::string& layer, const char* tensor, Index rows, Index cols,
                 Index expected_rows, Index expected_cols);
[[noreturn]] void invalid(const char* kind, const std::string& layer, const std::string& what);
// "needs N floats, has M; call reserve()" for a too-small workspace.
void check_scratch(const char* kind, const std::string& layer, const char* workspace, size_t needed,
                   size_t capacity);

}  // namespace pleat::nn
