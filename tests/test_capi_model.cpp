// Models and instances through the C API, as a host uses them: initialise a
// model for a skeleton, save and load it, bind it to a garment and a body,
// evaluate frames. Values are checked where the answer is known whatever the
// weights: in the rest pose, and under a motion that moves every joint
// alike, linear blend skinning with any convex weights is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "capi/pleat.h"
#include "support/capi_chain.h"
#include "support/capi_support.h"

using namespace pleat_test::chain;

namespace {

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(CapiModel, InitialisedModelDescribesItselfAndRoundTripsThroughAFile) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  const pleat_model_info info = info_of(model.get());
  EXPECT_EQ(info.joint_count, kJoints);
  EXPECT_EQ(info.shape_count, 0u);
  EXPECT_EQ(info.window_frames, 8u);
  EXPECT_EQ(info.variant, static_cast<uint32_t>(PLEAT_VARIANT_FLEXIGAT));
  EXPECT_EQ(info.code_width, 128u);
  EXPECT_EQ(info.default_top_k, 4u);
  EXPECT_EQ(info.format_version, 1u) << "uses nothing of format version 2";
  EXPECT_DOUBLE_EQ(info.frame_rate, 30.0);
  EXPECT_GT(info.parameter_count, 100000u);
  EXPECT_EQ(info.offset_filter_length, 0.0) << "the paper's form: no offset filter";
  EXPECT_EQ(info.skinning_prior_radius, 0.0) << "the nearest body vertex's weights";
  EXPECT_DOUBLE_EQ(info.skinning_prior_floor, double(1e-6f));
  EXPECT_STREQ(pleat_model_joint_name(model.get(), 2), "arm");
  EXPECT_EQ(pleat_model_joint_name(model.get(), 3), nullptr);
  EXPECT_EQ(pleat_model_joint_name(nullptr, 0), nullptr);

  const std::string dir = pleat_test::temp_dir("capi_model");
  ASSERT_EQ(pleat_model_save(model.get(), (dir + "/a.pleat").c_str()), PLEAT_OK) << pleat_last_error();
  pleat_model* loaded = nullptr;
  ASSERT_EQ(pleat_model_load((dir + "/a.pleat").c_str(), &loaded), PLEAT_OK) << pleat_last_error();
  ModelPtr again(loaded, pleat_model_destroy);
  EXPECT_EQ(info_of(again.get()).parameter_count, info.parameter_count);
  ASSERT_EQ(pleat_model_save(again.get(), (dir + "/b.pleat").c_str()), PLEAT_OK);
  const std::vector<char> a = file_bytes(dir + "/a.pleat");
  EXPECT_GT(a.size(), info.parameter_count * 4) << "float32 tensors";
  EXPECT_EQ(a, file_bytes(dir + "/b.pleat")) << "load + save reproduces the file byte for byte";

  ModelPtr gat = initialised(body.get(), PLEAT_VARIANT_GAT, 4, 60.0);
  const pleat_model_info g = info_of(gat.get());
  EXPECT_EQ(g.variant, static_cast<uint32_t>(PLEAT_VARIANT_GAT));
  EXPECT_EQ(g.window_frames, 4u);
  EXPECT_DOUBLE_EQ(g.frame_rate, 60.0);
}

