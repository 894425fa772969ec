#pragma once
// Entry points of the fused attention aggregation, one per instruction set
// (nn/kernels/attention_eigen.cpp, built like the GEMM: nn/gemm.h). Callers go
// through attention_aggregate (nn/graph_attention.h), which picks the build
// from nn::kernel_path().
#include <cstddef>
#include <cstdint>

#include "nn/attention_params.h"

namespace pleat::nn::kernels {

// One call: destination nodes [begin, end) of a CSR graph (sources of node i
// at sources[offsets[i] .. offsets[i+1])). Meaning of each buffer:
// attention_aggregate in nn/graph_attention.h.
template <typename Scalar>
struct AggregateCall {
  const AttentionParamsT<Scalar>* params;
  const int32_t* offsets;
  const int32_t* sources;
  const Scalar* z;
  std::ptrdiff_t zstride;
  const Scalar* norms;
  int32_t begin, end;
  Scalar* out;
  std::ptrdiff_t ostride;
  Scalar* alpha;
  Scalar* scratch;
  Scalar* lipschitz_denominator;
};

void attention_aggregate_baseline(const AggregateCall<float>& call);
void attention_aggregate_baseline(const AggregateCall<double>& call);
void attention_aggregate_avx2(const AggregateCall<float>& call);
void attention_aggregate_avx2(const AggregateCall<double>& call);

}  // namespace pleat::nn::kernels
