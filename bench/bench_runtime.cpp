// Frames per second of the full model (DESIGN §4, the initialiser's
// architecture) on skirt-like garments of ~1k, ~4k and ~16k vertices bound to
// the MakeHuman body, per stage, with the FLOP count per frame and the
// fraction of an sgemm peak measured in the same run. Each time is a host
// playing a 64-frame clip in calls of 8 frames (seconds_per_frame).
// Usage: bench_runtime <assets dir (../shared/data)> [--quick]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_support.h"
#include "body/bvh.h"
#include "body/makehuman.h"
#include "body/motion_ops.h"
#include "garment/garment.h"
#include "nn/gemm.h"
#include "nn/kernel_path.h"
#include "nn/tensor.h"
#include "runtime/instance.h"
#include "runtime/model_init.h"
#include "spectral/blas_threads.h"

extern "C" char* openblas_get_corename(void);

using namespace pleat;
using namespace pleat::runtime;

namespace {

using Clock = std::chrono::steady_clock;

// An open cylinder (a skirt) of rings x segments vertices around the hips.
std::shared_ptr<const Garment> skirt(int rings, int segments, double hip_height) {
  Points3d v(rings * segments, 3);
  const double pi = std::acos(-1.0);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double a = 2.0 * pi * s / segments, y = hip_height + 0.1 - 0.5 * r / (rings - 1);
      const double radius = 0.19 + 0.08 * r / (rings - 1);
      v.row(r * segments + s) << radius * std::sin(a), y, radius * std::cos(a);
    }
  Triangles t((rings - 1) * segments * 2, 3);
  Eigen::Index k = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      t.row(k++) << a, a + segments, b;
      t.row(k++) << b, a + segments, b + segments;
    }
  return std::make_shared<const Garment>(build_garment(v, t, {}, "skirt"));
}

// Multiply-adds x 2 of a graph stack on a garment with `edges` attention
// edges (self loops included): the folded GEMM plus the aggregation.
double stack_flops(const GraphStack& stack, double n, double edges) {
  double f = 0;
  for (const nn::GraphAttentionLayer& l : stack.layers)
    f += 2.0 * n * double(l.in_width()) * double(l.projected_width()) +
         edges * double(l.heads) * (2.0 * double(l.head_width()) + 6.0);
  return f;
}

struct StageFlops {
  double skinning = 0, blend = 0, refinement = 0;
};

StageFlops frame_flops(const Model& m, const Garment& g, int top_k) {
  const double n = g.rest.vertex_count(), c = double(m.code_width()), s = m.joint_count();
  const double edges = double(g.graph.indices.size()) + n;
  double gru = 0;
  for (const nn::GruLayer& l : m.motion_encoder.layers)
    gru += 2.0 * m.window_frames * (double(l.w_ih.size()) + double(l.w_hh.size()));
  StageFlops f;
  f.skinning = gru + 2.0 * n * c /* fusion */ + 2.0 * n * c * s /* logits */ + 4.0 * n * s /* softmax */ +
               n * top_k * 24.0 /* LBS */;
  f.blend = f.skinning + stack_flops(m.blend, n, edges);
  f.refinement = f.blend + n * (6.0 * s + 30.0) /* features */ + stack_flops(m.refinement, n, edges);
  return f;
}

double sgemm_peak(int reps) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1, 1);
  double best = 0;
  for (auto [m, k, n] : {std::tuple<int, int, int>{4096, 128, 128}, {4096, 256, 256}, {16384, 128, 128}}) {
    nn::MatrixRM a(m, k), b(k, n), c(m, n);
    for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = u(rng);
    for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = u(rng);
    const double t = pleat_bench::median_seconds([&] { c.noalias() = a * b; }, reps);
    best = std::max(best, 2.0 * m * k * n / t * 1e-9);
  }
  return best;
}