TEST(CapiModel, RestPoseAndRigidMotionsAreExactAtTheSkinningStage) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  const pleat_test::SimpleMesh mesh = garment_mesh();
  pleat_test::GarmentPtr garment = pleat_test::create_garment(mesh);
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  pleat_instance_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_instance_get_info(instance.get(), &info), PLEAT_OK);
  EXPECT_EQ(info.vertex_count, mesh.vertex_count());
  EXPECT_EQ(info.joint_count, kJoints);
  EXPECT_EQ(info.top_k, 3u) << "the default 4 is clamped to the joint count";
  const size_t n = info.vertex_count;

  // Rest pose: every skinning matrix is the identity.
  std::vector<float> weights;
  const std::vector<float> rest =
      evaluate(instance.get(), root_motion(3, kStill, kIdentity), 0, 3, PLEAT_STAGE_SKINNING, &weights);
  for (size_t i = 0; i < rest.size(); ++i) ASSERT_NEAR(rest[i], mesh.positions[i % (n * 3)], 1e-5f) << i;
  for (size_t v = 0; v < 3 * n; ++v) {
    float sum = 0.0f;
    for (uint32_t j = 0; j < kJoints; ++j) {
      EXPECT_GE(weights[v * kJoints + j], 0.0f);
      sum += weights[v * kJoints + j];
    }
    EXPECT_NEAR(sum, 1.0f, 1e-5f) << "vertex " << v % n;
  }

  // The root walks along +x and turns 90 degrees about Y; the other joints
  // keep their rest rotation, so every joint moves rigidly with the root.
  const float step[3] = {0.05f, 0.0f, 0.02f};
  const float s = std::sqrt(0.5f), turn[4] = {0.0f, s, 0.0f, s};
  const Poses walk = root_motion(6, step, turn);
  const std::vector<float> moved = evaluate(instance.get(), walk, 2, 4, PLEAT_STAGE_SKINNING);
  for (size_t f = 0; f < 4; ++f)
    for (size_t v = 0; v < n; ++v) {
      const float* r = &walk.roots[(f + 2) * 3];
      const float x = mesh.positions[v * 3] - kJointPositions[0],
                  y = mesh.positions[v * 3 + 1] - kJointPositions[1],
                  z = mesh.positions[v * 3 + 2] - kJointPositions[2];
      // Rotation by 90 degrees about Y: (x, y, z) -> (z, y, -x).
      const float expected[3] = {r[0] + z, r[1] + y, r[2] - x};
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(moved[(f * n + v) * 3 + k], expected[k], 2e-5f) << "frame " << f << " vertex " << v;
    }

  // Later stages add learned offsets: finite, and different from skinning.
  const std::vector<float> full = evaluate(instance.get(), walk, 2, 4, PLEAT_STAGE_FULL);
  double difference = 0.0;
  for (size_t i = 0; i < full.size(); ++i) {
    ASSERT_TRUE(std::isfinite(full[i]));
    difference = std::max(difference, std::abs(double(full[i]) - moved[i]));
  }
  EXPECT_GT(difference, 0.0);
}

TEST(CapiModel, ResultsDependOnlyOnThePoses) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  const float step[3] = {0.03f, 0.01f, 0.0f};
  const float tilt[4] = {0.0f, 0.0f, std::sin(0.1f), std::cos(0.1f)};
  const Poses poses = root_motion(9, step, tilt);

  InstancePtr one = bind(model.get(), garment.get(), body.get(), 1, 1);
  const std::vector<float> reference = evaluate(one.get(), poses, 0, 9, PLEAT_STAGE_FULL);
  InstancePtr two = bind(model.get(), garment.get(), body.get(), 2, 4);
  EXPECT_EQ(evaluate(two.get(), poses, 0, 9, PLEAT_STAGE_FULL), reference) << "threads and batch size";
  // Split calls, in any order, give the same frames.
  const size_t n = reference.size() / 9;
  std::vector<float> late = evaluate(two.get(), poses, 5, 4, PLEAT_STAGE_FULL);
  std::vector<float> early = evaluate(two.get(), poses, 0, 5, PLEAT_STAGE_FULL);
  early.insert(early.end(), late.begin(), late.end());
  EXPECT_EQ(early, reference);
  EXPECT_EQ(evaluate(one.get(), poses, 4, 1, PLEAT_STAGE_FULL),
            std::vector<float>(reference.begin() + 4 * n, reference.begin() + 5 * n));
  // Playing on: each call reuses the last call's last frame for its
  // velocities, but only for the very poses that frame was computed from. A
  // change to any frame in its motion window (frame 1 for frame 4: 8 frames
  // back) or to the frame itself between the calls must be seen.
  const auto played = [&](const Poses& first_call, const Poses& second_call) {
    InstancePtr player = bind(model.get(), garment.get(), body.get(), 2, 4);
    evaluate(player.get(), first_call, 0, 5, PLEAT_STAGE_FULL);
    return evaluate(player.get(), second_call, 5, 4, PLEAT_STAGE_FULL);
  };
  for (size_t changed : {1u, 4u}) {
    Poses other = poses;
    other.roots[changed * 3] += 0.05f;
    InstancePtr fresh = bind(model.get(), garment.get(), body.get(), 2, 4);
    const std::vector<float> want = evaluate(fresh.get(), other, 5, 4, PLEAT_STAGE_FULL);
    EXPECT_NE(want, late) << "frame " << changed << " matters to frames 5-8";
    EXPECT_EQ(played(poses, other), want) << "frame " << changed << " changed between the calls";
  }
  EXPECT_EQ(played(poses, poses), late);

  // The instance keeps model, garment and body alive.
  model.reset();
  garment.reset();
  body.reset();
  EXPECT_EQ(evaluate(two.get(), poses, 0, 9, PLEAT_STAGE_FULL), reference);
}

