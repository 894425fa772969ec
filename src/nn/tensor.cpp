#include "nn/tensor.h"

#include "core/error.h"

namespace pleat::nn {

namespace {

std::string extent(Index v) {
  return v < 0 ? std::string("any") : std::to_string(v);
}

}  // namespace

void invalid(const char* kind, const std::string& layer, const std::string& what) {
  fail(PLEAT_ERROR_INVALID_ARGUMENT, std::string(kind) + " '" + layer + "': " + what);
}

void check_shape(const char* kind, const std::string& layer, const char* tensor, Index rows, Index cols,
                 Index expected_rows, Index expected_cols) {
  if ((expected_rows < 0 || rows == expected_rows) && (expected_cols < 0 || cols == expected_cols)) return;
  invalid(kind, layer,
          std::string(tensor) + " is " + std::to_string(rows) + "x" + std::to_string(cols) + ", expected " +
              extent(expected_rows) + "x" + extent(expected_cols));
}

void check_scratch(const char* kind, const std::string& layer, const char* workspace, size_t needed,
                   size_t capacity) {
  if (needed <= capacity) return;
  invalid(kind, layer,
          std::string(workspace) + " holds " + std::to_string(capacity) + " floats, needs " +
              std::to_string(needed) + " (call reserve() once before the hot path)");
}

}  // namespace pleat::nn
