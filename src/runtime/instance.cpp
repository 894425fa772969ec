// Instance: binding (everything pose-independent, once) and per-frame
// evaluation in preallocated workspaces. docs/runtime.md defines every
// feature; the order of operations here is the contract the trainer's
// forward pass reproduces.
#include "runtime/instance.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "capi/pleat.h"
#include "core/error.h"
#include "core/geometry.h"
#include "nn/gemm.h"
#include "nn/mlp.h"
#include "nn/parallel.h"
#include "runtime/binding.h"
#include "runtime/body_collision.h"
#include "runtime/frame_features.h"
#include "runtime/vertex_mask.h"
#include "spectral/band_split.h"
#include "spectral/blas_threads.h"

namespace pleat::runtime {
namespace {

using nn::ConstMatrixRef;
using nn::MatrixRef;
using nn::MatrixRM;
using nn::view;

constexpr int32_t kRowBlock = nn::kAttentionTaskRows;
constexpr double kUnitTolerance = 1e-3;  // allowed | |q| - 1 | of a pose rotation

[[noreturn]] void bad(const std::string& what) {
  fail(PLEAT_ERROR_INVALID_ARGUMENT, what);
}

// fn(begin, end) over rows [0, n) in fixed blocks of kRowBlock, so the work
// of a row never depends on the executor. fn must not throw.
template <typename Fn>
void for_row_blocks(nn::Executor& executor, int32_t n, const Fn& fn) {
  struct Context {
    const Fn* fn;
    int32_t n;
  } context{&fn, n};
  executor.run((n + kRowBlock - 1) / kRowBlock,
               [](void* c, int32_t task) {
                 const Context& ctx = *static_cast<const Context*>(c);
                 const int32_t begin = task * kRowBlock;
                 (*ctx.fn)(begin, std::min(ctx.n, begin + kRowBlock));
               },
               &context);
}

// Ping-pong buffers of a graph stack plus its attention workspace; one set
// serves every stack of an instance (sized for the largest).
struct StackBuffers {
  std::vector<float> a, b;
  nn::GraphAttentionWorkspace attention;

  void reserve(const GraphStack& stack, const nn::AttentionGraph& graph) {
    Index widest = 0;
    for (const nn::GraphAttentionLayer& l : stack.layers) {
      widest = std::max(widest, l.out_width());
      attention.reserve(l, graph);
    }
    const size_t floats = static_cast<size_t>(graph.node_count()) * static_cast<size_t>(widest);
    if (a.size() < floats) a.resize(floats);
    if (b.size() < floats) b.resize(floats);
  }
};

// in (N x stack input) -> out (N x 3 or code width) through every layer;
// `first` (if given) replaces the stack's first layer.
void run_stack(const GraphStack& stack, const nn::AttentionGraph& graph, ConstMatrixRef in, MatrixRef out,
               StackBuffers& buffers, nn::Executor& executor,
               const nn::GraphAttentionLayer* first = nullptr) {
  const Index n = graph.node_count();
  const float* source = in.data();
  Index source_stride = in.outerStride(), source_width = in.cols();
  for (size_t i = 0; i < stack.layers.size(); ++i) {
    const nn::GraphAttentionLayer& layer = i == 0 && first ? *first : stack.layers[i];
    const bool last = i + 1 == stack.layers.size();
    float* target = last ? out.data() : (i % 2 == 0 ? buffers.a.data() : buffers.b.data());
    const Index target_stride = last ? out.outerStride() : layer.out_width();
    nn::graph_attention_forward(layer, graph, view(source, n, source_width, source_stride),
                                view(target, n, layer.out_width(), target_stride), buffers.attention, nullptr,
                                &executor);
    source = target;
    source_stride = target_stride;
    source_width = layer.out_width();
  }
}

}  // namespace

struct Instance::State {
  std::shared_ptr<const Model> model;
  std::shared_ptr<const Garment> garment;
  int32_t n = 0, joints = 0, window = 0, top_k = 0, max_batch = 0;
  Index code = 0;

  std::unique_ptr<Binding> binding;  // joint map, rest joints, encoder inputs, prior, graph, T̄
  FrameFeatures features;            // pose -> network inputs (frame_features.h)
  MatrixRM fused_static;             // N x C: G ⊙ b, pose-independent part of F^t

  nn::SerialExecutor serial;
  std::unique_ptr<nn::ThreadPool> pool;
  nn::Executor* executor = nullptr;

