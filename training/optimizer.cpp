#include "optimizer.h"

#include <algorithm>
#include <cmath>

namespace pleat::training {

Adamax::Adamax(std::vector<torch::Tensor> parameters, double learning_rate, double beta1, double beta2,
               double epsilon)
    : parameters_(std::move(parameters)),
      steps_(parameters_.size(), 0),
      decayed_(parameters_.size(), false),
      learning_rate_(learning_rate),
      beta1_(beta1),
      beta2_(beta2),
      epsilon_(epsilon) {
  for (const torch::Tensor& p : parameters_) {
    first_moment_.push_back(torch::zeros_like(p));
    infinity_norm_.push_back(torch::zeros_like(p));
  }
}

void Adamax::step() {
  torch::NoGradGuard no_grad;
  for (size_t i = 0; i < parameters_.size(); ++i) {
    torch::Tensor& p = parameters_[i];
    if (!p.grad().defined()) continue;
    const torch::Tensor g = p.grad();
    const int64_t t = ++steps_[i];
    if (decayed_[i]) p.mul_(1.0 - learning_rate_ * weight_decay_);
    first_moment_[i].mul_(beta1_).add_(g, 1.0 - beta1_);
    infinity_norm_[i] = torch::maximum(infinity_norm_[i] * beta2_, g.abs() + epsilon_);
    p.addcdiv_(first_moment_[i], infinity_norm_[i], -learning_rate_ / (1.0 - std::pow(beta1_, double(t))));
  }
}

void Adamax::set_weight_decay(double weight_decay, const std::vector<torch::Tensor>& decayed) {
  weight_decay_ = weight_decay;
  for (size_t i = 0; i < parameters_.size(); ++i)
    decayed_[i] = std::any_of(decayed.begin(), decayed.end(),
                              [&](const torch::Tensor& d) { return d.is_same(parameters_[i]); });
}

void Adamax::zero_grad() {
  for (torch::Tensor& p : parameters_)
    if (p.grad().defined()) p.mutable_grad() = torch::Tensor();
}

std::vector<torch::Tensor> Adamax::state() const {
  std::vector<torch::Tensor> out;
  for (size_t i = 0; i < parameters_.size(); ++i) {
    out.push_back(first_moment_[i]);
    out.push_back(infinity_norm_[i]);
  }
  out.push_back(torch::tensor(steps_, torch::kInt64));
  return out;
}

void Adamax::load_state(const std::vector<torch::Tensor>& state) {
  TORCH_CHECK(state.size() == 2 * parameters_.size() + 1, "Adamax state has ", state.size(),
              " tensors, expected ", 2 * parameters_.size() + 1);
  for (size_t i = 0; i < parameters_.size(); ++i) {
    TORCH_CHECK(state[2 * i].sizes() == parameters_[i].sizes(), "Adamax state of parameter ", i,
                " does not match its shape");
    first_moment_[i] = state[2 * i].clone();
    infinity_norm_[i] = state[2 * i + 1].clone();
  }
  const torch::Tensor steps = state.back().to(torch::kInt64).contiguous();
  TORCH_CHECK(steps.numel() == static_cast<int64_t>(parameters_.size()), "Adamax step counts do not match");
  for (size_t i = 0; i < parameters_.size(); ++i) steps_[i] = steps.data_ptr<int64_t>()[i];
}

double cosine_learning_rate(double start, double end, int64_t epoch, int64_t period) {
  if (period <= 0 || epoch >= period) return end;
  const double pi = 3.14159265358979323846;
  return end + 0.5 * (start - end) * (1.0 + std::cos(pi * double(epoch) / double(period)));
}

}  // namespace pleat::training
