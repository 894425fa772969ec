// Bodies and motions through the C API, as a host uses them: the MakeHuman
// model, reshaping, BVH clips retargeted onto the body, posing.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "capi/pleat.h"
#include "support/test_support.h"

namespace {

using BodyPtr = std::unique_ptr<pleat_body, decltype(&pleat_body_destroy)>;
using MotionPtr = std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)>;

BodyPtr makehuman() {
  pleat_body* b = nullptr;
  EXPECT_EQ(pleat_body_load((pleat_test::asset_dir() + "/body").c_str(), nullptr, &b), PLEAT_OK)
      << pleat_last_error();
  return BodyPtr(b, pleat_body_destroy);
}

MotionPtr load_motion(const std::string& relative) {
  pleat_motion* m = nullptr;
  EXPECT_EQ(pleat_motion_load((pleat_test::asset_dir() + "/motions/" + relative).c_str(), nullptr, &m),
            PLEAT_OK)
      << pleat_last_error();
  return MotionPtr(m, pleat_motion_destroy);
}

pleat_body_info info_of(const pleat_body* body) {
  pleat_body_info info{};
  info.struct_size = sizeof info;
  EXPECT_EQ(pleat_body_get_info(body, &info), PLEAT_OK) << pleat_last_error();
  return info;
}

float rest_height(const pleat_body* body) {
  const pleat_body_info info = info_of(body);
  std::vector<float> rest(info.vertex_count * size_t{3});
  EXPECT_EQ(pleat_body_get_rest(body, rest.data(), rest.size(), nullptr, 0, nullptr, 0), PLEAT_OK);
  float lo = 1e9f, hi = -1e9f;
  for (size_t i = 1; i < rest.size(); i += 3) lo = std::min(lo, rest[i]), hi = std::max(hi, rest[i]);
  return hi - lo;
}

int shape_index(const pleat_body* body, const std::string& name) {
  for (uint32_t i = 0; pleat_body_shape_name(body, i); ++i)
    if (name == pleat_body_shape_name(body, i)) return static_cast<int>(i);
  return -1;
}

}  // namespace

TEST(CapiBody, MakeHumanBodyHasTheCmuSkeletonAndReshapes) {
  BodyPtr body = makehuman();
  const pleat_body_info info = info_of(body.get());
  EXPECT_EQ(info.vertex_count, 13380u);
  EXPECT_EQ(info.joint_count, 31u);
  EXPECT_GT(info.shape_count, 5u);
  EXPECT_STREQ(pleat_body_joint_name(body.get(), 0), "Hips");
  EXPECT_EQ(pleat_body_joint_name(body.get(), info.joint_count), nullptr);

  const float default_height = rest_height(body.get());
  EXPECT_GT(default_height, 1.55f);
  EXPECT_LT(default_height, 1.85f);
  std::vector<double> shape(info.shape_count);
  ASSERT_EQ(pleat_body_get_shape(body.get(), shape.data(), shape.size()), PLEAT_OK);
  const int height = shape_index(body.get(), "height");
  ASSERT_GE(height, 0);
  EXPECT_DOUBLE_EQ(shape[static_cast<size_t>(height)], 0.5);
  shape[static_cast<size_t>(height)] = 1.0;
  ASSERT_EQ(pleat_body_set_shape(body.get(), shape.data(), shape.size()), PLEAT_OK) << pleat_last_error();
  EXPECT_GT(rest_height(body.get()), default_height + 0.05f);

  shape[static_cast<size_t>(height)] = 7.0;
  EXPECT_EQ(pleat_body_set_shape(body.get(), shape.data(), shape.size()), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("'height'"), std::string::npos) << pleat_last_error();
  EXPECT_EQ(pleat_body_set_shape(body.get(), shape.data(), 2), PLEAT_ERROR_INVALID_ARGUMENT);
}

