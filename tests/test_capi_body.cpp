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

namespace {

// A two-joint chain along +X: root at the origin, elbow at (1, 0, 0). Vertex 0
// follows the root, vertex 1 the elbow, vertex 2 is split half and half.
struct ChainArrays {
  const char* names[2] = {"root", "elbow"};
  int32_t parents[2] = {-1, 0};
  float joints[6] = {0, 0, 0, 1, 0, 0};
  float positions[9] = {0.5f, 0, 0, 2, 0, 0, 1, 0.5f, 0};
  uint32_t triangles[3] = {0, 1, 2};
  uint32_t weight_joints[6] = {0, 1, 1, 0, 0, 1};
  float weights[6] = {1, 0, 1, 0, 0.5f, 0.5f};
  pleat_body_desc desc() {
    pleat_body_desc d{};
    d.struct_size = sizeof d;
    d.joint_count = 2;
    d.joint_names = names;
    d.parents = parents;
    d.joint_positions = joints;
    d.vertex_count = 3;
    d.positions = positions;
    d.triangle_count = 1;
    d.triangles = triangles;
    d.influences = 2;
    d.weight_joints = weight_joints;
    d.weights = weights;
    return d;
  }
};

}  // namespace

TEST(CapiBody, ArraysBodyPosesAsComputedByHand) {
  ChainArrays a;
  const pleat_body_desc d = a.desc();
  pleat_body* b = nullptr;
  ASSERT_EQ(pleat_body_create(&d, &b), PLEAT_OK) << pleat_last_error();
  BodyPtr body(b, pleat_body_destroy);
  EXPECT_EQ(info_of(body.get()).shape_count, 0u);
  EXPECT_EQ(pleat_body_set_shape(body.get(), nullptr, 0), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("fixed shape"), std::string::npos);

  // Frame 0: rest pose at the rest root. Frame 1: elbow bent 90 degrees about
  // +Z, root moved to (0, 0, 2).
  const float s = std::sqrt(0.5f);
  const float rotations[16] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, s, s};
  const float roots[6] = {0, 0, 0, 0, 0, 2};
  std::vector<float> out(2 * 9);
  ASSERT_EQ(pleat_body_pose(body.get(), rotations, roots, 2, {out.data(), 0}), PLEAT_OK)
      << pleat_last_error();
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(out[i], a.positions[i], 1e-6f) << i;
  // Vertex 1 at (2,0,0) turns about the elbow (1,0,0) to (1,1,0), then +2 in z.
  const float expected[9] = {0.5f, 0, 2, 1, 1, 2,
                             // vertex 2 (1, 0.5): root copy (1, 0.5), elbow copy (0.5, 0), halved
                             0.75f, 0.25f, 2};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(out[9 + i], expected[i], 1e-6f) << i;

  const float bad[16] = {0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, s, s};
  std::vector<float> untouched(18, -7.0f);
  EXPECT_EQ(pleat_body_pose(body.get(), bad, roots, 2, {untouched.data(), 0}), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("frame 0 joint 1 'elbow'"), std::string::npos)
      << pleat_last_error();
  EXPECT_EQ(untouched[0], -7.0f);
}

TEST(CapiBody, ArraysBodyRefusesBadSkeletonsAndWeights) {
  pleat_body* b = nullptr;
  {
    ChainArrays a;
    a.weights[4] = 0.7f;  // vertex 2 sums to 1.2
    const pleat_body_desc d = a.desc();
    EXPECT_EQ(pleat_body_create(&d, &b), PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pleat_last_error()).find("vertex 2"), std::string::npos) << pleat_last_error();
  }
  {
    ChainArrays a;
    a.parents[1] = 1;  // its own parent: a cycle
    const pleat_body_desc d = a.desc();
    EXPECT_EQ(pleat_body_create(&d, &b), PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pleat_last_error()).find("'elbow'"), std::string::npos) << pleat_last_error();
  }
  {
    ChainArrays a;
    a.names[1] = "root";
    const pleat_body_desc d = a.desc();
    EXPECT_EQ(pleat_body_create(&d, &b), PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pleat_last_error()).find("named twice"), std::string::npos) << pleat_last_error();
  }
  {
    ChainArrays a;
    a.weight_joints[3] = 5;
    const pleat_body_desc d = a.desc();
    EXPECT_EQ(pleat_body_create(&d, &b), PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pleat_last_error()).find("weight_joints[3]"), std::string::npos)
        << pleat_last_error();
  }
  EXPECT_EQ(b, nullptr);
}
