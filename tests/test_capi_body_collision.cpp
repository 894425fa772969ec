// The body-collision post-pass (pleat_evaluate_options.body_collision_distance)
// on the MakeHuman body walking: a garment made of the torso's own surface
// pushed 1 cm inwards is inside the body on every frame without the pass and
// outside it with the pass. "Inside" is judged here independently of the
// library's candidates: against the nearest posed body vertex (brute force)
// and the area-weighted normals of the posed body mesh.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "capi/pleat.h"
#include "support/capi_chain.h"
#include "support/capi_support.h"

using namespace pleat_test::chain;

namespace {

using MotionPtr = std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)>;

// Fraction of garment vertices behind the nearest body vertex's normal.
double inside_fraction(const float* garment, size_t n, const float* body, size_t nb,
                       const std::vector<uint32_t>& body_triangles) {
  const std::vector<Eigen::Vector3f> normals = pleat_test::area_weighted_normals(body, nb, body_triangles);
  // Every 4th vertex: the brute-force search is the test's whole cost (ASan).
  size_t inside = 0, tested = 0;
  for (size_t v = 0; v < n; v += 4, ++tested) {
    const Eigen::Vector3f x(garment + 3 * v);
    size_t best = 0;
    float best_d2 = INFINITY;
    for (size_t b = 0; b < nb; ++b) {
      const float d2 = (x - Eigen::Vector3f(body + 3 * b)).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = b;
    }
    inside += (x - Eigen::Vector3f(body + 3 * best)).dot(normals[best]) < 0.0f;
  }
  return double(inside) / double(tested);
}

}  // namespace

TEST(CapiBodyCollision, ThePostPassMovesATorsoInsideTheBodyOut) {
  pleat_body* b = nullptr;
  ASSERT_EQ(pleat_body_load((pleat_test::asset_dir() + "/body").c_str(), nullptr, &b), PLEAT_OK)
      << pleat_last_error();
  BodyPtr body(b, pleat_body_destroy);
  pleat_body_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_body_get_info(body.get(), &info), PLEAT_OK);
  const size_t nb = info.vertex_count;
  std::vector<float> rest(nb * 3);
  std::vector<uint32_t> triangles(size_t(info.triangle_count) * 3);
  ASSERT_EQ(pleat_body_get_rest(body.get(), rest.data(), rest.size(), triangles.data(), triangles.size(),
                                nullptr, 0),
            PLEAT_OK);

  // The torso band (40-65 % of the body's height), 1 cm inside the body.
  float lo = INFINITY, hi = -INFINITY;
  for (size_t v = 0; v < nb; ++v) lo = std::min(lo, rest[3 * v + 1]), hi = std::max(hi, rest[3 * v + 1]);
  const std::vector<Eigen::Vector3f> normals = pleat_test::area_weighted_normals(rest.data(), nb, triangles);
  std::vector<int64_t> index(nb, -1);
  pleat_test::SimpleMesh torso;
  for (size_t t = 0; t < triangles.size(); t += 3) {
    bool keep = true;
    for (int k = 0; k < 3; ++k) {
      const float h = (rest[3 * triangles[t + k] + 1] - lo) / (hi - lo);
      keep = keep && h > 0.40f && h < 0.65f;
    }
    if (!keep) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = triangles[t + k];
      if (index[v] < 0) {
        index[v] = int64_t(torso.vertex_count());
        const Eigen::Vector3f inner = Eigen::Vector3f(&rest[3 * v]) - 0.01f * normals[v];
        torso.positions.insert(torso.positions.end(), {inner.x(), inner.y(), inner.z()});
      }
      torso.triangles.push_back(uint32_t(index[v]));
    }
  }
  const size_t n = torso.vertex_count();
  ASSERT_GT(n, 1000u);
  pleat_test::GarmentPtr garment = pleat_test::create_garment(torso);

  pleat_motion* m = nullptr;
  ASSERT_EQ(
      pleat_motion_load((pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").c_str(),
                        nullptr, &m),
      PLEAT_OK);
  MotionPtr clip(m, pleat_motion_destroy);
  ASSERT_EQ(pleat_motion_resample(clip.get(), 30.0, &m), PLEAT_OK);
  MotionPtr resampled(m, pleat_motion_destroy);
  ASSERT_EQ(pleat_motion_retarget(resampled.get(), body.get(), nullptr, &m), PLEAT_OK) << pleat_last_error();
  MotionPtr walk(m, pleat_motion_destroy);

  ModelPtr model = initialised(body.get());
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  const size_t first = 10, frames = 3;
  const auto run = [&](float distance) {
    std::vector<float> positions(frames * n * 3);
    pleat_evaluate_options o = stage_options(PLEAT_STAGE_SKINNING);
    o.body_collision_distance = distance;
    pleat_evaluate_outputs out = positions_into(positions.data());
    const pleat_status status =
        pleat_instance_evaluate_motion(instance.get(), walk.get(), first, frames, &o, &out);
    return status == PLEAT_OK ? positions : std::vector<float>{float(status)};
  };
  std::vector<float> posed_body(frames * nb * 3);
  ASSERT_EQ(pleat_body_pose_motion(body.get(), walk.get(), first, frames, {posed_body.data(), 0}), PLEAT_OK);

  const std::vector<float> plain = run(0.0f), pushed = run(0.003f);
  ASSERT_EQ(pushed.size(), frames * n * 3) << pleat_last_error();
  EXPECT_EQ(plain, run(0.0f)) << "distance 0 is no post-pass";
  for (size_t f = 0; f < frames; ++f) {
    const double before = inside_fraction(&plain[f * n * 3], n, &posed_body[f * nb * 3], nb, triangles);
    const double after = inside_fraction(&pushed[f * n * 3], n, &posed_body[f * nb * 3], nb, triangles);
    EXPECT_GT(before, 0.95) << "frame " << f;
    EXPECT_LT(after, 0.02) << "frame " << f;
  }
  float largest = 0.0f;
  for (size_t i = 0; i < plain.size(); ++i) largest = std::max(largest, std::abs(pushed[i] - plain[i]));
  EXPECT_GT(largest, 0.009f);
  EXPECT_LT(largest, 0.03f) << "a vertex 1 cm inside moves about 1.3 cm";

  for (float bad : {-0.1f, 2.0f, NAN}) {
    EXPECT_EQ(run(bad), std::vector<float>{float(PLEAT_ERROR_INVALID_ARGUMENT)});
    EXPECT_NE(std::string(pleat_last_error()).find("body_collision_distance"), std::string::npos)
        << pleat_last_error();
  }
}