// refinement_interval k: frames t with t % k == 0 are the full model's own;
// the frames after hold that frame's refinement offsets, turned with the
// character's heading, over their own skinned positions (the blend-shape
// stage's output), whatever the split into calls.
TEST(CapiModel, RefinementIntervalHoldsTheOffsetsInTheHeadingFrame) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  constexpr size_t kFrames = 11;
  constexpr uint32_t kInterval = 3;
  Poses poses;  // the root turns about +Y (the heading) and walks
  for (size_t f = 0; f < kFrames; ++f) {
    const float half = 0.5f * 0.15f * static_cast<float>(f);
    poses.rotations.insert(poses.rotations.end(), {0.0f, std::sin(half), 0.0f, std::cos(half)});
    for (uint32_t j = 1; j < kJoints; ++j)
      poses.rotations.insert(poses.rotations.end(), {0.0f, 0.0f, 0.0f, 1.0f});
    poses.roots.insert(poses.roots.end(), {0.02f * f, kJointPositions[1], 0.01f * f});
  }
  InstancePtr instance = bind(model.get(), garment.get(), body.get(), 1, 4);
  const std::vector<float> full = evaluate(instance.get(), poses, 0, kFrames, PLEAT_STAGE_FULL);
  const std::vector<float> skinned = evaluate(instance.get(), poses, 0, kFrames, PLEAT_STAGE_BLEND_SHAPES);
  const auto held = [&](size_t first, size_t count, uint32_t interval) {
    std::vector<float> positions(count * full.size() / kFrames, -1.0f);
    pleat_evaluate_options o = stage_options(PLEAT_STAGE_FULL);
    o.refinement_interval = interval;
    const pleat_evaluate_outputs out = positions_into(positions.data());
    const pleat_poses p = poses.view();
    EXPECT_EQ(pleat_instance_evaluate(instance.get(), &p, first, count, &o, &out), PLEAT_OK)
        << pleat_last_error();
    return positions;
  };
  const std::vector<float> got = held(0, kFrames, kInterval);
  const size_t n = full.size() / kFrames / 3;
  double refinement = 0.0, hold_differs = 0.0;
  for (size_t t = 0; t < kFrames; ++t) {
    const size_t t0 = t - t % kInterval;
    // Heading of frame t: 0.15 t rad about +Y; the offset turns by the difference.
    const float turn = 0.15f * static_cast<float>(t) - 0.15f * static_cast<float>(t0);
    const float c = std::cos(turn), s = std::sin(turn);
    for (size_t v = 0; v < n; ++v) {
      const size_t at = (t * n + v) * 3, at0 = (t0 * n + v) * 3;
      const float dx = full[at0] - skinned[at0], dy = full[at0 + 1] - skinned[at0 + 1],
                  dz = full[at0 + 2] - skinned[at0 + 2];
      const float want[3] = {skinned[at] + c * dx + s * dz, skinned[at + 1] + dy,
                             skinned[at + 2] - s * dx + c * dz};
      for (int k = 0; k < 3; ++k) {
        if (t == t0) {
          ASSERT_EQ(got[at + k], full[at + k]) << "refined frame " << t << " vertex " << v;
        }
        EXPECT_NEAR(got[at + k], want[k], 2e-6f) << "frame " << t << " vertex " << v;
        refinement = std::max(refinement, std::abs(double(full[at + k]) - skinned[at + k]));
        if (t != t0) hold_differs = std::max(hold_differs, std::abs(double(got[at + k]) - full[at + k]));
      }
    }
  }
  EXPECT_GT(refinement, 1e-4) << "the refinement moves the garment, so the test can see a hold";
  EXPECT_GT(hold_differs, 1e-6) << "held frames are not the full model's own";
  // A call that starts inside an interval, and interval 0 (= 1).
  EXPECT_EQ(held(4, 6, kInterval), std::vector<float>(got.begin() + 4 * n * 3, got.begin() + 10 * n * 3));
  EXPECT_EQ(held(0, kFrames, 0), full);
  pleat_evaluate_options o = stage_options(PLEAT_STAGE_FULL);
  o.refinement_interval = 1u << 21;
  std::vector<float> sink(full.size());
  const pleat_evaluate_outputs out = positions_into(sink.data());
  const pleat_poses p = poses.view();
  EXPECT_EQ(pleat_instance_evaluate(instance.get(), &p, 0, 1, &o, &out), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("refinement_interval"), std::string::npos)
      << pleat_last_error();
}