TEST(CapiBody, WalkRetargetedOntoTheBodyKeepsFeetOnTheGround) {
  BodyPtr body = makehuman();
  MotionPtr clip = load_motion("cmu_mb/12_03.bvh");  // a walk
  pleat_motion_info mi{};
  mi.struct_size = sizeof mi;
  ASSERT_EQ(pleat_motion_get_info(clip.get(), &mi), PLEAT_OK);
  EXPECT_EQ(mi.frame_count, 566u);
  EXPECT_DOUBLE_EQ(mi.frame_rate, 120.0);

  pleat_motion* m = nullptr;
  ASSERT_EQ(pleat_motion_resample(clip.get(), 30.0, &m), PLEAT_OK) << pleat_last_error();
  MotionPtr at30(m, pleat_motion_destroy);
  ASSERT_EQ(pleat_motion_retarget(at30.get(), body.get(), nullptr, &m), PLEAT_OK) << pleat_last_error();
  MotionPtr retargeted(m, pleat_motion_destroy);
  pleat_motion_info ri{};
  ri.struct_size = sizeof ri;
  ASSERT_EQ(pleat_motion_get_info(retargeted.get(), &ri), PLEAT_OK);
  EXPECT_EQ(ri.joint_count, 31u);
  EXPECT_DOUBLE_EQ(ri.frame_rate, 30.0);

  const pleat_body_info info = info_of(body.get());
  const size_t frames = 40, first = 10, n = info.vertex_count;
  std::vector<float> posed(frames * n * 3);
  ASSERT_EQ(pleat_body_pose_motion(body.get(), retargeted.get(), first, frames, {posed.data(), 0}), PLEAT_OK)
      << pleat_last_error();
  // The lowest body point (a sole) stays within a few cm of the floor while
  // walking, and the root travels forward.
  for (size_t f = 0; f < frames; ++f) {
    float lo = 1e9f;
    for (size_t v = 0; v < n; ++v) lo = std::min(lo, posed[(f * n + v) * 3 + 1]);
    EXPECT_NEAR(lo, 0.0f, 0.08f) << "frame " << first + f;
  }
  std::vector<float> roots(frames * 3);
  ASSERT_EQ(pleat_motion_get_frames(retargeted.get(), first, frames, nullptr, 0, roots.data(), roots.size()),
            PLEAT_OK);
  const float travel = std::hypot(roots[(frames - 1) * 3] - roots[0], roots[(frames - 1) * 3 + 2] - roots[2]);
  EXPECT_GT(travel, 0.5f) << "a walk covers ground";

  std::vector<float> q(frames * 31 * 4);
  ASSERT_EQ(pleat_motion_get_frames(retargeted.get(), first, frames, q.data(), q.size(), nullptr, 0),
            PLEAT_OK);
  for (size_t i = 0; i < q.size(); i += 4)
    EXPECT_NEAR(q[i] * q[i] + q[i + 1] * q[i + 1] + q[i + 2] * q[i + 2] + q[i + 3] * q[i + 3], 1.0f, 1e-5f);
}

TEST(CapiBody, BadInputIsNamed) {
  pleat_body* b = reinterpret_cast<pleat_body*>(0x1);
  EXPECT_EQ(pleat_body_load("/no/such/body.npz", nullptr, &b), PLEAT_ERROR_IO) << pleat_last_error();
  EXPECT_EQ(b, reinterpret_cast<pleat_body*>(0x1));
  pleat_motion* m = nullptr;
  EXPECT_NE(pleat_motion_load("/no/such/clip.bvh", nullptr, &m), PLEAT_OK);
  EXPECT_NE(std::string(pleat_last_error()).find("/no/such/clip.bvh"), std::string::npos)
      << pleat_last_error();

  BodyPtr body = makehuman();
  MotionPtr daz = load_motion("cmu_daz/02_02.bvh");
  // Daz names ("hip", "abdomen", ...) do not match the cmu_mb rig: the root
  // cannot be paired without the joint map.
  EXPECT_NE(pleat_motion_retarget(daz.get(), body.get(), nullptr, &m), PLEAT_OK);
  const std::string map = pleat_test::source_dir() + "/data/retarget/cmu_daz.txt";
  ASSERT_EQ(pleat_motion_retarget(daz.get(), body.get(), map.c_str(), &m), PLEAT_OK) << pleat_last_error();
  MotionPtr mapped(m, pleat_motion_destroy);
  std::vector<float> out(info_of(body.get()).vertex_count * size_t{3});
  EXPECT_EQ(pleat_body_pose_motion(body.get(), mapped.get(), 100000, 1, {out.data(), 0}),
            PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pleat_body_pose_motion(body.get(), daz.get(), 0, 1, {out.data(), 0}),
            PLEAT_ERROR_INVALID_ARGUMENT)
      << "a motion on another skeleton must be retargeted first";
}
