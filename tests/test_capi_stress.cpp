// The stress catalogue (docs/reliability.md): pathological garments and poses
// through the C API. Every case either fails with a specific status and a
// message, or evaluates to finite positions within kBound of the skinning
// stage's for the same frames (the offsets the network adds stay bounded
// because its hidden layers saturate; nothing may run away).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "capi/pleat.h"
#include "support/capi_chain.h"
#include "support/capi_support.h"
#include "support/interposed_allocator.h"
#include "support/sanitizers.h"

using namespace pleat_test::chain;

namespace {

constexpr float kBound = 0.5f;  // metres between the full and the skinning stage

// Frames that bend every joint through large angles, the root turning a full
// circle over the sequence.
Poses swinging(size_t frames) {
  Poses p;
  for (size_t f = 0; f < frames; ++f) {
    const float t = static_cast<float>(f) / static_cast<float>(frames);
    const float turn = 3.14159265f * t;  // half-angle: a full turn over the sequence
    p.rotations.insert(p.rotations.end(), {0.0f, std::sin(turn), 0.0f, std::cos(turn)});
    for (uint32_t j = 1; j < kJoints; ++j) {
      const float a = 1.2f * std::sin(6.0f * t + static_cast<float>(j));
      p.rotations.insert(p.rotations.end(), {std::sin(a), 0.0f, 0.0f, std::cos(a)});
    }
    for (int k = 0; k < 3; ++k) p.roots.push_back(kJointPositions[k] + (k == 0 ? 0.05f * f : 0.0f));
  }
  return p;
}

// Evaluates every frame at the skinning and the full stage and checks the
// outputs: finite, and the full stage within kBound of skinning.
void expect_finite_and_bounded(pleat_instance* instance, const Poses& poses, const std::string& context) {
  const size_t frames = poses.roots.size() / 3;
  const std::vector<float> skinned = evaluate(instance, poses, 0, frames, PLEAT_STAGE_SKINNING);
  const std::vector<float> full = evaluate(instance, poses, 0, frames, PLEAT_STAGE_FULL);
  ASSERT_EQ(skinned.size(), full.size());
  float worst = 0.0f;
  for (size_t i = 0; i < full.size(); ++i) {
    ASSERT_TRUE(std::isfinite(skinned[i]) && std::isfinite(full[i])) << context << ": value " << i;
    worst = std::max(worst, std::abs(full[i] - skinned[i]));
  }
  EXPECT_LE(worst, kBound) << context;
}

struct GarmentCase {
  std::string name;
  pleat_test::SimpleMesh mesh;
  std::set<pleat_status> refusals;  // statuses it may be refused with; empty: must load
  bool must_refuse = false;
  bool prepare = true;  // spectral bands (skipped for the largest garment: minutes of solving)
  size_t frames = 24;
};

pleat_test::SimpleMesh scaled(pleat_test::SimpleMesh m, float scale, Eigen::Vector3f at) {
  for (size_t v = 0; v < m.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k) m.positions[v * 3 + k] = at[k] + scale * (m.positions[v * 3 + k] - at[k]);
  return m;
}

std::vector<GarmentCase> garment_cases() {
  const pleat_test::SimpleMesh base = garment_mesh();
  std::vector<GarmentCase> cases;
  auto with = [&](std::string name, std::function<void(pleat_test::SimpleMesh&)> change,
                  std::set<pleat_status> refusals = {}) {
    pleat_test::SimpleMesh m = base;
    change(m);
    cases.push_back({std::move(name), std::move(m), std::move(refusals)});
  };
  with("zero-area faces",
       [](pleat_test::SimpleMesh& m) {
         m.triangles.insert(m.triangles.end(), {0, 1, 2});  // three collinear vertices of the first row
         m.triangles.insert(m.triangles.end(), {3, 3, 4});  // a repeated corner
       },
       {PLEAT_ERROR_INVALID_MESH});
  with("slivers", [](pleat_test::SimpleMesh& m) { m.positions[7 * 3 + 1] = m.positions[2 * 3 + 1] + 1e-6f; });
  with("duplicate faces",
       [](pleat_test::SimpleMesh& m) {
         const auto t = m.triangles;
         m.triangles.insert(m.triangles.end(), t.begin(), t.end());
       },
       {PLEAT_ERROR_INVALID_MESH});
  with("coincident unwelded copy", [](pleat_test::SimpleMesh& m) { m = pleat_test::concat(m, m); });
  with("non-manifold edge", [](pleat_test::SimpleMesh& m) {
    const uint32_t apex = static_cast<uint32_t>(m.vertex_count());
    m.positions.insert(m.positions.end(), {m.positions[0], m.positions[1], m.positions[2] + 0.1f});
    m.triangles.insert(m.triangles.end(), {m.triangles[0], m.triangles[1], apex});
  });
  with("isolated vertex", [](pleat_test::SimpleMesh& m) {
    m.positions.insert(m.positions.end(), {0, 2, 0});
  });
  with("one triangle",
       [](pleat_test::SimpleMesh& m) {
         m.positions.resize(9);
         m.triangles = {0, 1, 2};
         m.positions[7] += 0.1f;
       },
       {PLEAT_ERROR_INVALID_MESH});
  const Eigen::Vector3f centre(0.0f, 1.05f, 0.15f);
  cases.push_back({"0.1 mm garment (1e-4 m)", scaled(base, 1e-3f, centre), {PLEAT_ERROR_INVALID_MESH}});
  cases.push_back({"10 km garment (1e4 m)", scaled(base, 1e5f, centre), {PLEAT_ERROR_INVALID_MESH}});
  pleat_test::SimpleMesh one_vertex;
  one_vertex.positions = {0.0f, 1.0f, 0.15f};
  cases.push_back({"one vertex, no triangle", one_vertex, {PLEAT_ERROR_INVALID_MESH}, true});
  // 317 x 317 = 100,489 vertices, 2 mm apart, in front of the body: two
  // seconds in Release, two minutes under ASan, so the Release run covers it.
  if (!pleat_test::kUnderAddressSanitizer) {
    GarmentCase large{
        "100,489 vertices", pleat_test::grid(317, 317, 0.002f, Eigen::Vector3f(-0.3f, 0.8f, 0.15f)), {}};
    large.prepare = false;
    large.frames = 3;
    cases.push_back(std::move(large));
  }
  return cases;
}

TEST(CapiStress, PathologicalGarmentsAreRefusedOrStayBounded) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  for (const GarmentCase& c : garment_cases()) {
    const Poses poses = swinging(c.frames);
    pleat_garment* raw = nullptr;
    const uint32_t no_triangles[3] = {0, 0, 0};  // a valid pointer for a count of 0
    const pleat_status created =
        pleat_garment_create(c.mesh.positions.data(), c.mesh.vertex_count(),
                             c.mesh.triangles.empty() ? no_triangles : c.mesh.triangles.data(),
                             c.mesh.triangle_count(), nullptr, &raw);
    pleat_test::GarmentPtr garment(raw);
    std::printf("%-28s create %s", c.name.c_str(), pleat_status_name(created));
    if (created != PLEAT_OK) std::printf(" (%s)\n", pleat_last_error());
    EXPECT_TRUE(created != PLEAT_OK || !c.must_refuse) << c.name << ": loaded";
    if (created != PLEAT_OK) {
      EXPECT_TRUE(c.refusals.count(created))
          << c.name << ": " << pleat_status_name(created) << " " << pleat_last_error();
      EXPECT_NE(std::string(pleat_last_error()), "") << c.name;
      continue;
    }
    const pleat_status prepared = c.prepare ? pleat_garment_prepare(garment.get(), nullptr) : PLEAT_OK;
    std::printf(", prepare %s\n", c.prepare ? pleat_status_name(prepared) : "skipped");
    EXPECT_TRUE(prepared == PLEAT_OK || c.refusals.count(prepared))
        << c.name << ": prepare " << pleat_status_name(prepared) << " " << pleat_last_error();
    pleat_instance* instance = nullptr;
    const pleat_status bound =
        pleat_instance_create(model.get(), garment.get(), body.get(), nullptr, &instance);
    InstancePtr owned(instance, pleat_instance_destroy);
    if (bound != PLEAT_OK) {
      EXPECT_TRUE(c.refusals.count(bound))
          << c.name << ": bind " << pleat_status_name(bound) << " " << pleat_last_error();
      continue;
    }
    expect_finite_and_bounded(instance, poses, c.name);
  }
}

