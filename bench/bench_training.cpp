// Training throughput (frames per second, forward + backward) of the full
// network on the MakeHuman sample dress (2,205 vertices) bound to the
// MakeHuman body, with the custom graph-attention op and with the generic
// index_add formulation; plus one FlexiGAT 64->64 layer at N = 3000 x batch 8
// (DESIGN §6's measurement of index_add).
// Usage: bench_training <assets dir (../shared/data)> <repository root> [--quick]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>

#include "attention_op.h"
#include "bench_support.h"
#include "body/bvh.h"
#include "body/makehuman.h"
#include "body/motion_ops.h"
#include "garment/garment.h"
#include "io/mesh_import.h"
#include "network.h"
#include "runtime/model_init.h"

using namespace pleat;

namespace {}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_training <assets dir> <repository root> [--quick]\n");
    return 2;
  }
  const std::string assets = argv[1], repo = argv[2];
  const int reps = argc > 3 && std::strcmp(argv[3], "--quick") == 0 ? 3 : 7;
  {
    std::ifstream load("/proc/loadavg");
    std::string line;
    std::getline(load, line);
    std::printf("load average: %s; torch threads %d\n", line.c_str(), at::get_num_threads());
  }
  const Body body = MakeHumanModel::load(assets + "/body")->body(makehuman_default_beta());
  const ImportedMesh mesh = import_mesh(repo + "/data/garments/female_elegantsuit01.obj");
  GarmentBuildOptions go;
  go.unit_scale = 0.1;
  const auto garment =
      std::make_shared<const Garment>(build_garment(mesh.vertices, mesh.triangles, go, "dress"));
  std::vector<runtime::ShapeEntry> shape;
  for (const ShapeParameter& p : body.shape) shape.push_back({p.name, float(p.default_value)});
  const auto model = runtime::initialize_model({body.skeleton.names, body.skeleton.parents}, shape, {});
  const Motion walk = retarget_motion(
      resample_motion(read_bvh(repo + "/tests/fixtures/motion/12_03_walk_121.bvh").motion, 30.0),
      body.skeleton);
  std::vector<float> rotations, roots;
  for (int64_t f = 0; f < walk.frame_count; ++f) {
    for (int32_t j = 0; j < body.joint_count(); ++j) {
      const Eigen::Quaterniond& q = walk.frame(f)[j];
      rotations.insert(rotations.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    }
    for (int k = 0; k < 3; ++k) roots.push_back(float(walk.root_translation(f, k)));
  }
  const runtime::PoseSequence poses{rotations.data(), roots.data(), walk.frame_count, body.joint_count(),
                                    30.0};
  training::BoundGarment bound(*model, garment, body);
  training::Network network(*model);
  const std::vector<int64_t> frames = {4, 11, 18, 25};
  const auto batch_seconds = [&](training::Network& net, const training::BoundGarment& b) {
    return pleat_bench::median_seconds(
        [&] {
          net->zero_grad();
          net->forward(b, poses, frames, runtime::Stage::refinement).positions.pow(2).mean().backward();
        },
        reps);
  };
  std::printf("full network (%zu parameter tensors), N = %lld, batch of %zu frames, forward + backward:\n",
              network->parameters().size(), static_cast<long long>(bound.vertex_count()), frames.size());
  double custom = 0;
  for (bool generic : {false, true}) {
    network->set_generic_attention(generic);
    const double t = batch_seconds(network, bound);
    if (!generic) custom = t;
    std::printf("  %-34s %8.1f ms per batch  %6.2f frames/s\n",
                generic ? "generic index_add" : "custom op (runtime kernel)", t * 1e3,
                double(frames.size()) / t);
  }
  // The body encoder over every 8th of the 13,380 body vertices.
  runtime::ModelInitOptions strided_options;
  strided_options.body_vertex_stride = 8;
  const auto strided =
      runtime::initialize_model({body.skeleton.names, body.skeleton.parents}, shape, strided_options);
  training::BoundGarment strided_bound(*strided, garment, body);
  training::Network strided_network(*strided);
  const double t = batch_seconds(strided_network, strided_bound);
  std::printf("  %-34s %8.1f ms per batch  %6.2f frames/s  (%.2fx the stride-1 time)\n",
              "custom op, body_vertex_stride 8", t * 1e3, double(frames.size()) / t, t / custom);

  // One FlexiGAT 64 -> 64 layer, 4 heads, on 8 copies of a ~3000-vertex grid.
  const int side = 55;
  Csr csr;
  csr.offsets = {0};
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c) {
      for (auto [dr, dc] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {-1, -1}, {1, 1}}) {
        const int rr = r + dr, cc = c + dc;
        if (rr >= 0 && rr < side && cc >= 0 && cc < side) csr.indices.push_back(rr * side + cc);
      }
      std::sort(csr.indices.begin() + csr.offsets.back(), csr.indices.end());
      csr.offsets.push_back(static_cast<int32_t>(csr.indices.size()));
    }
  nn::AttentionGraph one = nn::attention_graph(csr), batch;
  batch.offsets = {0};
  batch.max_degree = one.max_degree;
  for (int c = 0; c < 8; ++c) {
    const int32_t base = static_cast<int32_t>(batch.sources.size()), shift = c * one.node_count();
    for (int32_t s : one.sources) batch.sources.push_back(s + shift);
    for (int32_t i = 1; i <= one.node_count(); ++i) batch.offsets.push_back(base + one.offsets[i]);
  }
  nn::GraphAttentionLayer spec = model->refinement.layers[1];  // 64 -> 64, 4 heads, flexigat
  training::GraphAttention layer(spec);
  const torch::Tensor v = torch::randn({batch.node_count(), spec.in_width()}).requires_grad_(true);
  std::printf("one FlexiGAT %lld->%lld layer, 4 heads, N = %d (8 x %d), forward + backward:\n",
              static_cast<long long>(spec.in_width()), static_cast<long long>(spec.out_width()),
              batch.node_count(), one.node_count());
  for (bool generic : {false, true}) {
    const double t = pleat_bench::median_seconds(
        [&] {
          layer->zero_grad();
          layer->forward(v, batch, generic).pow(2).mean().backward();
        },
        reps);
    std::printf("  %-26s %8.1f ms\n", generic ? "generic index_add" : "custom op (runtime kernel)", t * 1e3);
  }
  return 0;
}