  // Per-frame workspaces (sized at bind; evaluate never grows them).
  Quaternions pose;          // S, body order
  Transforms pose_global;    // S, body order
  SkinMatrices matrices;     // S, body order
  MatrixRM skin;             // S x 12 float [R | t] rows, model order
  MatrixRM joint_positions;  // S x 3 posed joints, model order
  // Motion codes q^t of a batch's frames, computed in parallel, one window
  // per task (results cannot depend on the split), with a window and a GRU
  // workspace per frame of the batch; row max_batch serves frames outside a
  // batch (history).
  std::vector<MatrixRM> window_x;  // max_batch + 1, each window x motion input
  std::vector<nn::GruWorkspace> gru;
  MatrixRM motion_codes;  // (max_batch + 1) x C
  // F^t never exists: F^t W = (G ⊙ b) (diag(q^t) W), so each frame scales
  // the rows of the skinning head and of the blend stack's first folded
  // projection by q^t (C x S and C x (H d' + 2H) values) instead of N x C.
  MatrixRM skinning_q;                  // C x S
  nn::GraphAttentionLayer blend_first;  // model.blend.layers[0] with folded scaled by q^t
  MatrixRM logits;                      // N x S
  MatrixRM offsets;                     // N x 3: blend shapes, their posed displacement, or refinement
  MatrixRM skinned[2];                  // N x 3: M̃ of the current and the previous frame
  MatrixRM normals;                     // N x 3
  MatrixRM refinement_in;               // N x refinement input
  MatrixRM refined;                     // N x 3: Δ of the last refined frame (heading frame, filtered)
  MatrixRM refined_bands[3];            // N x 3 each: low, mid, high of Δ (prepared garment only)
  StackBuffers stacks;
  std::vector<int32_t> chosen_joint;  // max_batch x N x k (model joints)
  std::vector<float> chosen_weight;   // max_batch x N x k
  MatrixRM staged;                    // max_batch x (N * 3): positions of the batch
  BodyCollision collision;            // the post-pass's candidates and workspace
  BandSplitScratch<float> band_scratch;

  // Vertex mask (empty `masked`: none). The stacks then run on its regions'
  // subgraphs, their rows compact: fused_masked holds fused_static's rows of
  // the blend region, region_out a stack's output.
  VertexMask mask;
  MatrixRM fused_masked;  // |blend region| x C
  MatrixRM region_out;    // max region x 3
  MatrixRM lbs;           // N x 3: the masked vertices' skinned positions (while a mask is set)

  // M̃ (with blend shapes) of the last frame a call evaluated stays in
  // skinned[last_slot]; the next call needs it for its first frame's
  // velocities, so a host playing a clip in calls of any size skins every
  // frame once. Valid while last_frame >= 0 and the poses it was computed
  // from (frames [last_frame - window, last_frame], copied into last_inputs)
  // are bit for bit the next call's.
  int64_t last_frame = -1;
  int last_slot = 0;
  std::vector<float> last_inputs;  // (window + 1) x (S x 4 + 3)