TEST(CapiStress, ExtremePosesAreRefusedOrStayBounded) {
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  const Poses reference = swinging(24);
  const std::vector<float> expected = evaluate(instance.get(), reference, 0, 24, PLEAT_STAGE_FULL);

  // q and -q are one rotation.
  Poses negated = reference;
  for (float& x : negated.rotations) x = -x;
  const std::vector<float> got = evaluate(instance.get(), negated, 0, 24, PLEAT_STAGE_FULL);
  for (size_t i = 0; i < got.size(); ++i) ASSERT_NEAR(got[i], expected[i], 1e-5f) << "-q, value " << i;

  // Large frame-to-frame motion: a root that teleports 1 km and back, a
  // joint that flips by nearly 360 degrees between frames, a root 50 km from
  // the origin (the largest accepted is 100 km).
  Poses teleport = reference;
  for (size_t f = 8; f < 12; ++f) teleport.roots[f * 3] += 1000.0f;
  expect_finite_and_bounded(instance.get(), teleport, "teleporting root");
  Poses flip = reference;
  for (size_t f = 0; f < 24; f += 2) {
    float* q = &flip.rotations[(f * kJoints + 1) * 4];
    q[0] = std::sin(3.1f), q[1] = 0.0f, q[2] = 0.0f, q[3] = std::cos(3.1f);  // 355 degrees
  }
  expect_finite_and_bounded(instance.get(), flip, "355-degree flips every other frame");
  Poses far = reference;
  for (size_t f = 0; f < 24; ++f) far.roots[f * 3 + 2] += 5e4f;
  expect_finite_and_bounded(instance.get(), far, "root 50 km out");

  // Values no pose has: refused, naming the frame, nothing written.
  const size_t n = garment_mesh().vertex_count();
  for (auto [what, value, rotation] : {std::tuple<const char*, float, bool>{"NaN rotation", NAN, true},
                                       {"infinite rotation", INFINITY, true},
                                       {"zero quaternion", 0.0f, true},
                                       {"quaternion of norm 1000", 1e3f, true},
                                       {"NaN root", NAN, false},
                                       {"root 1,000 km out", 1e6f, false},
                                       {"infinite root", -INFINITY, false}}) {
    Poses bad = reference;
    if (rotation) {
      float* q = &bad.rotations[(5 * kJoints + 2) * 4];
      if (value == 0.0f || value == 1e3f)
        for (int k = 0; k < 4; ++k) q[k] *= value;
      else
        q[1] = value;
    } else {
      bad.roots[5 * 3 + 1] = value;
    }
    std::vector<float> out(24 * n * 3, 42.0f);
    pleat_evaluate_outputs outputs{};
    outputs.struct_size = sizeof outputs;
    outputs.positions = {out.data(), 0};
    const pleat_poses view = bad.view();
    EXPECT_EQ(pleat_instance_evaluate(instance.get(), &view, 0, 24, nullptr, &outputs),
              PLEAT_ERROR_INVALID_ARGUMENT)
        << what;
    EXPECT_NE(std::string(pleat_last_error()).find("frame 5"), std::string::npos)
        << what << ": " << pleat_last_error();
    for (float x : out) ASSERT_EQ(x, 42.0f) << what << ": written by a refused call";
  }
}

}  // namespace