// band_attenuation a removes a of each band of the refinement's offsets. The
// band split is linear, so the high band of those offsets is the high band
// of the full output minus that of the blend-shape output (both from the
// band outputs): attenuated = full - a (high(full) - high(blend)).
TEST(CapiModel, BandAttenuationRemovesBandsOfTheRefinement) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  const float step[3] = {0.02f, 0.0f, 0.01f};
  const float turn[4] = {0.0f, std::sin(0.3f), 0.0f, std::cos(0.3f)};
  const Poses poses = root_motion(6, step, turn);
  const pleat_poses p = poses.view();
  const size_t n = garment_mesh().vertex_count(), floats = 6 * n * 3;
  const auto run = [&](pleat_instance* instance, uint32_t stage, float low, float mid, float high,
                       std::vector<float>* high_band = nullptr) {
    std::vector<float> positions(floats, -1.0f);
    pleat_evaluate_options o = stage_options(stage);
    o.band_attenuation[0] = low, o.band_attenuation[1] = mid, o.band_attenuation[2] = high;
    pleat_evaluate_outputs out = positions_into(positions.data());
    if (high_band) {
      high_band->assign(floats, -1.0f);
      out.high = {high_band->data(), 0};
    }
    const pleat_status status = pleat_instance_evaluate(instance, &p, 0, 6, &o, &out);
    return status == PLEAT_OK ? positions : std::vector<float>{static_cast<float>(status)};
  };
  InstancePtr unprepared = bind(model.get(), garment.get(), body.get());
  EXPECT_EQ(run(unprepared.get(), PLEAT_STAGE_FULL, 0, 0, 1), std::vector<float>{PLEAT_ERROR_NOT_PREPARED});
  EXPECT_NE(std::string(pleat_last_error()).find("prepare"), std::string::npos) << pleat_last_error();

  ASSERT_EQ(pleat_garment_prepare(garment.get(), nullptr), PLEAT_OK) << pleat_last_error();
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  std::vector<float> high_full, high_blend;
  const std::vector<float> full = run(instance.get(), PLEAT_STAGE_FULL, 0, 0, 0, &high_full);
  const std::vector<float> blend = run(instance.get(), PLEAT_STAGE_BLEND_SHAPES, 0, 0, 0, &high_blend);
  ASSERT_EQ(full.size(), floats);
  double refinement_high = 0.0;
  for (float a : {1.0f, 0.5f}) {
    const std::vector<float> got = run(instance.get(), PLEAT_STAGE_FULL, 0, 0, a);
    ASSERT_EQ(got.size(), floats) << pleat_last_error();
    for (size_t i = 0; i < floats; ++i) {
      const float removed = high_full[i] - high_blend[i];
      EXPECT_NEAR(got[i], full[i] - a * removed, 2e-6f) << "attenuation " << a << " float " << i;
      refinement_high = std::max(refinement_high, std::abs(double(removed)));
    }
  }
  EXPECT_GT(refinement_high, 1e-5) << "the refinement has a high band to remove";
  // Every band removed: the refinement is gone, the blend-shape stage is left.
  const std::vector<float> none = run(instance.get(), PLEAT_STAGE_FULL, 1, 1, 1);
  ASSERT_EQ(none.size(), floats);
  for (size_t i = 0; i < floats; ++i) EXPECT_NEAR(none[i], blend[i], 2e-6f) << i;
  // Out of range or not a number: refused, named.
  for (float bad : {1.5f, -0.1f, NAN}) {
    EXPECT_EQ(run(instance.get(), PLEAT_STAGE_FULL, 0, 0, bad),
              std::vector<float>{PLEAT_ERROR_INVALID_ARGUMENT});
    EXPECT_NE(std::string(pleat_last_error()).find("band_attenuation[2]' (high)"), std::string::npos)
        << pleat_last_error();
  }
}

