#pragma once
// The runtime's offset filter (runtime/offset_filter.h) as an autograd
// function, so training sees the positions the runtime computes. The filter
// is x = A^{-1} d with A = I + L symmetric, so its backward is the same
// solve applied to the incoming gradient.
#include <torch/torch.h>

#include "runtime/offset_filter.h"

namespace pleat::training {

// offsets: K x N x 3 float32 on the CPU. `filter` must outlive the autograd
// graph.
torch::Tensor filter_offsets(const torch::Tensor& offsets, const runtime::OffsetFilter& filter);

}  // namespace pleat::training