  void bind(const Body& body, const InstanceOptions& options);
  void check_poses(const PoseSequence& poses, int64_t begin, int64_t end) const;
  void motion_code(const PoseSequence& poses, int64_t t, int32_t row);
  void skin_frame(const PoseSequence& poses, int64_t t, Stage stage, int slot, float* weights_out,
                  int32_t* joints_out, int32_t code_row);
  void refine_offsets(const PoseSequence& poses, int64_t t, const MatrixRM* previous, int slot,
                      int32_t code_row, const float* band_attenuation);
  void add_refinement(const PoseSequence& poses, int64_t t, int slot, float* out) const;
  void write_batch(int64_t first_in_call, int64_t begin, int64_t count, const EvaluateOutputs& outputs);
  void set_vertex_mask(const uint8_t* flags);
  void blend_offsets();
  // Compares frame t's inputs with last_inputs, or copies them there.
  bool same_inputs(const PoseSequence& poses, int64_t t) const;
  void keep_inputs(const PoseSequence& poses, int64_t t);
};

void Instance::State::bind(const Body& body, const InstanceOptions& options) {
  const Model& m = *model;
  const Garment& g = *garment;
  n = g.rest.vertex_count();
  joints = m.joint_count();
  window = m.window_frames;
  code = m.code_width();
  if (options.threads < 1 || options.threads > 256)
    bad("instance threads is " + std::to_string(options.threads) + ", expected 1..256");
  if (options.max_batch < 1 || options.max_batch > 4096)
    bad("instance max_batch is " + std::to_string(options.max_batch) + ", expected 1..4096");
  if (options.top_k < 0) bad("instance top_k is " + std::to_string(options.top_k) + ", expected >= 0");
  top_k = std::min(options.top_k > 0 ? options.top_k : m.default_top_k, joints);
  max_batch = options.max_batch;

  binding = bind_inputs(m, g, body);
  collision = BodyCollision(body, binding->rest, binding->model_of_body);
  features = FrameFeatures(m, binding->skeleton, binding->body_of_model);

  // Body code b: the body encoder over every body vertex, [mean | max], pool.
  const MatrixRM& body_x = binding->body_input;
  MatrixRM body_h(body_x.rows(), m.body_encoder.out_width());
  nn::MlpWorkspace mlp_workspace;
  mlp_workspace.reserve(m.body_encoder, body_x.rows());
  nn::mlp_forward(m.body_encoder, body_x, body_h, mlp_workspace);
  MatrixRM pooled(1, 2 * body_h.cols());
  pooled.leftCols(body_h.cols()) = body_h.colwise().mean();
  pooled.rightCols(body_h.cols()) = body_h.colwise().maxCoeff();
  MatrixRM body_code(1, code);
  nn::dense_forward(m.body_pool, pooled, m.body_pool_activation, body_code);

  // Garment encoder G on the rest garment, fused with b.
  stacks.reserve(m.garment_encoder, binding->graph);
  fused_static.resize(n, code);
  run_stack(m.garment_encoder, binding->graph, binding->garment_input, fused_static, stacks, serial);
  fused_static.array().rowwise() *= body_code.row(0).array();

  if (options.threads > 1) pool = std::make_unique<nn::ThreadPool>(options.threads);
  executor = pool ? static_cast<nn::Executor*>(pool.get()) : &serial;

  // Workspaces.
  pose.resize(static_cast<size_t>(joints));
  pose_global.resize(static_cast<size_t>(joints));
  matrices.resize(static_cast<size_t>(joints));
  skin.resize(joints, 12);
  joint_positions.resize(joints, 3);
  window_x.assign(static_cast<size_t>(max_batch) + 1, MatrixRM(window, m.motion_encoder.input_width()));
  gru.resize(static_cast<size_t>(max_batch) + 1);
  for (nn::GruWorkspace& w : gru) w.reserve(m.motion_encoder, 1);
  motion_codes.resize(max_batch + 1, code);
  skinning_q.resize(code, joints);
  blend_first = m.blend.layers.front();
  logits.resize(n, joints);
  offsets.resize(n, 3);
  skinned[0].resize(n, 3);
  skinned[1].resize(n, 3);
  normals.resize(n, 3);
  refinement_in.resize(n, m.refinement.in_width());
  refined.resize(n, 3);
  stacks.reserve(m.blend, binding->graph);
  stacks.reserve(m.refinement, binding->graph);
  const size_t chosen = static_cast<size_t>(max_batch) * static_cast<size_t>(n) * static_cast<size_t>(top_k);
  chosen_joint.resize(chosen);
  chosen_weight.resize(chosen);
  staged.resize(max_batch, static_cast<Index>(n) * 3);
  last_inputs.resize(static_cast<size_t>(window + 1) * (static_cast<size_t>(joints) * 4 + 3));
  if (g.prepared) {
    for (MatrixRM& band : refined_bands) band.resize(n, 3);
    // One split of a full batch grows the scratch to its final size.
    MatrixRM probe = MatrixRM::Zero(max_batch, static_cast<Index>(n) * 3);
    MatrixRM sink(max_batch, static_cast<Index>(n) * 3);
    split_bands(g.prepared->bands, probe.data(), static_cast<size_t>(max_batch), static_cast<size_t>(n) * 3,
                sink.data(), static_cast<size_t>(n) * 3, static_cast<float*>(nullptr), 0,
                static_cast<float*>(nullptr), 0, &band_scratch);
  }
}

void Instance::State::check_poses(const PoseSequence& poses, int64_t begin, int64_t end) const {
  for (int64_t f = begin; f < end; ++f) {
    for (int32_t j = 0; j < joints; ++j) {
      const float* q = poses.rotations + (f * joints + j) * 4;
      const double norm =
          std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
      if (!std::isfinite(norm) || std::abs(norm - 1.0) > kUnitTolerance)
        bad("poses frame " + std::to_string(f) + " joint " + std::to_string(j) + " '" +
            binding->skeleton.names[j] + "': rotation is not a unit quaternion (norm " +
            std::to_string(norm) + ")");
    }
    for (int k = 0; k < 3; ++k) {
      const float x = poses.root_positions[f * 3 + k];
      if (!std::isfinite(x) || std::abs(x) > kMaxCoordinate)
        bad("poses frame " + std::to_string(f) + ": root position is not finite or beyond " +
            std::to_string(kMaxCoordinate) + " m");
    }
  }
}

// q^t into motion_codes.row(row), with that row's window and workspace.
// One frame's window at a time: a batch of windows would change the GEMM
// shapes and with them the rounding, and results must not depend on batching.
void Instance::State::motion_code(const PoseSequence& poses, int64_t t, int32_t row) {
  const Model& m = *model;
  MatrixRM& x = window_x[static_cast<size_t>(row)];
  features.motion_window(poses, t, x);
  normalize_rows(m.motion_normalization, x, 0, window);
  nn::gru_window(m.motion_encoder, x, window, motion_codes.middleRows(row, 1), gru[static_cast<size_t>(row)]);
}

// M̃ of frame t into skinned[slot]: fusion with the motion code in
// motion_codes.row(code_row) (computed here when code_row is max_batch),
// skinning weights (top k written to weights_out / joints_out, N x k), blend
// shapes (stage >= blend_shapes), LBS.
void Instance::State::skin_frame(const PoseSequence& poses, int64_t t, Stage stage, int slot,
                                 float* weights_out, int32_t* joints_out, int32_t code_row) {
  const Model& m = *model;
  if (code_row == max_batch) motion_code(poses, t, code_row);
  features.skinning_matrices(poses, t, pose, pose_global, binding->rest_global, matrices, skin,
                             joint_positions);

  const int32_t k = top_k;
  const bool blend = stage != Stage::skinning;
  const auto q = motion_codes.row(code_row).transpose().array();
  skinning_q = m.skinning.weight.array().colwise() * q;
  if (blend) blend_first.folded = m.blend.layers.front().folded.array().colwise() * q;
  for_row_blocks(*executor, n, [&](int32_t begin, int32_t end) {
    const Index rows = end - begin;
    auto l = logits.middleRows(begin, rows);
    nn::gemm(fused_static.middleRows(begin, rows), skinning_q, l);
    if (m.skinning.bias.size() != 0) l.rowwise() += m.skinning.bias;
    if (binding->prior.size() != 0) l += binding->prior.middleRows(begin, rows);
    for (int32_t v = begin; v < end; ++v)
      top_k_softmax(logits.row(v).data(), joints, k, weights_out + static_cast<size_t>(v) * k,
                    joints_out + static_cast<size_t>(v) * k);
  });
  if (blend) blend_offsets();
  // M̃ = M [T̄; 1] + M [blend_scale B; 0] with M = Σ w_k S_k (3 x 4): the
  // blend shapes' posed displacement is the second term, and the offset
  // filter smooths that (posed, where the skinning weights have mixed in).
  MatrixRM& out = skinned[slot];
  const bool filter = blend && binding->offset_filter;
  const bool masked = !mask.masked.empty();
  for_row_blocks(*executor, n, [&](int32_t begin, int32_t end) {
    for (int32_t v = begin; v < end; ++v) {
      // M as 12-float packets: half the instructions of an element loop at 8 or 31 joints.
      Eigen::Matrix<float, 12, 1> sum = Eigen::Matrix<float, 12, 1>::Zero();
      for (int32_t i = 0; i < k; ++i)
        sum.noalias() += weights_out[static_cast<size_t>(v) * k + i] *
                         Eigen::Map<const Eigen::Matrix<float, 12, 1>>(
                             skin.row(joints_out[static_cast<size_t>(v) * k + i]).data());
      const float* s = sum.data();
      const float x = binding->rest(v, 0), y = binding->rest(v, 1), z = binding->rest(v, 2);
      out(v, 0) = s[0] * x + s[1] * y + s[2] * z + s[3];
      out(v, 1) = s[4] * x + s[5] * y + s[6] * z + s[7];
      out(v, 2) = s[8] * x + s[9] * y + s[10] * z + s[11];
      if (!blend) continue;
      if (masked) lbs.row(v) = out.row(v);
      const float bx = m.blend_scale * offsets(v, 0), by = m.blend_scale * offsets(v, 1),
                  bz = m.blend_scale * offsets(v, 2);
      const float dx = s[0] * bx + s[1] * by + s[2] * bz, dy = s[4] * bx + s[5] * by + s[6] * bz,
                  dz = s[8] * bx + s[9] * by + s[10] * bz;
      if (filter) {  // kept apart until the filter has run
        offsets(v, 0) = dx, offsets(v, 1) = dy, offsets(v, 2) = dz;
      } else {
        out(v, 0) += dx, out(v, 1) += dy, out(v, 2) += dz;
      }
    }
  });
  if (filter) {
    binding->offset_filter->apply(offsets.data(), 1);
    out += offsets;
  }
}

// Δ^t into `refined` (heading frame, offset filter applied, bands
// attenuated unless band_attenuation is null) from skinned[slot], the
// previous frame's M̃ (null: the clip's first frame, velocity 0) and frame
// t's motion code in motion_codes.row(code_row).
void Instance::State::refine_offsets(const PoseSequence& poses, int64_t t, const MatrixRM* previous, int slot,
                                     int32_t code_row, const float* band_attenuation) {
  const Model& m = *model;
  const MatrixRM& current = skinned[slot];
  vertex_normals(current.data(), n, garment->rest.triangles, normals.data());
  // skin_frame left frame t's posed joints in joint_positions.
  const Eigen::Matrix3f heading = features.heading(poses, t).cast<float>();
  const float fps = static_cast<float>(m.frame_rate);
  const bool masked = !mask.masked.empty();
  const SubGraph& region = mask.refinement;
  const int32_t rows = masked ? static_cast<int32_t>(region.vertices.size()) : n;
  for_row_blocks(*executor, rows, [&](int32_t begin, int32_t end) {
    for (int32_t i = begin; i < end; ++i) {
      const int32_t v = masked ? region.vertices[static_cast<size_t>(i)] : i;
      Eigen::Vector3f velocity = Eigen::Vector3f::Zero();
      if (previous != nullptr) velocity = (current.row(v) - previous->row(v)).transpose() * fps;
      const FrameFeatures::FusedCode fused{fused_static.row(v).data(), motion_codes.row(code_row).data(),
                                           code};
      features.refinement_row(m.refinement.features, heading, velocity, normals.row(v).transpose(),
                              current.row(v).transpose(), joint_positions, fused,
                              refinement_in.row(i).data());
    }
    normalize_rows(m.refinement.normalization, refinement_in, begin, end);
  });
  if (!masked) {
    run_stack(m.refinement, binding->graph, refinement_in, refined, stacks, *executor);
  } else {
    refined.setZero();
    if (rows > 0) {
      run_stack(m.refinement, region.graph, refinement_in.topRows(rows), region_out.topRows(rows), stacks,
                *executor);
      for (size_t a = 0; a < mask.active.size(); ++a)
        refined.row(mask.active[a]) = region_out.row(mask.active_in_refinement[a]);
    }
  }
  if (binding->offset_filter) binding->offset_filter->apply(refined.data(), 1);
  if (band_attenuation != nullptr) {
    // Band split is linear per coordinate, so it commutes with the heading
    // rotation applied later.
    const size_t floats = static_cast<size_t>(n) * 3;
    split_bands(garment->prepared->bands, refined.data(), 1, floats, refined_bands[0].data(), floats,
                refined_bands[1].data(), floats, refined_bands[2].data(), floats, &band_scratch);
    for (int b = 0; b < 3; ++b)
      if (band_attenuation[b] > 0.0f) refined -= band_attenuation[b] * refined_bands[b];
  }
}

// M^t = M̃^t + refinement_scale * H_t Δ into `out` (N x 3), with M̃^t in
// skinned[slot] and Δ in `refined` (frame t's own, or the last refined
// frame's when the refinement is held).
void Instance::State::add_refinement(const PoseSequence& poses, int64_t t, int slot, float* out) const {
  const Model& m = *model;
  const MatrixRM& current = skinned[slot];
  const Eigen::Matrix3f heading = features.heading(poses, t).cast<float>();
  for_row_blocks(*executor, n, [&](int32_t begin, int32_t end) {
    for (int32_t v = begin; v < end; ++v) {
      const Eigen::Vector3f delta = heading * refined.row(v).transpose();
      for (int c = 0; c < 3; ++c) out[v * 3 + c] = current(v, c) + m.refinement_scale * delta[c];
    }
  });
}

// The blend stack's output B into `offsets`: on the whole garment, or with a
// mask on the blend region, kept where M̃ must be exact and zero elsewhere.
void Instance::State::blend_offsets() {
  const Model& m = *model;
  if (mask.masked.empty()) {
    run_stack(m.blend, binding->graph, fused_static, offsets, stacks, *executor, &blend_first);
    return;
  }
  offsets.setZero();
  const auto rows = static_cast<Index>(mask.blend.vertices.size());
  if (rows == 0) return;
  run_stack(m.blend, mask.blend.graph, fused_masked, region_out.topRows(rows), stacks, *executor,
            &blend_first);
  for (int32_t i : mask.posed_in_blend)
    offsets.row(mask.blend.vertices[static_cast<size_t>(i)]) = region_out.row(i);
}

// M̃ of frame t reads frames [t - window, t] of the poses (motion window and
// its root velocities; skinning matrices of t), clamped at 0: those
// rotations and root positions, as two spans.
namespace {
struct PoseInputs {
  const float* rotations;
  size_t rotation_floats;
  const float* roots;
  size_t root_floats;
};
PoseInputs pose_inputs(const PoseSequence& poses, int64_t t, int32_t window, int32_t joints) {
  const int64_t lo = std::max<int64_t>(0, t - window), frames = t - lo + 1;
  return {poses.rotations + lo * joints * 4, static_cast<size_t>(frames * joints * 4),
          poses.root_positions + lo * 3, static_cast<size_t>(frames * 3)};
}
}  // namespace

bool Instance::State::same_inputs(const PoseSequence& poses, int64_t t) const {
  const PoseInputs in = pose_inputs(poses, t, window, joints);
  return std::memcmp(in.rotations, last_inputs.data(), in.rotation_floats * sizeof(float)) == 0 &&
         std::memcmp(in.roots, last_inputs.data() + in.rotation_floats, in.root_floats * sizeof(float)) == 0;
}

void Instance::State::keep_inputs(const PoseSequence& poses, int64_t t) {
  const PoseInputs in = pose_inputs(poses, t, window, joints);
  std::copy(in.rotations, in.rotations + in.rotation_floats, last_inputs.data());
  std::copy(in.roots, in.roots + in.root_floats, last_inputs.data() + in.rotation_floats);
}

void Instance::State::set_vertex_mask(const uint8_t* flags) {
  const Model& m = *model;
  last_frame = -1;  // M̃ depends on the mask's regions
  mask = flags ? make_vertex_mask(binding->graph, flags, static_cast<int32_t>(m.blend.layers.size()),
                                  static_cast<int32_t>(m.refinement.layers.size()))
               : VertexMask{};
  if (mask.masked.empty()) {  // free what an earlier mask held
    fused_masked = MatrixRM();
    region_out = MatrixRM();
    lbs = MatrixRM();
    return;
  }
  fused_masked.resize(static_cast<Index>(mask.blend.vertices.size()), code);
  for (size_t i = 0; i < mask.blend.vertices.size(); ++i)
    fused_masked.row(static_cast<Index>(i)) = fused_static.row(mask.blend.vertices[i]);
  region_out.resize(static_cast<Index>(std::max(mask.blend.vertices.size(), mask.refinement.vertices.size())),
                    3);
  lbs.resize(n, 3);
  stacks.reserve(m.blend, mask.blend.graph);
  stacks.reserve(m.refinement, mask.refinement.graph);
}

void Instance::State::write_batch(int64_t first_in_call, int64_t begin, int64_t count,
                                  const EvaluateOutputs& outputs) {
  const size_t frame_floats = static_cast<size_t>(n) * 3;
  for (int64_t b = 0; b < count; ++b) {
    const float* x = staged.row(b).data();
    for (size_t i = 0; i < frame_floats; ++i)
      if (!std::isfinite(x[i]))
        fail(PLEAT_ERROR_NUMERICAL, "model '" + model->source + "' gave a non-finite position at frame " +
                                        std::to_string(begin + b) + " vertex " + std::to_string(i / 3) +
                                        " (frames before it were written)");
  }
  for (int64_t b = 0; b < count; ++b) {
    const size_t at = static_cast<size_t>(begin + b - first_in_call);
    const float* x = staged.row(b).data();
    if (outputs.positions.data)
      std::copy(x, x + frame_floats, outputs.positions.data + at * outputs.positions.stride);
    if (outputs.normals.data)
      vertex_normals(x, n, garment->rest.triangles, outputs.normals.data + at * outputs.normals.stride);
    if (outputs.skinning_weights.data) {
      float* w = outputs.skinning_weights.data + at * outputs.skinning_weights.stride;
      std::fill(w, w + static_cast<size_t>(n) * joints, 0.0f);
      const size_t base = static_cast<size_t>(b) * n * top_k;
      for (int32_t v = 0; v < n; ++v)
        for (int32_t i = 0; i < top_k; ++i)
          w[static_cast<size_t>(v) * joints + chosen_joint[base + v * top_k + i]] =
              chosen_weight[base + v * top_k + i];
    }
  }
  if (outputs.low.data || outputs.mid.data || outputs.high.data) {
    const size_t at = static_cast<size_t>(begin - first_in_call);
    const auto band = [&](const OutputBuffer& o) { return o.data ? o.data + at * o.stride : nullptr; };
    split_bands(garment->prepared->bands, staged.data(), static_cast<size_t>(count), frame_floats,
                band(outputs.low), outputs.low.stride, band(outputs.mid), outputs.mid.stride,
                band(outputs.high), outputs.high.stride, &band_scratch);
  }
}

Instance::Instance(std::shared_ptr<const Model> model, std::shared_ptr<const Garment> garment,
                   const Body& body, const InstanceOptions& options)
    : state_(std::make_unique<State>()) {
  if (!model || !garment) bad("instance needs a model and a garment");
  state_->model = std::move(model);
  state_->garment = std::move(garment);
  // Bind-time products run on one BLAS thread as evaluate's do: OpenBLAS's
  // threaded GEMM rounds differently, and the cached codes must not depend on
  // what other threads happen to be doing.
  const SingleThreadedBlas blas;
  state_->bind(body, options);
}

Instance::~Instance() = default;

void Instance::evaluate(const PoseSequence& poses, int64_t first, int64_t count, Stage stage,
                        const EvaluateOutputs& outputs, const EvaluateDetail& detail) {
  State& s = *state_;
  const Model& m = *s.model;
  if (stage != Stage::skinning && stage != Stage::blend_shapes && stage != Stage::refinement)
    bad("evaluate: unknown stage " + std::to_string(static_cast<int32_t>(stage)));
  if (poses.joint_count != s.joints)
    bad("poses have " + std::to_string(poses.joint_count) + " joints per frame, the bound body has " +
        std::to_string(s.joints));
  if (!(std::abs(poses.frame_rate - m.frame_rate) <= 1e-6 * m.frame_rate))
    bad("poses come at " + std::to_string(poses.frame_rate) + " fps, model '" + m.source + "' runs at " +
        std::to_string(m.frame_rate) + " fps (resample the motion with pleat_motion_resample)");
  if (first < 0 || count < 0 || first > poses.frame_count || count > poses.frame_count - first)
    bad("frames [" + std::to_string(first) + ", " + std::to_string(first + count) + ") are outside the " +
        std::to_string(poses.frame_count) + " frames of the poses");
  if (detail.interval < 1)
    bad("evaluate: refinement interval is " + std::to_string(detail.interval) + ", expected >= 1");
  const char* band_names[3] = {"low", "mid", "high"};
  for (int b = 0; b < 3; ++b)
    if (!(detail.band_attenuation[b] >= 0.0f && detail.band_attenuation[b] <= 1.0f))
      bad(std::string("evaluate: the ") + band_names[b] + " band's attenuation is " +
          std::to_string(detail.band_attenuation[b]) + ", expected 0..1");
  if (!(detail.body_collision >= 0.0f && detail.body_collision <= 1.0f))
    bad("evaluate: the body-collision distance is " + std::to_string(detail.body_collision) +
        " m, expected 0..1");
  const bool attenuate = detail.band_attenuation[0] > 0.0f || detail.band_attenuation[1] > 0.0f ||
                         detail.band_attenuation[2] > 0.0f;
  const float* attenuation = attenuate ? detail.band_attenuation : nullptr;  // null: nothing to split
  if (count == 0) return;
  if (!poses.rotations || !poses.root_positions) bad("poses rotations and root_positions must not be null");
  if ((outputs.low.data || outputs.mid.data || outputs.high.data) && !s.garment->prepared)
    fail(PLEAT_ERROR_NOT_PREPARED,
         "band outputs need a prepared garment (pleat_garment_prepare before binding)");
  if (attenuate && stage == Stage::refinement && !s.garment->prepared)
    fail(PLEAT_ERROR_NOT_PREPARED,
         "band attenuation needs a prepared garment (pleat_garment_prepare before binding)");
  const size_t frame_floats = static_cast<size_t>(s.n) * 3;
  for (const OutputBuffer* o :
       {&outputs.positions, &outputs.normals, &outputs.low, &outputs.mid, &outputs.high})
    if (o->data && o->stride < frame_floats)
      bad("an output's stride is below the " + std::to_string(frame_floats) + " floats of a frame");
  if (outputs.skinning_weights.data && outputs.skinning_weights.stride < static_cast<size_t>(s.n) * s.joints)
    bad("the skinning weights' stride is below the N x S floats of a frame");

  const bool refine = stage == Stage::refinement;
  // The refined frame whose offsets the call's first frame holds (itself
  // unless the call starts inside an interval).
  const int64_t interval = refine ? detail.interval : 1;
  const int64_t first_refined = first - first % interval;
  // History: the motion window of that frame (and, for the refinement's
  // velocity, of the frame before it) reaches back window frames.
  const int64_t history = refine ? s.window + 1 : s.window;
  s.check_poses(poses, std::max<int64_t>(0, first_refined - history), first + count);

  const SingleThreadedBlas blas;  // one BLAS thread: the instance's pool owns the cores
  const size_t k = static_cast<size_t>(s.top_k);
  const int64_t kept_frame = s.last_frame;
  s.last_frame = -1;            // the slots change below; valid again once this call succeeds
  int previous_slot = -1;       // skinned[] slot holding M̃ of the frame before, once known
  if (first_refined < first) {  // Δ of that earlier frame, as if evaluated in sequence
    if (first_refined > 0)
      s.skin_frame(poses, first_refined - 1, stage, 1, s.chosen_weight.data(), s.chosen_joint.data(),
                   s.max_batch);
    s.skin_frame(poses, first_refined, stage, 0, s.chosen_weight.data(), s.chosen_joint.data(), s.max_batch);
    s.refine_offsets(poses, first_refined, first_refined > 0 ? &s.skinned[1] : nullptr, 0, s.max_batch,
                     attenuation);
    if (first_refined == first - 1) previous_slot = 0;  // already the frame before
  }
  // The frame before the call's first one: its M̃ is needed for velocities
  // (the last call's last frame, if the slots still hold it for these poses).
  if (refine && first > 0 && previous_slot < 0) {
    if (first_refined == first && kept_frame == first - 1 && s.same_inputs(poses, first - 1)) {
      previous_slot = s.last_slot;
    } else {
      s.skin_frame(poses, first - 1, stage, 1, s.chosen_weight.data(), s.chosen_joint.data(), s.max_batch);
      previous_slot = 1;
    }
  }
  for (int64_t begin = first; begin < first + count; begin += s.max_batch) {
    const int64_t batch = std::min<int64_t>(s.max_batch, first + count - begin);
    struct Codes {
      State* s;
      const PoseSequence* poses;
      int64_t begin;
    } codes{&s, &poses, begin};
    s.executor->run(
        static_cast<int32_t>(batch),
        [](void* c, int32_t b) {
          const Codes& ctx = *static_cast<const Codes*>(c);
          ctx.s->motion_code(*ctx.poses, ctx.begin + b, b);
        },
        &codes);
    for (int64_t b = 0; b < batch; ++b) {
      const int64_t t = begin + b;
      const int slot = previous_slot == 0 ? 1 : 0;
      const size_t chosen = static_cast<size_t>(b) * static_cast<size_t>(s.n) * k;
      s.skin_frame(poses, t, stage, slot, s.chosen_weight.data() + chosen, s.chosen_joint.data() + chosen,
                   static_cast<int32_t>(b));
      float* staged = s.staged.row(b).data();
      if (refine) {
        if (t % interval == 0)
          s.refine_offsets(poses, t, t > 0 ? &s.skinned[previous_slot] : nullptr, slot,
                           static_cast<int32_t>(b), attenuation);
        s.add_refinement(poses, t, slot, staged);
      } else {
        std::copy(s.skinned[slot].data(), s.skinned[slot].data() + frame_floats, staged);
      }
      if (stage != Stage::skinning)
        for (int32_t v : s.mask.masked)
          for (int c = 0; c < 3; ++c) staged[v * 3 + c] = s.lbs(v, c);
      if (detail.body_collision > 0.0f) s.collision.apply(s.skin, detail.body_collision, staged);
      previous_slot = slot;
    }
    s.write_batch(first, begin, batch, outputs);
  }
  if (stage != Stage::skinning) {
    s.last_frame = first + count - 1;
    s.last_slot = previous_slot;
    s.keep_inputs(poses, s.last_frame);
  }
}

void Instance::set_vertex_mask(const uint8_t* mask) {
  state_->set_vertex_mask(mask);
}

int32_t Instance::active_vertex_count() const {
  const VertexMask& mask = state_->mask;
  return mask.masked.empty() ? state_->n : static_cast<int32_t>(mask.active.size());
}

int32_t Instance::vertex_count() const {
  return state_->n;
}
int32_t Instance::joint_count() const {
  return state_->joints;
}
int32_t Instance::top_k() const {
  return state_->top_k;
}
int32_t Instance::max_batch() const {
  return state_->max_batch;
}
const Model& Instance::model() const {
  return *state_->model;
}

}  // namespace pleat::runtime
