#include "nn/gru.h"

#include <Eigen/Core>

#include "nn/gemm.h"

namespace pleat::nn {

namespace {

constexpr const char* kGruKind = "gru";

void check_layers(const Gru& gru) {
  if (gru.layers.empty()) invalid(kGruKind, gru.name, "has no layers");
  const Index h = gru.hidden_width();
  for (size_t l = 0; l < gru.layers.size(); ++l) {
    const GruLayer& layer = gru.layers[l];
    const std::string p = "layer " + std::to_string(l) + " ";
    const Index in = l == 0 ? gru.input_width() : h;
    check_shape(kGruKind, gru.name, (p + "w_ih").c_str(), layer.w_ih.rows(), layer.w_ih.cols(), in, 3 * h);
    check_shape(kGruKind, gru.name, (p + "w_hh").c_str(), layer.w_hh.rows(), layer.w_hh.cols(), h, 3 * h);
    check_shape(kGruKind, gru.name, (p + "b_ih").c_str(), 1, layer.b_ih.size(), 1, 3 * h);
    check_shape(kGruKind, gru.name, (p + "b_hh").c_str(), 1, layer.b_hh.size(), 1, 3 * h);
  }
}

// One layer, one step, in place on h (batch x H). gi, gh: batch x 3H scratch.
void layer_step(const GruLayer& layer, ConstMatrixRef x, MatrixRef h, MatrixMap gi, MatrixMap gh) {
  const Index hw = h.cols();
  gemm(x, layer.w_ih, gi);
  gemm(h, layer.w_hh, gh);
  for (Index b = 0; b < h.rows(); ++b) {
    Eigen::Map<Eigen::ArrayXf> i(gi.row(b).data(), 3 * hw);
    Eigen::Map<Eigen::ArrayXf> g(gh.row(b).data(), 3 * hw);
    i += layer.b_ih.transpose().array();
    g += layer.b_hh.transpose().array();
    // r and z: sigmoid of the summed pre-activations (stored back into i).
    auto rz = i.head(2 * hw);
    rz = 1.0f / (1.0f + (-(rz + g.head(2 * hw))).exp());
    auto r = i.head(hw);
    auto z = i.segment(hw, hw);
    auto n = i.tail(hw);
    n = (n + r * g.tail(hw)).tanh();
    Eigen::Map<Eigen::ArrayXf> hh(h.row(b).data(), hw);
    hh = (1.0f - z) * n + z * hh;
  }
}

void step_all(const Gru& gru, ConstMatrixRef x, MatrixRef state, Index batch, float* scratch) {
  const Index hw = gru.hidden_width();
  MatrixMap gi = view(scratch, batch, 3 * hw);
  MatrixMap gh = view(scratch + 3 * batch * hw, batch, 3 * hw);
  for (Index l = 0; l < gru.layer_count(); ++l) {
    auto h = state.middleRows(l * batch, batch);
    if (l == 0) {
      layer_step(gru.layers[0], x, h, gi, gh);
    } else {
      layer_step(gru.layers[static_cast<size_t>(l)], state.middleRows((l - 1) * batch, batch), h, gi, gh);
    }
  }
}

}  // namespace

void Gru::validate() const {
  check_layers(*this);
  for (const GruLayer& l : layers)
    if (!l.w_ih.allFinite() || !l.w_hh.allFinite() || !l.b_ih.allFinite() || !l.b_hh.allFinite())
      invalid(kGruKind, name, "a weight or bias holds a NaN or infinite value");
}

void gru_step(const Gru& gru, ConstMatrixRef x, MatrixRef state, GruWorkspace& workspace) {
  check_layers(gru);
  const Index batch = x.rows(), hw = gru.hidden_width();
  check_shape(kGruKind, gru.name, "input x", x.rows(), x.cols(), -1, gru.input_width());
  check_shape(kGruKind, gru.name, "state", state.rows(), state.cols(), gru.layer_count() * batch, hw);
  check_scratch(kGruKind, gru.name, "GruWorkspace", 6 * static_cast<size_t>(batch * hw),
                workspace.scratch().capacity());
  step_all(gru, x, state, batch, workspace.scratch().data());
}

void gru_window(const Gru& gru, ConstMatrixRef x, Index steps, MatrixRef out, GruWorkspace& workspace) {
  check_layers(gru);
  if (steps <= 0) invalid(kGruKind, gru.name, "window needs at least one step");
  const Index hw = gru.hidden_width();
  if (x.rows() % steps != 0)
    invalid(kGruKind, gru.name,
            "input x has " + std::to_string(x.rows()) + " rows, not a multiple of the " +
                std::to_string(steps) + " steps (expected steps*batch rows, time-major)");
  const Index batch = x.rows() / steps;
  check_shape(kGruKind, gru.name, "input x", x.rows(), x.cols(), steps * batch, gru.input_width());
  check_shape(kGruKind, gru.name, "output", out.rows(), out.cols(), batch, hw);
  const size_t gates = 6 * static_cast<size_t>(batch * hw);
  check_scratch(kGruKind, gru.name, "GruWorkspace",
                gates + static_cast<size_t>(gru.layer_count() * batch * hw), workspace.scratch().capacity());
  float* scratch = workspace.scratch().data();
  MatrixMap state = view(scratch + gates, gru.layer_count() * batch, hw);
  state.setZero();
  for (Index t = 0; t < steps; ++t) step_all(gru, x.middleRows(t * batch, batch), state, batch, scratch);
  out = state.bottomRows(batch);
}

}  // namespace pleat::nn