namespace {

// Frames [0, count) of `motion` at the skinning and the full stage: finite,
// and the full stage within kBound of skinning.
void evaluate_motion_bounded(pleat_instance* instance, const pleat_motion* motion, size_t count,
                             const std::string& context) {
  pleat_instance_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_instance_get_info(instance, &info), PLEAT_OK);
  std::vector<std::vector<float>> stages;
  for (uint32_t stage : {PLEAT_STAGE_SKINNING, PLEAT_STAGE_FULL}) {
    std::vector<float> positions(count * info.vertex_count * 3, NAN);
    const pleat_evaluate_options o = stage_options(stage);
    const pleat_evaluate_outputs out = positions_into(positions.data());
    ASSERT_EQ(pleat_instance_evaluate_motion(instance, motion, 0, count, &o, &out), PLEAT_OK)
        << context << ": " << pleat_last_error();
    stages.push_back(std::move(positions));
  }
  float worst = 0.0f;
  for (size_t i = 0; i < stages[0].size(); ++i) {
    ASSERT_TRUE(std::isfinite(stages[0][i]) && std::isfinite(stages[1][i])) << context << ": value " << i;
    worst = std::max(worst, std::abs(stages[1][i] - stages[0][i]));
  }
  EXPECT_LE(worst, kBound) << context;
}

}  // namespace

