#pragma once
// Adamax (Kingma & Ba 2015, §7.1; PyTorch's torch.optim.Adamax) with cosine
// annealing of the learning rate: the optimiser of DESIGN §6. libtorch's C++
// API has Adam but no Adamax, so it is written here, with its state in plain
// tensors so checkpoints restore it exactly.
#include <torch/torch.h>

#include <vector>

namespace pleat::training {

class Adamax {
 public:
  Adamax(std::vector<torch::Tensor> parameters, double learning_rate = 3e-3, double beta1 = 0.9,
         double beta2 = 0.999, double epsilon = 1e-8);

  // One update of every parameter that has a gradient (frozen parameters,
  // requires_grad false, have none):
  //   m = β1 m + (1 - β1) g;  u = max(β2 u, |g| + ε);  p -= lr / (1 - β1^t) · m / u
  void step();
  void zero_grad();
  void set_learning_rate(double lr) { learning_rate_ = lr; }
  double learning_rate() const { return learning_rate_; }

  // Decoupled weight decay (Loshchilov & Hutter 2019, AdamW): each step first
  // shrinks the parameters that are in `decayed` by p -= lr · weight_decay · p,
  // apart from the gradient's update, so the decay follows the annealed
  // learning rate and is not rescaled by u as an L2 term in the loss would be.
  void set_weight_decay(double weight_decay, const std::vector<torch::Tensor>& decayed);

  // m and u of every parameter, then the step counts (one per parameter).
  std::vector<torch::Tensor> state() const;
  void load_state(const std::vector<torch::Tensor>& state);

 private:
  std::vector<torch::Tensor> parameters_, first_moment_, infinity_norm_;
  std::vector<int64_t> steps_;
  std::vector<bool> decayed_;
  double learning_rate_, beta1_, beta2_, epsilon_, weight_decay_ = 0.0;
};

// Cosine annealing from `start` to `end` over `period` epochs (then `end`).
double cosine_learning_rate(double start, double end, int64_t epoch, int64_t period);

}  // namespace pleat::training