// Only what is asked for is written: normals alone (no positions buffer)
// are the area-weighted normals of the positions a positions-only call
// gives, and the floats between strided frames stay as the host left them.
TEST(CapiModel, OnlyTheRequestedOutputsAreWritten) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  const pleat_test::SimpleMesh mesh = garment_mesh();
  pleat_test::GarmentPtr garment = pleat_test::create_garment(mesh);
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  const float step[3] = {0.02f, 0.0f, 0.01f};
  const float turn[4] = {0.0f, std::sin(0.2f), 0.0f, std::cos(0.2f)};
  const Poses poses = root_motion(3, step, turn);
  const pleat_poses p = poses.view();
  const size_t n = mesh.vertex_count(), stride = n * 3 + 2;
  const std::vector<float> positions = evaluate(instance.get(), poses, 0, 3, PLEAT_STAGE_FULL);

  std::vector<float> normals(3 * stride, -7.0f);
  pleat_evaluate_outputs out{};
  out.struct_size = sizeof out;
  out.normals = {normals.data(), stride};
  const pleat_evaluate_options o = stage_options(PLEAT_STAGE_FULL);
  ASSERT_EQ(pleat_instance_evaluate(instance.get(), &p, 0, 3, &o, &out), PLEAT_OK) << pleat_last_error();
  for (size_t f = 0; f < 3; ++f) {
    const std::vector<Eigen::Vector3f> want =
        pleat_test::area_weighted_normals(positions.data() + f * n * 3, n, mesh.triangles);
    for (size_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(normals[f * stride + v * 3 + k], want[v][k], 1e-5f) << "frame " << f << " vertex " << v;
    EXPECT_EQ(normals[f * stride + n * 3], -7.0f) << "frame " << f << ": the gap after the frame";
    EXPECT_EQ(normals[f * stride + n * 3 + 1], -7.0f);
  }
  // Skinning weights alone: a convex combination of at most the instance's top k joints per vertex.
  std::vector<float> weights(3 * n * kJoints, -1.0f);
  out = pleat_evaluate_outputs{};
  out.struct_size = sizeof out;
  out.skinning_weights = {weights.data(), 0};
  ASSERT_EQ(pleat_instance_evaluate(instance.get(), &p, 0, 3, &o, &out), PLEAT_OK) << pleat_last_error();
  pleat_instance_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_instance_get_info(instance.get(), &info), PLEAT_OK);
  for (size_t v = 0; v < 3 * n; ++v) {
    float sum = 0.0f;
    uint32_t nonzero = 0;
    for (uint32_t j = 0; j < kJoints; ++j) {
      const float w = weights[v * kJoints + j];
      EXPECT_GE(w, 0.0f);
      sum += w;
      nonzero += w > 0.0f;
    }
    EXPECT_NEAR(sum, 1.0f, 1e-5f) << v;
    EXPECT_LE(nonzero, info.top_k) << v;
  }
}

// A vertex mask: the networks run on the active vertices' neighbourhood only
// (9 rings for this model: 5 refinement layers, the normals' ring, 3 blend
// layers). The active vertices get what the whole garment gives them, so a
// region one ring too small shows here; the masked ones get the skinning
// stage's positions.
TEST(CapiModel, AVertexMaskKeepsTheActiveVerticesAndSkinsTheRest) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  const int columns = 40, rows = 12;  // the left 10 columns active: the mask's edge is inside the grid
  pleat_test::GarmentPtr garment =
      pleat_test::create_garment(pleat_test::grid(columns, rows, 0.01f, Eigen::Vector3f(-0.2f, 0.8f, 0.15f)));
  InstancePtr instance = bind(model.get(), garment.get(), body.get(), 2, 4);
  const float step[3] = {0.02f, 0.0f, 0.01f};
  const float turn[4] = {0.0f, std::sin(0.2f), 0.0f, std::cos(0.2f)};
  const Poses poses = root_motion(7, step, turn);
  const size_t n = size_t(columns) * rows;
  std::vector<uint8_t> mask(n);
  for (size_t v = 0; v < n; ++v) mask[v] = v % columns < 10;  // grid() numbers vertices row by row

  const std::vector<float> full = evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_FULL);
  const std::vector<float> blend = evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_BLEND_SHAPES);
  const std::vector<float> skinned = evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_SKINNING);
  ASSERT_EQ(pleat_instance_set_vertex_mask(instance.get(), mask.data(), n), PLEAT_OK) << pleat_last_error();
  const std::vector<float> masked_full = evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_FULL);
  const std::vector<float> masked_blend = evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_BLEND_SHAPES);
  double refinement = 0.0, blend_shapes = 0.0;
  for (size_t i = 0; i < full.size(); ++i) {
    const size_t v = i / 3 % n;
    if (mask[v]) {
      EXPECT_NEAR(masked_full[i], full[i], 1e-6f) << "active vertex " << v;
      EXPECT_NEAR(masked_blend[i], blend[i], 1e-6f) << "active vertex " << v;
      refinement = std::max(refinement, std::abs(double(full[i]) - blend[i]));
      blend_shapes = std::max(blend_shapes, std::abs(double(blend[i]) - skinned[i]));
    } else {
      EXPECT_EQ(masked_full[i], skinned[i]) << "masked vertex " << v;
      EXPECT_EQ(masked_blend[i], skinned[i]) << "masked vertex " << v;
    }
  }
  EXPECT_GT(refinement, 1e-4) << "the refinement moves the active vertices";
  EXPECT_GT(blend_shapes, 2e-5) << "so do the blend shapes";

  // NULL, or every vertex active, is no mask.
  ASSERT_EQ(pleat_instance_set_vertex_mask(instance.get(), nullptr, 0), PLEAT_OK);
  EXPECT_EQ(evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_FULL), full);
  std::fill(mask.begin(), mask.end(), uint8_t{7});
  ASSERT_EQ(pleat_instance_set_vertex_mask(instance.get(), mask.data(), n), PLEAT_OK);
  EXPECT_EQ(evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_FULL), full);
  // Nothing active: everything skinned.
  std::fill(mask.begin(), mask.end(), uint8_t{0});
  ASSERT_EQ(pleat_instance_set_vertex_mask(instance.get(), mask.data(), n), PLEAT_OK);
  EXPECT_EQ(evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_FULL), skinned);
  // A mask for another garment is refused, named, and the mask in place stays.
  EXPECT_EQ(pleat_instance_set_vertex_mask(instance.get(), mask.data(), n - 1), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("'vertex_count' is 479"), std::string::npos)
      << pleat_last_error();
  EXPECT_EQ(evaluate(instance.get(), poses, 2, 5, PLEAT_STAGE_FULL), skinned);
  EXPECT_EQ(pleat_instance_set_vertex_mask(nullptr, mask.data(), n), PLEAT_ERROR_INVALID_ARGUMENT);
}