// The shipped dress model on the MakeHuman body with every macro slider at 0
// (the ethnic ones, which must not all be 0, at 1), every one at 1, and
// alternating: the body stays valid and the dress evaluates finite and
// bounded through a walk.
TEST(CapiStress, MakeHumanSlidersAtTheirLimitsTogether) {
  pleat_body* raw_body = nullptr;
  ASSERT_EQ(pleat_body_load((pleat_test::asset_dir() + "/body").c_str(), nullptr, &raw_body), PLEAT_OK)
      << pleat_last_error();
  BodyPtr body(raw_body, pleat_body_destroy);
  pleat_model* raw_model = nullptr;
  ASSERT_EQ(pleat_model_load((pleat_test::source_dir() + "/data/models/dress.pleat").c_str(), &raw_model),
            PLEAT_OK)
      << pleat_last_error();
  ModelPtr model(raw_model, pleat_model_destroy);
  pleat_garment_load_options go{};
  go.struct_size = sizeof go;
  go.unit_scale = 0.1;
  pleat_garment* raw_garment = nullptr;
  ASSERT_EQ(pleat_garment_load((pleat_test::source_dir() + "/data/garments/female_elegantsuit01.obj").c_str(),
                               &go, &raw_garment),
            PLEAT_OK)
      << pleat_last_error();
  pleat_test::GarmentPtr garment(raw_garment);
  pleat_motion* raw_clip = nullptr;
  ASSERT_EQ(
      pleat_motion_load((pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").c_str(),
                        nullptr, &raw_clip),
      PLEAT_OK);
  std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)> clip(raw_clip, pleat_motion_destroy);

  pleat_body_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_body_get_info(body.get(), &info), PLEAT_OK);
  ASSERT_GT(info.shape_count, 5u);
  // Every slider at 0 leaves no ethnicity to normalise: refused by name.
  std::vector<double> zeros(info.shape_count, 0.0);
  EXPECT_EQ(pleat_body_set_shape(body.get(), zeros.data(), zeros.size()), PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("ethnic"), std::string::npos) << pleat_last_error();
  const auto ethnic = [&](size_t i) {
    const std::string name = pleat_body_shape_name(body.get(), static_cast<uint32_t>(i));
    return name == "african" || name == "asian" || name == "caucasian";
  };
  for (int pattern = 0; pattern < 3; ++pattern) {
    std::vector<double> shape(info.shape_count);
    for (size_t i = 0; i < shape.size(); ++i)
      shape[i] = pattern == 2 ? double(i % 2) : pattern == 1 || ethnic(i) ? 1.0 : 0.0;
    const std::string context =
        pattern == 2 ? "sliders alternating 0 and 1" : "every slider at " + std::to_string(pattern);
    ASSERT_EQ(pleat_body_set_shape(body.get(), shape.data(), shape.size()), PLEAT_OK)
        << context << ": " << pleat_last_error();
    std::vector<float> rest(size_t(info.vertex_count) * 3);
    ASSERT_EQ(pleat_body_get_rest(body.get(), rest.data(), rest.size(), nullptr, 0, nullptr, 0), PLEAT_OK);
    for (float x : rest) ASSERT_TRUE(std::isfinite(x)) << context << ": body rest";

    pleat_motion* m = nullptr;
    ASSERT_EQ(pleat_motion_resample(clip.get(), 30.0, &m), PLEAT_OK) << pleat_last_error();
    std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)> at30(m, pleat_motion_destroy);
    ASSERT_EQ(pleat_motion_retarget(at30.get(), body.get(), nullptr, &m), PLEAT_OK) << pleat_last_error();
    std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)> retargeted(m, pleat_motion_destroy);
    InstancePtr instance = bind(model.get(), garment.get(), body.get());
    evaluate_motion_bounded(instance.get(), retargeted.get(), 12, context);
  }
}

