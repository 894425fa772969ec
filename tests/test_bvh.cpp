// BVH reader: every shared clip loads with the header's frame count and rate,
// hand-written files give known rotations, malformed files fail with
// PLEAT_ERROR_FORMAT naming the line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "body/bvh.h"
#include "core/error.h"
#include "support/expect_error.h"
#include "support/test_support.h"

namespace fs = std::filesystem;
using pleat::BvhClip;
using pleat::BvhOptions;

namespace {

std::string motions_dir() {
  return pleat_test::asset_dir() + "/motions";
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

using pleat_test::expect_error;

Eigen::Matrix3d rot(char axis, double degrees) {
  const Eigen::Vector3d a = axis == 'X'   ? Eigen::Vector3d::UnitX()
                            : axis == 'Y' ? Eigen::Vector3d::UnitY()
                                          : Eigen::Vector3d::UnitZ();
  return Eigen::AngleAxisd(degrees * M_PI / 180.0, a).toRotationMatrix();
}

// Two joints and an end site; root channels in an unusual order.
const char* kTiny =
    "HIERARCHY\r\n"
    "ROOT Hips\r\n"
    "{\r\n"
    "  OFFSET 0 0 0\r\n"
    "  CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation\r\n"
    "  JOINT Chest\r\n"
    "  {\r\n"
    "    OFFSET 0 10 0\r\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\r\n"
    "    End Site\r\n"
    "    {\r\n"
    "      OFFSET 0 5 0\r\n"
    "    }\r\n"
    "  }\r\n"
    "}\r\n"
    "MOTION\r\n"
    "Frames: 2\r\n"
    "Frame Time: 0.0333333\r\n"
    "1 2 3 10 20 30 40 50 60 \r\n"
    "0 0 0 0 0 0 0 0 90\r\n"
    "\r\n";

std::string tiny_with(const std::string& from, const std::string& to) {
  std::string s = kTiny;
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST(Bvh, TinyFileRotationsFollowChannelOrder) {
  BvhOptions options;
  options.scale = 0.01;  // centimetres
  const BvhClip clip = pleat::parse_bvh(kTiny, "tiny.bvh", options);
  const pleat::Motion& m = clip.motion;
  ASSERT_EQ(m.skeleton.joint_count(), 2);
  EXPECT_EQ(m.skeleton.names[1], "Chest");
  EXPECT_EQ(m.skeleton.parents[1], 0);
  EXPECT_EQ(m.frame_count, 2);
  EXPECT_DOUBLE_EQ(m.frame_rate, 30.0);  // 1 / 0.0333333 snapped
  EXPECT_TRUE(clip.conversion.frame_rate_snapped);
  EXPECT_FALSE(clip.conversion.scale_guessed);
  EXPECT_EQ(clip.rotation_orders[0], "YXZ");
  EXPECT_EQ(clip.rotation_orders[1], "ZXY");
  EXPECT_NEAR(m.skeleton.rest_translation(1, 1), 0.10, 1e-15);
  EXPECT_TRUE(m.root_translation.row(0).isApprox(Eigen::RowVector3d(0.01, 0.02, 0.03), 1e-15));
  // Intrinsic composition in the order given.
  const Eigen::Matrix3d root = rot('Y', 10) * rot('X', 20) * rot('Z', 30);
  const Eigen::Matrix3d chest = rot('Z', 40) * rot('X', 50) * rot('Y', 60);
  EXPECT_LT((m.frame(0)[0].toRotationMatrix() - root).norm(), 1e-12);
  EXPECT_LT((m.frame(0)[1].toRotationMatrix() - chest).norm(), 1e-12);
  EXPECT_LT((pleat::bvh_euler_rotation("ZXY", {40, 50, 60}).toRotationMatrix() - chest).norm(), 1e-12);
  // Frame 1: the chest turned 90 degrees about Y; the end site 5 cm above it.
  ASSERT_EQ(clip.end_sites.size(), 1u);
  EXPECT_EQ(clip.end_sites[0].joint, 1);
  pleat::Points3d joints, ends;
  pleat::bvh_frame_positions(clip, 1, &joints, &ends);
  EXPECT_TRUE(joints.row(1).isApprox(Eigen::RowVector3d(0, 0.10, 0), 1e-12));
  EXPECT_TRUE(ends.row(0).isApprox(Eigen::RowVector3d(0, 0.15, 0), 1e-12));
  // Frame 0: the end site goes where R_root * (offset + R_chest * end).
  pleat::bvh_frame_positions(clip, 0, &joints, &ends);
  const Eigen::Vector3d expected = Eigen::Vector3d(0.01, 0.02, 0.03) +
                                   root * (Eigen::Vector3d(0, 0.10, 0) + chest * Eigen::Vector3d(0, 0.05, 0));
  EXPECT_LT((ends.row(0).transpose() - expected).norm(), 1e-12);
}

TEST(Bvh, UnitGuessAndZUp) {
  // 170 units tall in centimetres, Z up: a leg down -Z and a head up +Z.
  const char* text =
      "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 95\nCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation "
      "Xrotation\n"
      "JOINT Leg\n{\nOFFSET 10 0 -95\nCHANNELS 3 Xrotation Yrotation Zrotation\nEnd Site\n{\nOFFSET 0 -20 "
      "0\n}\n}\n"
      "JOINT Head\n{\nOFFSET 0 0 75\nCHANNELS 3 Xrotation Yrotation Zrotation\nEnd Site\n{\nOFFSET 0 0 "
      "0\n}\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 0.5\n0 5 95 0 0 0 90 0 0 0 0 0\n";
  const BvhClip clip = pleat::parse_bvh(text, "zup.bvh");
  EXPECT_TRUE(clip.conversion.scale_guessed);
  EXPECT_DOUBLE_EQ(clip.conversion.scale, 0.01);
  EXPECT_EQ(clip.conversion.unit, "centimetre");
  EXPECT_TRUE(clip.conversion.z_up_converted);
  EXPECT_NEAR(clip.conversion.height_m, 1.7, 1e-12);
  EXPECT_DOUBLE_EQ(clip.motion.frame_rate, 2.0);
  // (x, y, z) -> (x, z, -y): the root at 0.95 m up, moved 5 cm toward -Z.
  EXPECT_LT((clip.motion.root_translation.row(0) - Eigen::RowVector3d(0, 0.95, -0.05)).norm(), 1e-12);
  EXPECT_LT((clip.motion.skeleton.rest_translation.row(1) - Eigen::RowVector3d(0.1, -0.95, 0)).norm(), 1e-12);
  // The leg turned 90 degrees about the file's X axis: its end site (file -Y)
  // goes to file -Z, i.e. pleat -Y.
  pleat::Points3d joints, ends;
  pleat::bvh_frame_positions(clip, 0, &joints, &ends);
  EXPECT_LT((ends.row(0) - (joints.row(1) + Eigen::RowVector3d(0, -0.2, 0))).norm(), 1e-12);
  EXPECT_FALSE(clip.conversion.summary().empty());
}

TEST(Bvh, MalformedInputNamesTheLine) {
  const auto F = PLEAT_ERROR_FORMAT;
  auto parse = [](const std::string& text) { return [text] { pleat::parse_bvh(text, "bad.bvh"); }; };
  expect_error(parse(tiny_with("    CHANNELS 3 Zrotation Xrotation Yrotation\r\n", "")), F,
               "bad.bvh:6: joint 'Chest' has no CHANNELS");
  expect_error(parse(tiny_with("0 0 0 0 0 0 0 0 90", "0 0 0 0 0 0 0 90")), F,
               "bad.bvh:20: frame 1 has 8 values");
  expect_error(parse(tiny_with("0 0 0 0 0 0 0 0 90", "0 0 0 0 0 0 0 0 90 1")), F,
               "bad.bvh:20: frame 1 has 10 values");
  expect_error(parse(tiny_with("0 0 0 0 0 0 0 0 90\r\n", "")), F, "truncated MOTION data: 1 rows");
  expect_error(parse(tiny_with("Frames: 2", "Frames: 1")), F, "bad.bvh:20: more motion rows");
  expect_error(parse(tiny_with("Frames: 2", "Frames: 999999999")), F, "truncated MOTION data: 2 rows");
  expect_error(parse(tiny_with("40 50 60", "40 nan 60")), F, "bad.bvh:19: non-finite value 'nan'");
  expect_error(parse(tiny_with("40 50 60", "40 5x 60")), F, "bad.bvh:19: '5x' is not a number");
  expect_error(parse(tiny_with("    OFFSET 0 10 0", "    OFSET 0 10 0")), F,
               "bad.bvh:8: unknown keyword 'OFSET'");
  expect_error(parse(tiny_with("OFFSET 0 10 0", "OFFSET 0 10")), F,
               "bad.bvh:8: OFFSET of joint 'Chest' needs 3");
  expect_error(parse(tiny_with("CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 3 Zrotation Xrotation")),
               F, "bad.bvh:9: CHANNELS declares 3 channels but names 2");
  expect_error(parse(tiny_with("Zrotation Xrotation Yrotation", "Zrotation Wrotation Yrotation")), F,
               "bad.bvh:9: unknown channel 'Wrotation'");
  expect_error(parse(tiny_with("Frame Time: 0.0333333", "Frame Time: 0")), F,
               "bad.bvh:18: frame time must be");
  expect_error(parse(tiny_with("MOTION\r\n", "")), F, "bad.bvh:16: expected MOTION");
  expect_error(parse(tiny_with("  }\r\n}\r\n", "  }\r\n")), F, "bad.bvh:15: unknown keyword 'MOTION'");
  expect_error(parse(std::string(kTiny).substr(0, 120)), F, "bad.bvh:");
  expect_error(parse(""), F, "empty file");
  expect_error(parse(tiny_with("JOINT Chest", "JOINT Hips")), F, "named twice");
  expect_error([] { pleat::read_bvh("/nonexistent/x.bvh"); }, PLEAT_ERROR_IO, "/nonexistent/x.bvh");
  BvhOptions bad;
  bad.scale = -1;
  expect_error([&] { pleat::parse_bvh(kTiny, "tiny.bvh", bad); }, PLEAT_ERROR_INVALID_ARGUMENT, "scale");
}

TEST(Bvh, EverySharedClipLoads) {
  const std::string dir = motions_dir();
  if (!fs::exists(dir)) FAIL() << dir << " not present";
  const std::regex frames_re(R"(Frames:\s*(\d+))"), time_re(R"(Frame Time:\s*([0-9.eE+-]+))");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.path().extension() != ".bvh") continue;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    const std::string text = slurp(path);
    std::smatch fm, tm;
    ASSERT_TRUE(std::regex_search(text, fm, frames_re));
    ASSERT_TRUE(std::regex_search(text, tm, time_re));
    const int64_t frames = std::stoll(fm[1]);
    const double frame_time = std::stod(tm[1]);
    const BvhClip clip = pleat::read_bvh(path);
    const pleat::Motion& m = clip.motion;
    ++files;
    EXPECT_EQ(m.frame_count, frames);
    EXPECT_NEAR(m.frame_rate, 1.0 / frame_time, 1e-4 / frame_time);
    EXPECT_EQ(m.frame_rate, std::round(m.frame_rate));  // 120, 30, 24
    EXPECT_EQ(m.rotations.size(), static_cast<size_t>(frames * m.skeleton.joint_count()));
    for (const auto& q : m.rotations) ASSERT_TRUE(q.coeffs().allFinite());
    ASSERT_TRUE(m.root_translation.allFinite());
    // A human between 1.2 and 2 m tall (rest skeleton extent, head end site to toes).
    EXPECT_GT(clip.conversion.height_m, 1.2) << clip.conversion.summary();
    EXPECT_LT(clip.conversion.height_m, 2.0) << clip.conversion.summary();
    const std::string family = entry.path().parent_path().filename().string();
    if (family == "cmu_mb" || family == "cmu_3dsmax") {
      EXPECT_EQ(m.skeleton.joint_count(), 31);
      EXPECT_EQ(clip.conversion.channel_count, 96);
      EXPECT_EQ(clip.conversion.unit, "CMU ASF unit (1/0.45 inch)");
      EXPECT_DOUBLE_EQ(m.frame_rate, 120.0);
    } else if (family == "cmu_daz") {
      EXPECT_EQ(m.skeleton.joint_count(), 43);
      EXPECT_EQ(m.skeleton.names[0], "hip");
      EXPECT_EQ(clip.conversion.unit, "centimetre");
    } else if (family == "cmu_other") {
      EXPECT_EQ(m.skeleton.joint_count(), 19);
      EXPECT_EQ(clip.conversion.unit, "inch");
      EXPECT_DOUBLE_EQ(m.frame_rate, 30.0);
    } else if (family == "makehuman_poses") {
      EXPECT_EQ(m.frame_count, 1);
      EXPECT_DOUBLE_EQ(m.frame_rate, 24.0);
      EXPECT_TRUE(clip.conversion.z_up_converted);
      // Relative position channels, detected where non-root joints have some.
      EXPECT_EQ(clip.conversion.positions_relative, clip.conversion.joints_with_positions > 0);
      EXPECT_EQ(clip.conversion.unit, "decimetre");
      EXPECT_LT(clip.conversion.dropped_translation_m, 1e-3) << clip.conversion.summary();
    }
    if (family != "makehuman_poses") {
      EXPECT_FALSE(clip.conversion.z_up_converted);
      EXPECT_FALSE(clip.conversion.positions_relative);
      // Standing clips keep the root about a hip height above y = 0 on average.
      const double mean_root_y = m.root_translation.col(1).mean();
      EXPECT_GT(mean_root_y, 0.3) << clip.conversion.summary();
      EXPECT_LT(mean_root_y, 1.3) << clip.conversion.summary();
    }
  }
  EXPECT_GE(files, 30);
}

TEST(Bvh, KnownClipHeaders) {
  const std::string dir = motions_dir();
  if (!fs::exists(dir)) FAIL() << dir << " not present";
  const BvhClip a = pleat::read_bvh(dir + "/cmu_mb/01_01.bvh");
  EXPECT_EQ(a.motion.frame_count, 2752);
  EXPECT_DOUBLE_EQ(a.motion.frame_rate, 120.0);
  EXPECT_EQ(a.motion.skeleton.names[22], "LFingers");
  const BvhClip b = pleat::read_bvh(dir + "/cmu_other/10_01.bvh");
  EXPECT_EQ(b.motion.frame_count, 201);
  EXPECT_DOUBLE_EQ(b.motion.frame_rate, 30.0);
  EXPECT_EQ(b.rotation_orders[0], "ZXY");
  const BvhClip c = pleat::read_bvh(dir + "/cmu_3dsmax/131_01.bvh");  // CRLF
  EXPECT_EQ(c.motion.frame_count, 994);
  EXPECT_EQ(c.motion.skeleton.names.back(), "RThumb");
}

TEST(Bvh, FixtureLoads) {
  const BvhClip clip =
      pleat::read_bvh(pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh");
  EXPECT_EQ(clip.motion.frame_count, 121);
  EXPECT_EQ(clip.motion.skeleton.joint_count(), 31);
  EXPECT_EQ(clip.end_sites.size(), 7u);  // toes x2, head, fingers x2, thumbs x2
}