// Seconds per frame of a host playing the clip from frame 0 in calls of 8
// consecutive frames (outputs: 8 frames), median of `reps` plays.
double seconds_per_frame(Instance& instance, const PoseSequence& poses, Stage stage,
                         const EvaluateOutputs& outputs, int reps, const EvaluateDetail& detail = {}) {
  return pleat_bench::median_seconds(
             [&] {
               for (int64_t f = 0; f < poses.frame_count; f += 8)
                 instance.evaluate(poses, f, std::min<int64_t>(8, poses.frame_count - f), stage, outputs,
                                   detail);
             },
             reps) /
         static_cast<double>(poses.frame_count);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_runtime <assets dir> [--quick]\n");
    return 2;
  }
  const std::string assets = argv[1];
  const bool quick = argc > 2 && std::strcmp(argv[2], "--quick") == 0;
  const int reps = quick ? 5 : 15;
  {
    std::ifstream load("/proc/loadavg");
    std::string line;
    std::getline(load, line);
    std::printf("load average: %s\n", line.c_str());
  }
  {
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line))
      if (line.rfind("model name", 0) == 0) {
        std::printf("cpu: %s\n", line.substr(line.find(':') + 2).c_str());
        break;
      }
  }
  const double peak = sgemm_peak(reps);
  std::printf("sgemm peak (OpenBLAS %s kernels, 2 threads, same run): %.1f GFLOP/s\n",
              openblas_get_corename(), peak);
  // Every stage is timed on each kernel path the CPU runs (nn/kernel_path.h);
  // fps and GFLOP/s are for the default, the last of them.
  std::vector<nn::KernelPath> kernels;
  for (nn::KernelPath k : {nn::KernelPath::baseline, nn::KernelPath::avx2})
    if (nn::set_kernel_path(k)) kernels.push_back(k);
  std::printf("kernel path (GEMM and attention): %s by default\n", nn::kernel_path_name(kernels.back()));

  const Body body = MakeHumanModel::load(assets + "/body")->body(makehuman_default_beta());
  ModelSkeleton skeleton{body.skeleton.names, body.skeleton.parents};
  std::vector<ShapeEntry> shape;
  for (const ShapeParameter& p : body.shape) shape.push_back({p.name, float(p.default_value)});
  std::shared_ptr<const Model> model = initialize_model(skeleton, shape, ModelInitOptions{});

  Motion motion = retarget_motion(
      resample_motion(read_bvh(assets + "/motions/cmu_mb/12_03.bvh").motion, 30.0), body.skeleton);
  const int32_t joints = body.joint_count();
  const int64_t frames = std::min<int64_t>(motion.frame_count, 64);
  std::vector<float> rotations(frames * joints * 4), roots(frames * 3);
  for (int64_t f = 0; f < frames; ++f) {
    for (int32_t j = 0; j < joints; ++j) {
      const Eigen::Quaterniond& q = motion.frame(f)[j];
      float* r = &rotations[(f * joints + j) * 4];
      r[0] = float(q.x()), r[1] = float(q.y()), r[2] = float(q.z()), r[3] = float(q.w());
    }
    for (int k = 0; k < 3; ++k) roots[f * 3 + k] = float(motion.root_translation(f, k));
  }
  PoseSequence poses{rotations.data(), roots.data(), frames, joints, 30.0};
  const double hips = body.skeleton.rest_translation(0, 1);

  std::printf("\nfull model: %lld parameters, window %d, top-k %d; batch of 8 frames per call\n",
              static_cast<long long>(parameter_count(*model)), model->window_frames, model->default_top_k);
  std::printf("%7s %7s %-12s %13s %13s %9s %9s %8s %7s\n", "N", "threads", "stage", "ms/fr baseline",
              "ms/fr avx2", "fps", "MFLOP/fr", "GFLOP/s", "% peak");
  const std::vector<std::pair<int, int>> sizes =
      quick ? std::vector<std::pair<int, int>>{{32, 32}, {64, 64}}
            : std::vector<std::pair<int, int>>{{32, 32}, {64, 64}, {128, 128}};
  for (auto [rings, segments] : sizes) {
    std::shared_ptr<const Garment> garment = skirt(rings, segments, hips);
    const StageFlops flops = frame_flops(*model, *garment, model->default_top_k);
    for (int threads : {1, 2}) {
      InstanceOptions options;
      options.threads = threads;
      options.max_batch = 8;
      Instance instance(model, garment, body, options);
      const int n = instance.vertex_count();
      std::vector<float> out(size_t(8) * n * 3);
      EvaluateOutputs outputs;
      outputs.positions = {out.data(), size_t(n) * 3};
      for (auto [stage, name, f] :
           {std::tuple<Stage, const char*, double>{Stage::skinning, "skinning", flops.skinning},
            {Stage::blend_shapes, "blend-shapes", flops.blend},
            {Stage::refinement, "full", flops.refinement}}) {
        double ms[2] = {NAN, NAN}, t = 0.0;
        for (nn::KernelPath kernel : kernels) {
          nn::set_kernel_path(kernel);
          t = seconds_per_frame(instance, poses, stage, outputs, reps);
          ms[kernel == nn::KernelPath::avx2] = t * 1e3;
        }
        const double gflops = f / t * 1e-9;
        std::printf("%7d %7d %-12s %13.3f %13.3f %9.1f %9.1f %8.1f %6.1f%%\n", n, threads, name, ms[0], ms[1],
                    1.0 / t, f * 1e-6, gflops, 100.0 * gflops / peak);
      }
    }
  }

  // What model settings cost on top of the full stage: top-k skinning
  // (decisions 0007 and 0036; "all joints" is the exact softmax), the offset
  // filter (decision 0008) and the refinement reading the fused code
  // (decision 0015), one thread, ratios to the plain model measured in the
  // same run.
  std::shared_ptr<const Garment> garment = skirt(64, 64, hips);
  std::printf("\nmodel settings, full stage, N = %d, 1 thread, batch of 8\n", garment->rest.vertex_count());
  std::printf("%-32s %9s %7s\n", "setting", "ms/frame", "ratio");
  double plain = 0.0;
  ModelInitOptions reads_code;
  reads_code.refinement_features.push_back(Feature::fused_code);
  const std::shared_ptr<const Model> fused = initialize_model(skeleton, shape, reads_code);
  for (auto [name, top_k, h, base] :
       {std::tuple<const char*, int, float, const Model*>{"top-4, no filter", 4, 0.0f, model.get()},
        {"top-8, no filter", 8, 0.0f, model.get()},
        {"top-16, no filter", 16, 0.0f, model.get()},
        {"all joints, no filter", joints, 0.0f, model.get()},
        {"top-4, filter h 1 cm", 4, 0.01f, model.get()},
        {"top-8, filter h 1 cm", 8, 0.01f, model.get()},
        {"top-8, refinement + F^t", 8, 0.0f, fused.get()},
        {"top-8, filter, refinement + F^t", 8, 0.01f, fused.get()}}) {
    auto variant = std::make_shared<Model>(*base);
    variant->default_top_k = top_k;
    variant->offset_filter_length = h;
    InstanceOptions options;
    options.max_batch = 8;
    Instance instance(variant, garment, body, options);
    std::vector<float> out(size_t(8) * instance.vertex_count() * 3);
    EvaluateOutputs outputs;
    outputs.positions = {out.data(), size_t(instance.vertex_count()) * 3};
    const double t = seconds_per_frame(instance, poses, Stage::refinement, outputs, reps);
    if (plain == 0.0) plain = t;
    std::printf("%-32s %9.3f %7.3f\n", name, t * 1e3, t / plain);
  }

  // The refinement's level of detail (pleat_evaluate_options.
  // refinement_interval), on the plain model, 2 threads, against the full
  // stage every frame and the blend-shape stage (no refinement) in the same run.
  std::printf("\nrefinement interval, N = %d, 2 threads, batch of 8 (ms/frame; ratio to every frame)\n",
              garment->rest.vertex_count());
  InstanceOptions two;
  two.threads = 2;
  two.max_batch = 8;
  Instance lod(model, garment, body, two);
  std::vector<float> lod_out(size_t(8) * lod.vertex_count() * 3);
  EvaluateOutputs lod_outputs;
  lod_outputs.positions = {lod_out.data(), size_t(lod.vertex_count()) * 3};
  const double blend = seconds_per_frame(lod, poses, Stage::blend_shapes, lod_outputs, reps);
  double every = 0.0;
  for (int interval : {1, 2, 4, 8}) {
    const double t =
        seconds_per_frame(lod, poses, Stage::refinement, lod_outputs, reps, EvaluateDetail{interval, {}});
    if (every == 0.0) every = t;
    std::printf("  every %d frame(s) %9.3f %7.3f  (%.0f fps)\n", interval, t * 1e3, t / every, 1.0 / t);
  }
  std::printf("  blend shapes only %9.3f %7.3f\n", blend * 1e3, blend / every);

  // The body-collision post-pass (pleat_evaluate_options.body_collision_distance)
  // on the skinning and full stages, against the same stage without it.
  std::printf("\nbody-collision post-pass (2 mm), same instance (ms/frame; added ms)\n");
  for (Stage stage : {Stage::skinning, Stage::refinement}) {
    const auto time = [&](float distance) {
      EvaluateDetail detail;
      detail.body_collision = distance;
      return seconds_per_frame(lod, poses, stage, lod_outputs, reps, detail);
    };
    const double without = time(0.0f), with = time(0.002f);
    std::printf("  %-14s %9.3f -> %9.3f  (+%.3f)\n", stage == Stage::skinning ? "skinning" : "full",
                without * 1e3, with * 1e3, (with - without) * 1e3);
  }
  return 0;
}