// 100,000 frames (times PLEAT_STRESS_SCALE; scripts/stress.sh runs 10x) of a
// periodic motion, evaluated in chunks into one reused buffer: no allocation
// in any call, every value finite and within kBound of the skinning stage's,
// and the last period bit-identical to the first (no drift).
TEST(CapiStress, LongSequencesNeitherDriftNorGrow) {
  if (pleat_test::kUnderAddressSanitizer) GTEST_SKIP() << "minutes under ASan; the Release run covers it";
  const char* scale_text = std::getenv("PLEAT_STRESS_SCALE");
  const size_t scale = scale_text ? std::max(1, std::atoi(scale_text)) : 1;
  const size_t frames = 100000 * scale, chunk = 1000, period = 10;
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  const Poses one_period = swinging(period);
  Poses poses;
  for (size_t f = 0; f < frames; f += period) {
    poses.rotations.insert(poses.rotations.end(), one_period.rotations.begin(), one_period.rotations.end());
    for (size_t i = 0; i < period; ++i)
      poses.roots.insert(poses.roots.end(), {kJointPositions[0], kJointPositions[1], kJointPositions[2]});
  }
  const size_t n = garment_mesh().vertex_count();
  std::vector<float> full(chunk * n * 3), skinned(chunk * n * 3), first_period, last_period;
  const pleat_poses view = poses.view();
  const auto run = [&](size_t first, uint32_t stage, std::vector<float>& out) {
    const pleat_evaluate_options o = stage_options(stage);
    const pleat_evaluate_outputs outputs = positions_into(out.data());
    return pleat_instance_evaluate(instance.get(), &view, first, chunk, &o, &outputs);
  };
  first_period.reserve(period * n * 3);
  last_period.reserve(period * n * 3);
  const long allocations_before = pleat_test::allocation_count();
  float worst = 0.0f;
  bool finite = true;
  for (size_t first = 0; first < frames; first += chunk) {
    ASSERT_EQ(run(first, PLEAT_STAGE_FULL, full), PLEAT_OK) << pleat_last_error();
    ASSERT_EQ(run(first, PLEAT_STAGE_SKINNING, skinned), PLEAT_OK) << pleat_last_error();
    for (size_t i = 0; i < full.size(); ++i) {
      finite = finite && std::isfinite(full[i]);
      worst = std::max(worst, std::abs(full[i] - skinned[i]));
    }
    if (first == 10 * chunk) first_period.assign(full.begin(), full.begin() + period * n * 3);
  }
  last_period.assign(full.end() - period * n * 3, full.end());
  if (pleat_test::kAllocatorInterposed) {
    EXPECT_EQ(pleat_test::allocation_count() - allocations_before, 0) << "evaluate allocated";
  }
  EXPECT_TRUE(finite);
  EXPECT_LE(worst, kBound);
  EXPECT_EQ(first_period, last_period) << "frames " << 10 * chunk << "+ and the last period differ";
}