TEST(CapiModel, BandOutputsSplitThePositionsOfAPreparedGarment) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  const Poses poses = root_motion(2, kStill, kIdentity);
  const pleat_poses p = poses.view();
  const size_t n = garment_mesh().vertex_count();
  std::vector<float> positions(2 * n * 3), low(2 * n * 3), mid(2 * n * 3), high(2 * n * 3);
  pleat_evaluate_outputs out{};
  out.struct_size = sizeof out;
  out.positions = {positions.data(), 0};
  out.low = {low.data(), 0};
  out.mid = {mid.data(), 0};
  out.high = {high.data(), 0};

  InstancePtr unprepared = bind(model.get(), garment.get(), body.get());
  EXPECT_EQ(pleat_instance_evaluate(unprepared.get(), &p, 0, 2, nullptr, &out), PLEAT_ERROR_NOT_PREPARED);
  EXPECT_NE(std::string(pleat_last_error()).find("prepare"), std::string::npos) << pleat_last_error();

  ASSERT_EQ(pleat_garment_prepare(garment.get(), nullptr), PLEAT_OK) << pleat_last_error();
  InstancePtr prepared = bind(model.get(), garment.get(), body.get());
  ASSERT_EQ(pleat_instance_evaluate(prepared.get(), &p, 0, 2, nullptr, &out), PLEAT_OK) << pleat_last_error();
  double low_energy = 0.0, high_energy = 0.0;
  for (size_t i = 0; i < positions.size(); ++i) {
    EXPECT_NEAR(low[i] + mid[i] + high[i], positions[i], 1e-5f) << i;
    low_energy += double(low[i]) * low[i];
    high_energy += double(high[i]) * high[i];
  }
  EXPECT_GT(low_energy, high_energy) << "a smooth garment lives mostly in the low band";
}

