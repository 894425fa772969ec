#pragma once
// The body-collision post-pass of evaluate (docs/runtime.md): garment
// vertices that end inside the body, or closer to it than a distance, move
// out along the body's normal. Bound once per instance: each garment vertex
// gets as candidates the body vertex nearest to it at rest and that vertex's
// mesh neighbours; per frame only those body vertices are skinned (with the
// frame's skinning matrices) and each garment vertex is tested against the
// nearest of its candidates. Allocates nothing per frame.
#include <cstdint>
#include <vector>

#include "body/body.h"
#include "nn/tensor.h"

namespace pleat::runtime {

class BodyCollision {
 public:
  BodyCollision() = default;
  // garment_rest: N x 3 (metres); model_of_body: body joint -> model joint,
  // the row of the frame's skinning matrices.
  BodyCollision(const Body& body, const Points3f& garment_rest, const std::vector<int32_t>& model_of_body);

  // skin: S x 12 [R | t] rows of this frame (model joint order); positions:
  // N x 3 floats, changed in place. A vertex further than kReach from every
  // candidate is left alone (a hem swinging away from the legs).
  void apply(const nn::MatrixRM& skin, float distance, float* positions);

  static constexpr float kReach = 0.1f;  // metres

 private:
  std::vector<int32_t> candidate_offsets_{0};  // N + 1, into candidates_
  std::vector<int32_t> candidates_;            // slots of used_
  std::vector<int32_t> weight_offsets_{0};     // per used body vertex, into joints_/weights_
  std::vector<int32_t> joints_;                // model joint order
  std::vector<float> weights_;
  nn::MatrixRM rest_, rest_normals_;  // used body vertices, U x 3
  nn::MatrixRM posed_, posed_normals_;
};

}  // namespace pleat::runtime