// A clip recorded at 240 fps (e.g. optical capture) reaches the model through
// pleat_motion_resample. Each 30 fps frame of clip A is held for eight frames
// of clip B at 240 fps, so B resampled to 30 fps lands on A's frames exactly:
// the garment must come out as A's, finite and bounded.
TEST(CapiStress, A240FpsClipEvaluatesAsItsResampledFrames) {
  const std::string dir = pleat_test::temp_dir("capi_stress_240fps");
  const auto write_bvh = [&](const std::string& path, int repeat, double frame_time) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr) << path;
    std::fprintf(
        f,
        "HIERARCHY\nROOT hips\n{\n OFFSET 0 1 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation "
        "Xrotation Yrotation\n JOINT spine\n {\n  OFFSET 0 0.3 0\n  CHANNELS 3 Zrotation Xrotation "
        "Yrotation\n  JOINT arm\n  {\n   OFFSET 0.3 0.1 0\n   CHANNELS 3 Zrotation Xrotation Yrotation\n"
        "   End Site\n   {\n    OFFSET 0.1 0 0\n   }\n  }\n }\n}\nMOTION\nFrames: %d\nFrame Time: %.9f\n",
        12 * repeat, frame_time);
    for (int frame = 0; frame < 12; ++frame)
      for (int r = 0; r < repeat; ++r)
        std::fprintf(f, "%.4f 1 %.4f %.3f 0 %.3f %.3f %.3f 0 %.3f 0 %.3f\n", 0.03 * frame, 0.01 * frame,
                     20.0 * std::sin(0.5 * frame), 15.0 * frame, 40.0 * std::sin(0.7 * frame),
                     10.0 * std::cos(0.3 * frame), 60.0 * std::sin(0.9 * frame), 5.0 * frame);
    std::fclose(f);
  };
  ASSERT_NO_FATAL_FAILURE(write_bvh(dir + "/a30.bvh", 1, 1.0 / 30.0));
  ASSERT_NO_FATAL_FAILURE(write_bvh(dir + "/b240.bvh", 8, 1.0 / 240.0));
  BodyPtr body = chain_body();
  ModelPtr model = initialised(body.get());
  pleat_test::GarmentPtr garment = pleat_test::create_garment(garment_mesh());
  InstancePtr instance = bind(model.get(), garment.get(), body.get());
  pleat_motion_load_options o{};
  o.struct_size = sizeof o;
  o.unit_scale = 1.0;
  const auto prepared = [&](const std::string& path, double expect_fps) {
    pleat_motion *loaded = nullptr, *resampled = nullptr, *retargeted = nullptr;
    EXPECT_EQ(pleat_motion_load(path.c_str(), &o, &loaded), PLEAT_OK) << pleat_last_error();
    pleat_motion_info info{};
    info.struct_size = sizeof info;
    EXPECT_EQ(pleat_motion_get_info(loaded, &info), PLEAT_OK);
    EXPECT_NEAR(info.frame_rate, expect_fps, 1e-6) << path;
    EXPECT_EQ(pleat_motion_resample(loaded, 30.0, &resampled), PLEAT_OK) << pleat_last_error();
    EXPECT_EQ(pleat_motion_retarget(resampled, body.get(), nullptr, &retargeted), PLEAT_OK)
        << pleat_last_error();
    pleat_motion_destroy(loaded);
    pleat_motion_destroy(resampled);
    return std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)>(retargeted, pleat_motion_destroy);
  };
  const auto a = prepared(dir + "/a30.bvh", 30.0);
  const auto b = prepared(dir + "/b240.bvh", 240.0);
  ASSERT_TRUE(a && b);
  pleat_motion_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_motion_get_info(b.get(), &info), PLEAT_OK);
  ASSERT_GE(info.frame_count, 12u) << "96 frames at 240 fps (95 / 240 s) span 12 at 30 fps";
  const size_t n = garment_mesh().vertex_count();
  const auto run = [&](const pleat_motion* motion, uint32_t stage) {
    std::vector<float> out(12 * n * 3, NAN);
    const pleat_evaluate_options eo = stage_options(stage);
    const pleat_evaluate_outputs outputs = positions_into(out.data());
    EXPECT_EQ(pleat_instance_evaluate_motion(instance.get(), motion, 0, 12, &eo, &outputs), PLEAT_OK)
        << pleat_last_error();
    return out;
  };
  const std::vector<float> want = run(a.get(), PLEAT_STAGE_FULL), got = run(b.get(), PLEAT_STAGE_FULL);
  const std::vector<float> skinned = run(b.get(), PLEAT_STAGE_SKINNING);
  float moved = 0.0f;
  for (size_t i = 0; i < want.size(); ++i) {
    ASSERT_TRUE(std::isfinite(got[i])) << i;
    EXPECT_NEAR(got[i], want[i], 1e-4f) << "frame " << i / (n * 3);
    EXPECT_LE(std::abs(got[i] - skinned[i]), kBound) << i;
    moved = std::max(moved, std::abs(got[i] - got[i % (n * 3)]));
  }
  EXPECT_GT(moved, 0.05f) << "the clip moves the garment";
}