TEST(CapiModel, BadInputIsRefusedAndNamed) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  const std::string dir = pleat_test::temp_dir("capi_model_bad");

  pleat_model* m = reinterpret_cast<pleat_model*>(0x1);
  EXPECT_EQ(pleat_model_load((dir + "/missing.pleat").c_str(), &m), PLEAT_ERROR_IO);
  EXPECT_NE(std::string(pleat_last_error()).find("missing.pleat"), std::string::npos) << pleat_last_error();
  std::ofstream(dir + "/garbage.pleat") << "this is not a model file, not even close to one";
  EXPECT_EQ(pleat_model_load((dir + "/garbage.pleat").c_str(), &m), PLEAT_ERROR_FORMAT);
  EXPECT_EQ(m, reinterpret_cast<pleat_model*>(0x1)) << "outputs untouched on failure";
  EXPECT_EQ(pleat_model_load(nullptr, &m), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pleat_model_initialize(nullptr, nullptr, &m), PLEAT_ERROR_INVALID_ARGUMENT);
  pleat_model_init_options bad_init{};
  bad_init.struct_size = sizeof bad_init;
  bad_init.variant = 9;
  EXPECT_EQ(pleat_model_initialize(body.get(), &bad_init, &m), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("variant"), std::string::npos) << pleat_last_error();

  // A body whose skeleton differs from the model's cannot drive it.
  BodyPtr other = chain_body("hand");
  pleat_instance* in = reinterpret_cast<pleat_instance*>(0x1);
  EXPECT_EQ(pleat_instance_create(model.get(), garment.get(), other.get(), nullptr, &in),
            PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("'arm'"), std::string::npos) << pleat_last_error();
  EXPECT_EQ(in, reinterpret_cast<pleat_instance*>(0x1));
  EXPECT_EQ(pleat_instance_create(model.get(), nullptr, body.get(), nullptr, &in),
            PLEAT_ERROR_INVALID_ARGUMENT);

  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  const Poses poses = root_motion(4, kStill, kIdentity);
  const size_t n = garment_mesh().vertex_count();
  std::vector<float> positions(4 * n * 3, 42.0f);
  pleat_evaluate_outputs out{};
  out.struct_size = sizeof out;
  out.positions = {positions.data(), 0};
  const auto refused = [&](const pleat_poses& p, size_t first, size_t count, const pleat_evaluate_options* o,
                           pleat_status status, const std::string& part) {
    EXPECT_EQ(pleat_instance_evaluate(instance.get(), &p, first, count, o, &out), status) << part;
    EXPECT_NE(std::string(pleat_last_error()).find(part), std::string::npos) << pleat_last_error();
  };
  pleat_poses p = poses.view();
  refused(p, 2, 3, nullptr, PLEAT_ERROR_INVALID_ARGUMENT, "outside the 4 frames");
  p.joint_count = 2;
  refused(p, 0, 1, nullptr, PLEAT_ERROR_INVALID_ARGUMENT, "joint");
  p = poses.view(24.0);
  refused(p, 0, 1, nullptr, PLEAT_ERROR_INVALID_ARGUMENT, "pleat_motion_resample");
  Poses broken = poses;
  broken.rotations[(2 * kJoints + 1) * 4 + 3] = NAN;
  p = broken.view();
  refused(p, 0, 4, nullptr, PLEAT_ERROR_INVALID_ARGUMENT, "frame 2");
  p = poses.view();
  pleat_evaluate_options stage{};
  stage.struct_size = sizeof stage;
  stage.stage = 17;
  refused(p, 0, 1, &stage, PLEAT_ERROR_INVALID_ARGUMENT, "stage");
  p.struct_size = 0;
  refused(p, 0, 1, nullptr, PLEAT_ERROR_INVALID_ARGUMENT, "struct_size");
  p = poses.view();
  out.positions.frame_stride = 5;
  refused(p, 0, 1, nullptr, PLEAT_ERROR_INVALID_ARGUMENT, "frame_stride");
  for (float x : positions) ASSERT_EQ(x, 42.0f) << "nothing written by a refused call";
  EXPECT_EQ(pleat_instance_evaluate(nullptr, &p, 0, 1, nullptr, &out), PLEAT_ERROR_INVALID_ARGUMENT);
  pleat_instance_destroy(nullptr);
  pleat_model_destroy(nullptr);
}

// Instances on different threads (each with its own worker pool, all pinning
// OpenBLAS) give exactly what one instance gives alone.
TEST(CapiModel, ConcurrentInstancesDoNotInterfere) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  const float step[3] = {0.02f, 0.0f, 0.01f};
  const float tilt[4] = {std::sin(0.05f), 0.0f, 0.0f, std::cos(0.05f)};
  const Poses poses = root_motion(12, step, tilt);
  InstancePtr alone = bind(model.get(), garment.get(), body.get());
  const std::vector<float> reference = evaluate(alone.get(), poses, 0, 12, PLEAT_STAGE_FULL);

  std::vector<std::vector<float>> results(4);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < results.size(); ++t)
    threads.emplace_back([&, t] {
      InstancePtr mine = bind(model.get(), garment.get(), body.get(), 1 + t % 2, 1 + t);
      for (int repeat = 0; repeat < 5; ++repeat)
        results[t] = evaluate(mine.get(), poses, 0, 12, PLEAT_STAGE_FULL);
    });
  for (std::thread& t : threads) t.join();
  for (const std::vector<float>& r : results) EXPECT_EQ(r, reference);
}

// No drift over long sequences: the motion encoder re-reads each frame's
// window from a zero state, so frame 100,010 of a motion with period 10
// equals frame 20 bit for bit.
TEST(CapiModel, HundredThousandFramesDoNotDrift) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  Poses poses;
  const size_t frames = 100011;
  for (size_t f = 0; f < frames; ++f) {
    const float a = 0.4f * std::sin(2.0f * 3.14159265f * static_cast<float>(f % 10) / 10.0f);
    for (uint32_t j = 0; j < kJoints; ++j)
      poses.rotations.insert(poses.rotations.end(),
                             {0.0f, 0.0f, std::sin(a * (j + 1) / 2), std::cos(a * (j + 1) / 2)});
    poses.roots.insert(poses.roots.end(), {kJointPositions[0], kJointPositions[1], kJointPositions[2]});
  }
  EXPECT_EQ(evaluate(instance.get(), poses, 100010, 1, PLEAT_STAGE_FULL),
            evaluate(instance.get(), poses, 20, 1, PLEAT_STAGE_FULL));
  EXPECT_NE(evaluate(instance.get(), poses, 100010, 1, PLEAT_STAGE_FULL),
            evaluate(instance.get(), poses, 21, 1, PLEAT_STAGE_FULL));
}

