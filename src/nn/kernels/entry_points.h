#pragma once
// Entry points of the network's kernels, one per instruction set (the files
// of nn/kernels, each compiled as a baseline and an AVX2 build). Callers go
// through gemm (nn/gemm.h), attention_aggregate (nn/graph_attention.h) and
// apply_activation (nn/activation.h), which pick the build from
// nn::kernel_path().
#include <cstddef>
#include <cstdint>

#include "nn/kernel_params.h"

namespace pleat::nn::kernels {

// c = a b, row-major with row strides (nn/kernels/gemm_eigen.cpp).
void gemm_baseline(const float* a, long a_stride, const float* b, long b_stride, float* c, long c_stride,
                   long m, long k, long n);
void gemm_avx2(const float* a, long a_stride, const float* b, long b_stride, float* c, long c_stride, long m,
               long k, long n);

// data[0 .. count) = act(data), in place (nn/kernels/activation_eigen.cpp).
void activate_baseline(ActivationKind kind, float parameter, float* data, long count);
void activate_avx2(ActivationKind kind, float parameter, float* data, long count);

// The attention aggregation (nn/kernels/attention_eigen.cpp). One call: destination nodes [begin, end) of a
// CSR graph (sources of node i at sources[offsets[i] .. offsets[i+1])). Meaning of each buffer:
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
