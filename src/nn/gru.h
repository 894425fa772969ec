#pragma once
// Multi-layer GRU, PyTorch convention (torch.nn.GRU, batch of independent
// sequences). Per layer and step, with gates in the order r, z, n:
//   r  = sigmoid(x W_ir + b_ir + h W_hr + b_hr)
//   z  = sigmoid(x W_iz + b_iz + h W_hz + b_hz)
//   n  = tanh(x W_in + b_in + r * (h W_hn + b_hn))
//   h' = (1 - z) * n + z * h
// Layer l > 0 takes layer l-1's new hidden state of the same step as x.
#include <string>
#include <vector>

#include "nn/tensor.h"

namespace pleat::nn {

struct GruLayer {
  MatrixRM w_ih;   // in x 3H, column blocks [r | z | n]  (= weight_ih_l{k} transposed)
  MatrixRM w_hh;   // H x 3H, column blocks [r | z | n]   (= weight_hh_l{k} transposed)
  RowVector b_ih;  // 3H  (bias_ih_l{k})
  RowVector b_hh;  // 3H  (bias_hh_l{k}); b_hn stays inside r * (...)
};

struct Gru {
  std::string name = "gru";
  std::vector<GruLayer> layers;

  Index layer_count() const { return static_cast<Index>(layers.size()); }
  Index input_width() const { return layers.empty() ? 0 : layers.front().w_ih.rows(); }
  Index hidden_width() const { return layers.empty() ? 0 : layers.front().w_hh.rows(); }
  // Throws unless every layer's shapes chain (in -> H -> H ...), biases are 3H
  // and every parameter is finite.
  void validate() const;
};

// Gate buffers for a batch (2 x batch x 3H) plus a zero-started state for
// gru_window (layers x batch x H).
class GruWorkspace {
 public:
  void reserve(const Gru& gru, Index batch) {
    const size_t b = static_cast<size_t>(batch), h = static_cast<size_t>(gru.hidden_width());
    scratch_.reserve(6 * b * h + static_cast<size_t>(gru.layer_count()) * b * h);
  }
  Scratch& scratch() { return scratch_; }

 private:
  Scratch scratch_;
};

// Streaming: one step for a batch. x: batch x input_width. state:
// (layers * batch) x H, layer l's hidden states in rows [l*batch, (l+1)*batch),
// read as h_{t-1} and overwritten with h_t (start from zeros). The last
// layer's output is state.bottomRows(batch).
void gru_step(const Gru& gru, ConstMatrixRef x, MatrixRef state, GruWorkspace& workspace);

// Window: `steps` steps from a zero state. x: (steps * batch) x input_width,
// time-major (step t is rows [t*batch, (t+1)*batch)). out: batch x H, the last
// layer's hidden state after the last step. Runs exactly the code of
// gru_step, so it equals feeding the same steps to gru_step one by one
// bit for bit.
void gru_window(const Gru& gru, ConstMatrixRef x, Index steps, MatrixRef out, GruWorkspace& workspace);

}  // namespace pleat::nn