namespace {

using MotionPtr = std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)>;

// A BVH clip of the chain (joints named as chain_body's unless `arm` says
// otherwise): the hips walk along x and turn, spine and arm swing.
MotionPtr chain_clip(const std::string& name, const char* arm = "arm", const char* frame_time = "0.0333333") {
  const std::string path = pleat_test::temp_dir("capi_model_motion") + "/" + name + ".bvh";
  std::ofstream bvh(path);
  bvh << "HIERARCHY\nROOT hips\n{\n OFFSET 0 1 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation "
         "Xrotation "
         "Yrotation\n JOINT spine\n {\n  OFFSET 0 0.3 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  JOINT "
      << arm
      << "\n  {\n   OFFSET 0.3 0.1 0\n   CHANNELS 3 Zrotation Xrotation Yrotation\n   End Site\n   {\n    "
         "OFFSET 0.2 "
         "0 0\n   }\n  }\n }\n}\nMOTION\nFrames: 8\nFrame Time: "
      << frame_time << "\n";
  for (int f = 0; f < 8; ++f)
    bvh << 0.02 * f << " 1 0 " << 3 * f << " 0 " << 5 * f << " " << 4 * f << " 2 0 " << -6 * f << " 0 " << f
        << "\n";
  bvh.close();
  pleat_motion_load_options o{};
  o.struct_size = sizeof o;
  o.unit_scale = 1.0;
  pleat_motion* m = nullptr;
  EXPECT_EQ(pleat_motion_load(path.c_str(), &o, &m), PLEAT_OK) << pleat_last_error();
  return MotionPtr(m, pleat_motion_destroy);
}

}  // namespace

// A motion evaluates exactly as its frames copied out into pleat_poses, and
// one on another skeleton or at another rate is refused by name.
TEST(CapiModel, MotionsEvaluateAsTheirPoses) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  MotionPtr motion = chain_clip("chain");
  Poses poses;
  poses.rotations.resize(8 * kJoints * 4);
  poses.roots.resize(8 * 3);
  ASSERT_EQ(pleat_motion_get_frames(motion.get(), 0, 8, poses.rotations.data(), poses.rotations.size(),
                                    poses.roots.data(), poses.roots.size()),
            PLEAT_OK)
      << pleat_last_error();
  std::vector<float> weights;
  const std::vector<float> positions = evaluate(instance.get(), poses, 3, 5, PLEAT_STAGE_FULL, &weights);

  const size_t n = positions.size() / 5;
  std::vector<float> from_motion(positions.size(), -1.0f), motion_weights(weights.size(), -1.0f);
  pleat_evaluate_outputs out{};
  out.struct_size = sizeof out;
  out.positions = {from_motion.data(), 0};
  out.skinning_weights = {motion_weights.data(), 0};
  ASSERT_EQ(pleat_instance_evaluate_motion(instance.get(), motion.get(), 3, 5, nullptr, &out), PLEAT_OK)
      << pleat_last_error();
  EXPECT_EQ(from_motion, positions) << "frames 0-2 are the history in both";
  EXPECT_EQ(motion_weights, weights);
  EXPECT_NE(std::vector<float>(positions.begin(), positions.begin() + n),
            std::vector<float>(positions.end() - n, positions.end()))
      << "the clip moves the garment";

  const auto refused = [&](const pleat_motion* m, size_t first, size_t count, const std::string& expected) {
    EXPECT_EQ(pleat_instance_evaluate_motion(instance.get(), m, first, count, nullptr, &out),
              PLEAT_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pleat_last_error()).find(expected), std::string::npos) << pleat_last_error();
  };
  refused(chain_clip("hand", "hand").get(), 0, 1, "motion joint 2 is 'hand', the bound body's is 'arm'");
  refused(chain_clip("fast", "arm", "0.0166667").get(), 0, 1, "poses come at 60");
  refused(motion.get(), 6, 3, "frames [6, 9) are outside the motion's 8");
  refused(nullptr, 0, 1, "motion");
}
