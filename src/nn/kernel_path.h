#pragma once
// Which build of the network's hot kernels runs: the GEMM (nn/gemm.h) and the
// fused attention aggregation (nn/graph_attention.h) are compiled once for
// baseline x86-64 (SSE2) and once for AVX2 + FMA (nn/kernels/), and one
// process-wide choice picks between them: the best the CPU runs, found once
// from CPUID. No environment variable; tests and benchmarks may force one.
namespace pleat::nn {

enum class KernelPath { baseline, avx2 };

// The path the kernels use: the best the CPU runs, unless set.
KernelPath kernel_path();
// For tests and benchmarks: forces a path (false, and no change, when the
// CPU cannot run it). Not thread-safe with running kernels.
bool set_kernel_path(KernelPath path);
const char* kernel_path_name(KernelPath path);  // "baseline (SSE2)", "avx2+fma"

}  // namespace pleat::nn
