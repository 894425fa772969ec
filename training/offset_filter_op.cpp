#include "offset_filter_op.h"

namespace pleat::training {
namespace {

using torch::autograd::AutogradContext;
using torch::autograd::tensor_list;

torch::Tensor solve(const torch::Tensor& d, const runtime::OffsetFilter& filter) {
  torch::Tensor x = d.contiguous().clone();
  filter.apply(x.data_ptr<float>(), x.size(0));
  return x;
}

const runtime::OffsetFilter& filter_of(AutogradContext* ctx) {
  return *reinterpret_cast<const runtime::OffsetFilter*>(
      static_cast<intptr_t>(ctx->saved_data["filter"].toInt()));
}

class FilterFunction : public torch::autograd::Function<FilterFunction> {
 public:
  static torch::Tensor forward(AutogradContext* ctx, const torch::Tensor& d,
                               const runtime::OffsetFilter* filter) {
    ctx->saved_data["filter"] = static_cast<int64_t>(reinterpret_cast<intptr_t>(filter));
    return solve(d, *filter);
  }
  static tensor_list backward(AutogradContext* ctx, tensor_list grad_outputs) {
    return {solve(grad_outputs[0], filter_of(ctx)), torch::Tensor()};
  }
};

}  // namespace

torch::Tensor filter_offsets(const torch::Tensor& offsets, const runtime::OffsetFilter& filter) {
  TORCH_CHECK(offsets.dim() == 3 && offsets.size(1) == filter.vertex_count() && offsets.size(2) == 3 &&
                  offsets.scalar_type() == torch::kFloat32 && offsets.device().is_cpu(),
              "filter_offsets: offsets must be K x ", filter.vertex_count(), " x 3 float32 on the CPU");
  return FilterFunction::apply(offsets, &filter);
}

}  // namespace pleat::training
