// Motion operations: resampling, retargeting (by names and mapping files),
// mirroring, turning, and their error cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "body/bvh.h"
#include "body/makehuman.h"
#include "body/motion_ops.h"
#include "core/error.h"
#include "support/expect_error.h"
#include "support/test_support.h"

namespace fs = std::filesystem;
using pleat::Motion;
using pleat::Points3d;

namespace {

std::string motions_dir() {
  return pleat_test::asset_dir() + "/motions";
}
std::string map_path(const std::string& name) {
  return pleat_test::source_dir() + "/data/retarget/" + name;
}

Motion walk_fixture() {
  return pleat::read_bvh(pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").motion;
}

using pleat_test::expect_error;

double angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

Eigen::Vector3d bone(const Points3d& p, int32_t from, int32_t to) {
  return (p.row(to) - p.row(from)).transpose().normalized();
}

// Largest angle (degrees) over all frames between the target bone a->b and the source bone sa->sb.
double max_bone_angle(const Motion& source, const Motion& target, const std::string& sa,
                      const std::string& sb, const std::string& ta, const std::string& tb) {
  const int32_t s0 = source.skeleton.find(sa), s1 = source.skeleton.find(sb);
  const int32_t t0 = target.skeleton.find(ta), t1 = target.skeleton.find(tb);
  EXPECT_TRUE(s0 >= 0 && s1 >= 0 && t0 >= 0 && t1 >= 0) << sa << sb << ta << tb;
  if (s0 < 0 || s1 < 0 || t0 < 0 || t1 < 0) return 180;
  double worst = 0;
  for (int64_t f = 0; f < source.frame_count; ++f) {
    const Points3d ps = pleat::joint_positions(source, f), pt = pleat::joint_positions(target, f);
    const double c = std::clamp(bone(ps, s0, s1).dot(bone(pt, t0, t1)), -1.0, 1.0);
    worst = std::max(worst, std::acos(c) * 180.0 / M_PI);
  }
  return worst;
}

struct FootError {
  double max = 0;           // largest distance (metres) between the target joint and scale * the source joint
  double max_vertical = 0;  // largest |difference in y|
  double max_from_mean = 0;  // largest distance from the mean difference (trajectory shape)
  double target_min_y = 1e9;
};

FootError foot_error(const Motion& source, const Motion& target, const std::string& s, const std::string& t,
                     double scale) {
  const int32_t js = source.skeleton.find(s), jt = target.skeleton.find(t);
  FootError e;
  std::vector<Eigen::RowVector3d> d;
  Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
  for (int64_t f = 0; f < source.frame_count; ++f) {
    const Eigen::RowVector3d pt = pleat::joint_positions(target, f).row(jt);
    d.push_back(pt - scale * pleat::joint_positions(source, f).row(js));
    mean += d.back() / static_cast<double>(source.frame_count);
    e.max = std::max(e.max, d.back().norm());
    e.max_vertical = std::max(e.max_vertical, std::abs(d.back()[1]));
    e.target_min_y = std::min(e.target_min_y, pt[1]);
  }
  for (const auto& x : d) e.max_from_mean = std::max(e.max_from_mean, (x - mean).norm());
  return e;
}

double max_joint_distance(const Motion& source, const Motion& target, const std::string& s,
                          const std::string& t, double scale) {
  return foot_error(source, target, s, t, scale).max;
}

// The cmu_mb skeleton with the MakeHuman rig's finger names.
pleat::Skeleton cmu_mb_target() {
  pleat::Skeleton s = walk_fixture().skeleton;
  pleat::rename_joints(&s, pleat::read_joint_map(map_path("cmu_mb.txt")));
  return s;
}

const char* const kCmuMbRig[] = {
    "Hips",         "LHipJoint",      "LeftUpLeg",       "LeftLeg",         "LeftFoot",
    "LeftToeBase",  "RHipJoint",      "RightUpLeg",      "RightLeg",        "RightFoot",
    "RightToeBase", "LowerBack",      "Spine",           "Spine1",          "Neck",
    "Neck1",        "Head",           "LeftShoulder",    "LeftArm",         "LeftForeArm",
    "LeftHand",     "LeftFingerBase", "LeftHandFinger1", "LThumb",          "RightShoulder",
    "RightArm",     "RightForeArm",   "RightHand",       "RightFingerBase", "RightHandFinger1",
    "RThumb"};

}  // namespace

TEST(Resample, KeepsPoseAtMatchingTimes) {
  const Motion m = walk_fixture();  // 121 frames at 120 fps = 1 s
  const Motion r = pleat::resample_motion(m, 30.0);
  EXPECT_EQ(r.frame_count, 31);
  EXPECT_EQ(r.frame_rate, 30.0);
  const int32_t n = m.skeleton.joint_count();
  for (int64_t i = 0; i < r.frame_count; ++i) {
    for (int32_t j = 0; j < n; ++j) ASSERT_LT(angle(r.frame(i)[j], m.frame(4 * i)[j]), 1e-12);
    ASSERT_LT((r.root_translation.row(i) - m.root_translation.row(4 * i)).norm(), 1e-12);
  }
  // 120 -> 50: frame 5 is source frame 12 exactly; frame 1 (u = 2.4) lies between 2 and 3.
  const Motion h = pleat::resample_motion(m, 50.0);
  EXPECT_EQ(h.frame_count, 51);
  EXPECT_LT((pleat::joint_positions(h, 5) - pleat::joint_positions(m, 12)).cwiseAbs().maxCoeff(), 1e-12);
  for (int32_t j = 0; j < n; ++j)
    EXPECT_LT(angle(h.frame(1)[j], m.frame(2)[j].slerp(0.4, m.frame(3)[j])), 1e-9);
  EXPECT_LT((h.root_translation.row(1) - (0.6 * m.root_translation.row(2) + 0.4 * m.root_translation.row(3)))
                .norm(),
            1e-12);
  // Up and back down again.
  const Motion back = pleat::resample_motion(pleat::resample_motion(m, 240.0), 120.0);
  ASSERT_EQ(back.frame_count, m.frame_count);
  for (size_t k = 0; k < m.rotations.size(); ++k) ASSERT_LT(angle(back.rotations[k], m.rotations[k]), 1e-9);
  // Frame count = floor(duration * rate) + 1 (566 frames at 120 fps -> 142 at 30).
  Motion long_clip = pleat::cut_motion(m, 0, 1);
  long_clip.frame_count = 566;
  long_clip.rotations.assign(566 * static_cast<size_t>(n), Eigen::Quaterniond::Identity());
  long_clip.root_translation = Points3d::Zero(566, 3);
  EXPECT_EQ(pleat::resample_motion(long_clip, 30.0).frame_count, 142);
  expect_error([&] { pleat::resample_motion(m, 0.0); }, PLEAT_ERROR_INVALID_ARGUMENT, "target frame rate");
}

TEST(Resample, CutMotion) {
  const Motion m = walk_fixture();
  const Motion c = pleat::cut_motion(m, 10, 20);
  EXPECT_EQ(c.frame_count, 20);
  EXPECT_EQ(c.frame(0)[5].coeffs(), m.frame(10)[5].coeffs());
  EXPECT_EQ(c.root_translation.row(19), m.root_translation.row(29));
  expect_error([&] { pleat::cut_motion(m, 110, 20); }, PLEAT_ERROR_INVALID_ARGUMENT, "outside [0, 121)");
}

TEST(Resample, HoldRepeatsTheLastFrame) {
  const Motion m = pleat::cut_motion(walk_fixture(), 10, 5);
  const Motion h = pleat::hold_motion(m, 3);
  ASSERT_EQ(h.frame_count, 8);
  pleat::validate_motion(h, "held");
  EXPECT_EQ(h.frame(2)[5].coeffs(), m.frame(2)[5].coeffs());
  for (int64_t f = 4; f < 8; ++f) {
    for (int32_t j = 0; j < m.skeleton.joint_count(); ++j)
      ASSERT_EQ(h.frame(f)[j].coeffs(), m.frame(4)[j].coeffs()) << f << " " << j;
    EXPECT_EQ(h.root_translation.row(f), m.root_translation.row(4));
  }
  // A single-frame pose file (24 fps header) resampled to 30 fps and held
  // becomes a static clip.
  const Motion pose =
      pleat::resample_motion(pleat::read_bvh(motions_dir() + "/makehuman_poses/standing01.bvh").motion, 30.0);
  EXPECT_EQ(pleat::hold_motion(pose, 59).frame_count, 60);
  EXPECT_EQ(pleat::hold_motion(m, 0).frame_count, 5);
  expect_error([&] { pleat::hold_motion(m, -1); }, PLEAT_ERROR_INVALID_ARGUMENT, "-1 frames");
}

TEST(Retarget, OntoItselfIsIdentity) {
  const Motion m = walk_fixture();
  pleat::RetargetReport report;
  const Motion r = pleat::retarget_motion(m, m.skeleton, {}, &report);
  EXPECT_DOUBLE_EQ(report.root_scale, 1.0);
  EXPECT_TRUE(report.unmapped_targets.empty());
  for (size_t k = 0; k < m.rotations.size(); ++k) ASSERT_LT(angle(r.rotations[k], m.rotations[k]), 1e-9) << k;
  EXPECT_LT((r.root_translation - m.root_translation).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Retarget, WalkOntoSmallerAPosedSkeletonKeepsFeet) {
  const Motion m = walk_fixture();
  pleat::Skeleton target = m.skeleton;
  target.rest_translation *= 0.9;
  // Arms hanging 45 degrees down in the rest pose (an A pose), and longer forearms.
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  target.rest_rotation[target.find("LeftArm")] = Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 4, z));
  target.rest_rotation[target.find("RightArm")] = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, z));
  target.rest_translation.row(target.find("LeftHand")) *= 1.2;
  target.rest_translation.row(target.find("RightHand")) *= 1.2;
  const Points3d rest = pleat::joint_positions(pleat::cut_motion(m, 0, 1), 0);  // sanity of the A pose
  pleat::Motion rest_target = pleat::cut_motion(m, 0, 1);
  rest_target.skeleton = target;
  rest_target.rotations.assign(rest_target.rotations.size(), Eigen::Quaterniond::Identity());
  const Points3d a_pose = pleat::joint_positions(rest_target, 0);
  const int32_t la = target.find("LeftArm"), lf = target.find("LeftForeArm");
  EXPECT_LT(a_pose(lf, 1) - a_pose(la, 1), -0.1);  // the elbow hangs below the shoulder
  (void)rest;

  pleat::RetargetReport report;
  const Motion r = pleat::retarget_motion(m, target, {}, &report);
  EXPECT_NEAR(report.root_scale, 0.9, 1e-12);
  for (const char* foot : {"LeftFoot", "RightFoot", "LeftToeBase", "RightToeBase"})
    EXPECT_LT(max_joint_distance(m, r, foot, foot, 0.9), 0.02) << foot;  // a few cm; in fact ~1e-15
  for (const char* side : {"Left", "Right"}) {
    const std::string s = side;
    EXPECT_LT(max_bone_angle(m, r, s + "Arm", s + "ForeArm", s + "Arm", s + "ForeArm"), 1e-4) << side;
    EXPECT_LT(max_bone_angle(m, r, s + "ForeArm", s + "Hand", s + "ForeArm", s + "Hand"), 1e-4) << side;
    EXPECT_LT(max_bone_angle(m, r, s + "UpLeg", s + "Leg", s + "UpLeg", s + "Leg"), 1e-4) << side;
  }
  EXPECT_LT(max_bone_angle(m, r, "Spine1", "Head", "Spine1", "Head"), 1e-4);
}

TEST(Retarget, WalkOntoTheMakeHumanBodyFollowsTheSourceFeet) {
  // The product path: a CMU walk onto the open body model's A-posed cmu_mb
  // skeleton (other proportions than subject 12). After scaling by the leg
  // ratio the ankles follow the source's trajectories to a few centimetres.
  const Motion m = walk_fixture();
  const auto model = pleat::MakeHumanModel::load(pleat_test::asset_dir() + "/body");
  const pleat::Body body = model->body(pleat::makehuman_default_beta());
  pleat::RetargetReport report;
  const Motion r = pleat::retarget_motion(m, body.skeleton, {}, &report);
  EXPECT_GT(report.root_scale, 0.5);
  EXPECT_LT(report.root_scale, 1.5);
  for (const char* foot : {"LeftFoot", "RightFoot"}) {
    const FootError e = foot_error(m, r, foot, foot, report.root_scale);
    std::printf("%s: max %.4f m, vertical %.4f m, from mean %.4f m (root scale %.3f)\n", foot, e.max,
                e.max_vertical, e.max_from_mean, report.root_scale);
    EXPECT_LT(e.max_from_mean, 0.05) << foot << ": trajectory shape";
    EXPECT_LT(e.max_vertical, 0.05) << foot << ": height over the ground";
  }
}

TEST(Retarget, UnmappedTargetJointStaysAtRest) {
  const Motion m = walk_fixture();
  pleat::Skeleton target = m.skeleton;
  target.names.push_back("Prop");
  target.parents.push_back(target.find("LeftHand"));
  target.rest_translation.conservativeResize(target.joint_count(), 3);
  target.rest_translation.row(target.joint_count() - 1) << 0.05, 0, 0;
  target.rest_rotation.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())));
  pleat::RetargetReport report;
  const Motion r = pleat::retarget_motion(m, target, {}, &report);
  ASSERT_EQ(report.unmapped_targets, std::vector<std::string>{"Prop"});
  for (int64_t f = 0; f < r.frame_count; ++f)
    ASSERT_EQ(r.frame(f)[target.joint_count() - 1].coeffs(), Eigen::Quaterniond::Identity().coeffs());
}

TEST(Retarget, MappingFilesParseAndNameRigJoints) {
  const std::set<std::string> rig(std::begin(kCmuMbRig), std::end(kCmuMbRig));
  int files = 0;
  for (const auto& entry : fs::directory_iterator(pleat_test::source_dir() + "/data/retarget")) {
    if (entry.path().extension() != ".txt") continue;
    ++files;
    const pleat::JointMap map = pleat::read_joint_map(entry.path().string());
    EXPECT_GE(map.entries.size(), 2u) << entry.path();
    for (const auto& e : map.entries)
      EXPECT_TRUE(rig.count(e.target)) << entry.path() << ":" << e.line << " " << e.target;
  }
  EXPECT_EQ(files, 7);
}

TEST(Retarget, DazWalkByMappingFile) {
  const std::string path = motions_dir() + "/cmu_daz/02_02.bvh";
  if (!fs::exists(path)) FAIL() << path << " not present";
  const Motion daz = pleat::read_bvh(path).motion;
  const pleat::JointMap map = pleat::read_joint_map(map_path("cmu_daz.txt"));
  pleat::RetargetOptions options;
  options.map = &map;
  pleat::RetargetReport report;
  const Motion r = pleat::retarget_motion(daz, cmu_mb_target(), options, &report);
  pleat::validate_motion(r, "retargeted");
  EXPECT_EQ(r.frame_count, daz.frame_count);
  EXPECT_EQ(report.unmapped_targets.size(), 31u - 23u);
  EXPECT_GT(report.root_scale, 0.8);
  EXPECT_LT(report.root_scale, 1.2);
  const std::pair<const char*, const char*> bones[][2] = {
      {{"lThigh", "lShin"}, {"LeftUpLeg", "LeftLeg"}},
      {{"lShin", "lFoot"}, {"LeftLeg", "LeftFoot"}},
      {{"rThigh", "rShin"}, {"RightUpLeg", "RightLeg"}},
      {{"rShin", "rFoot"}, {"RightLeg", "RightFoot"}},
      {{"lShldr", "lForeArm"}, {"LeftArm", "LeftForeArm"}},
      {{"lForeArm", "lHand"}, {"LeftForeArm", "LeftHand"}},
      {{"rShldr", "rForeArm"}, {"RightArm", "RightForeArm"}},
      {{"neck", "head"}, {"Neck", "Head"}}};
  for (const auto& b : bones)
    EXPECT_LT(max_bone_angle(daz, r, b[0].first, b[0].second, b[1].first, b[1].second), 0.5) << b[1].first;
  // Feet follow the scaled source feet. The two skeletons differ in
  // proportions and in where the root sits relative to the hip joints (cmu_mb's
  // Hips are ~6 cm behind them, Daz's hip ~1 cm in front), so the ankles keep a
  // constant offset of ~7 cm forward; heights and trajectory shapes agree to a
  // few cm (measured: 2.7 cm vertical, 6.5 cm around the mean offset).
  for (const auto& [s, t] :
       {std::pair<const char*, const char*>{"lFoot", "LeftFoot"}, {"rFoot", "RightFoot"}}) {
    const FootError e = foot_error(daz, r, s, t, report.root_scale);
    EXPECT_LT(e.max_vertical, 0.04) << t;
    EXPECT_LT(e.max_from_mean, 0.08) << t;
    RecordProperty(std::string("foot_vertical_") + t, std::to_string(e.max_vertical));
  }
}

// The single-frame poses of makehuman-assets (MakeHuman's default rig, 163
// joints; the T pose 173) onto the body's cmu_mb skeleton. Both rigs sit on
// the same base mesh; the default rig cuts the thigh, upper arm, lower spine
// and neck into segments the poses bend, which one cmu_mb bone can only
// follow in part, so each bone is held to its measured worst angle against
// the chord of its source chain (makehuman_default.txt); a wrong pairing
// (left for right, a segment further down) is off by far more.
TEST(Retarget, MakeHumanPosesByMappingFile) {
  const auto model = pleat::MakeHumanModel::load(pleat_test::asset_dir() + "/body");
  const pleat::Body body = model->body(pleat::makehuman_default_beta());
  const pleat::JointMap map = pleat::read_joint_map(map_path("makehuman_default.txt"));
  pleat::RetargetOptions options;
  options.map = &map;
  struct Bone {
    const char *source_from, *source_to, *target_from, *target_to;
    double max_degrees;  // measured 4.9, 0.8, 8.3, 2.6, 10.6, 17.1
  };
  const Bone bones[] = {{"upperleg01.L", "lowerleg01.L", "LeftUpLeg", "LeftLeg", 5.5},
                        {"upperleg01.R", "lowerleg01.R", "RightUpLeg", "RightLeg", 5.5},
                        {"lowerleg01.L", "foot.L", "LeftLeg", "LeftFoot", 1.0},
                        {"lowerleg01.R", "foot.R", "RightLeg", "RightFoot", 1.0},
                        {"upperarm01.L", "lowerarm01.L", "LeftArm", "LeftForeArm", 9.0},
                        {"upperarm01.R", "lowerarm01.R", "RightArm", "RightForeArm", 9.0},
                        {"lowerarm01.L", "wrist.L", "LeftForeArm", "LeftHand", 3.0},
                        {"lowerarm01.R", "wrist.R", "RightForeArm", "RightHand", 3.0},
                        {"spine04", "spine02", "LowerBack", "Spine", 11.0},
                        {"neck01", "head", "Neck", "Head", 18.0}};
  int poses = 0;
  for (const auto& entry : fs::directory_iterator(motions_dir() + "/makehuman_poses")) {
    if (entry.path().extension() != ".bvh") continue;
    ++poses;
    const Motion pose = pleat::read_bvh(entry.path().string()).motion;
    pleat::RetargetReport report;
    const Motion r = pleat::retarget_motion(pose, body.skeleton, options, &report);
    pleat::validate_motion(r, entry.path().string());
    EXPECT_EQ(report.unmapped_targets.size(), 31u - 24u) << entry.path() << ": Neck1 and the fingers";
    for (const Bone& b : bones)
      EXPECT_LT(max_bone_angle(pose, r, b.source_from, b.source_to, b.target_from, b.target_to),
                b.max_degrees)
          << entry.path() << " " << b.target_from;
  }
  EXPECT_EQ(poses, 16);
}

TEST(Retarget, ThreeDsMaxAndSimplifiedFamilies) {
  const std::string max_path = motions_dir() + "/cmu_3dsmax/131_01.bvh";
  const std::string other_path = motions_dir() + "/cmu_other/10_01.bvh";
  if (!fs::exists(max_path) || !fs::exists(other_path)) FAIL() << "shared motions not present";
  const pleat::Skeleton target = cmu_mb_target();
  {
    // 3dsMax rest pose has the arms down; cmu_mb's are in a T pose.
    const Motion src = pleat::cut_motion(pleat::read_bvh(max_path).motion, 0, 240);
    const pleat::JointMap map = pleat::read_joint_map(map_path("cmu_3dsmax.txt"));
    pleat::RetargetOptions options;
    options.map = &map;
    pleat::RetargetReport report;
    const Motion r = pleat::retarget_motion(src, target, options, &report);
    EXPECT_TRUE(report.unmapped_targets.empty());
    EXPECT_LT(max_bone_angle(src, r, "LeftShoulder", "LeftElbow", "LeftArm", "LeftForeArm"), 0.5);
    EXPECT_LT(max_bone_angle(src, r, "RightElbow", "RightWrist", "RightForeArm", "RightHand"), 0.5);
    EXPECT_LT(max_bone_angle(src, r, "LeftKnee", "LeftAnkle", "LeftLeg", "LeftFoot"), 0.5);
    // Different subjects: the ankle stays above the ground and within ~7 cm of
    // the scaled source's height (measured 7.1 cm at worst, 3.3 cm on average).
    const FootError e = foot_error(src, r, "LeftAnkle", "LeftFoot", report.root_scale);
    EXPECT_GT(e.target_min_y, 0.0);
    EXPECT_LT(e.max_vertical, 0.09);
  }
  {
    const Motion src = pleat::read_bvh(other_path).motion;
    const pleat::JointMap map = pleat::read_joint_map(map_path("cmu_other.txt"));
    pleat::RetargetOptions options;
    options.map = &map;
    const Motion r = pleat::retarget_motion(src, target, options);
    EXPECT_LT(max_bone_angle(src, r, "LeftShoulder", "LeftElbow", "LeftArm", "LeftForeArm"), 0.5);
    EXPECT_LT(max_bone_angle(src, r, "RightHip", "RightKnee", "RightUpLeg", "RightLeg"), 0.5);
  }
}

TEST(Retarget, BadInputs) {
  const Motion m = walk_fixture();
  const auto I = PLEAT_ERROR_INVALID_ARGUMENT;
  // Unknown names in a mapping file, naming the line.
  const pleat::JointMap unknown_target =
      pleat::parse_joint_map("Hips Hips\n# c\nLeftUpLeg NoSuchJoint\n", "m.txt");
  pleat::RetargetOptions options;
  options.map = &unknown_target;
  expect_error([&] { pleat::retarget_motion(m, m.skeleton, options); }, I,
               "m.txt:3: target joint 'NoSuchJoint' is not in the target skeleton");
  const pleat::JointMap unknown_source = pleat::parse_joint_map("Hips Hips\nnope|nada LeftUpLeg\n", "m.txt");
  options.map = &unknown_source;
  expect_error([&] { pleat::retarget_motion(m, m.skeleton, options); }, I,
               "m.txt:2: source joint 'nope' or 'nada' is not in the source skeleton");
  options.missing_source = pleat::MissingJoint::kSkip;
  pleat::RetargetReport report;
  pleat::retarget_motion(m, m.skeleton, options, &report);
  EXPECT_EQ(report.skipped_lines.size(), 1u);
  // Malformed mapping files.
  expect_error([] { pleat::parse_joint_map("a b\nc d e\n", "m.txt"); }, PLEAT_ERROR_FORMAT,
               "m.txt:2: expected");
  expect_error([] { pleat::parse_joint_map("a b\nc b\n", "m.txt"); }, PLEAT_ERROR_FORMAT,
               "m.txt:2: target joint 'b' already mapped on line 1");
  expect_error([] { pleat::parse_joint_map("a||x b\n", "m.txt"); }, PLEAT_ERROR_FORMAT,
               "m.txt:1: empty source name");
  expect_error([] { pleat::read_joint_map("/nonexistent/map.txt"); }, PLEAT_ERROR_IO, "/nonexistent/map.txt");
  // An unpaired target root.
  const pleat::JointMap no_root = pleat::parse_joint_map("LeftUpLeg LeftUpLeg\n", "m.txt");
  options = {};
  options.map = &no_root;
  options.match_equal_names = false;
  expect_error([&] { pleat::retarget_motion(m, m.skeleton, options); }, I,
               "target root 'Hips' has no source joint");
  // A NaN rotation in the motion.
  Motion bad = m;
  bad.rotations[3 * static_cast<size_t>(m.skeleton.joint_count()) + 2].x() = NAN;
  expect_error([&] { pleat::retarget_motion(bad, m.skeleton); }, I, "frame 3, joint 2 'LeftUpLeg'");
  expect_error([&] { pleat::resample_motion(bad, 30); }, I, "frame 3, joint 2 'LeftUpLeg'");
  expect_error([&] { pleat::mirror_motion(bad); }, I, "frame 3, joint 2 'LeftUpLeg'");
  // A cycle in the hierarchy.
  pleat::Skeleton cyclic = m.skeleton;
  cyclic.parents[2] = 3;
  expect_error([&] { pleat::validate_skeleton(cyclic, "cyclic"); }, I,
               "cyclic: joint 2 'LeftUpLeg' has parent 3");
  expect_error([&] { pleat::retarget_motion(m, cyclic); }, I, "parents must come first");
}

TEST(Mirror, JointNames) {
  EXPECT_EQ(pleat::mirror_joint_name("LeftUpLeg"), "RightUpLeg");
  EXPECT_EQ(pleat::mirror_joint_name("RightHandIndex1"), "LeftHandIndex1");
  EXPECT_EQ(pleat::mirror_joint_name("LHipJoint"), "RHipJoint");
  EXPECT_EQ(pleat::mirror_joint_name("RThumb"), "LThumb");
  EXPECT_EQ(pleat::mirror_joint_name("lShldr"), "rShldr");
  EXPECT_EQ(pleat::mirror_joint_name("leftEye"), "rightEye");
  EXPECT_EQ(pleat::mirror_joint_name("upperarm01.L"), "upperarm01.R");
  EXPECT_EQ(pleat::mirror_joint_name("thigh_r"), "thigh_l");
  EXPECT_EQ(pleat::mirror_joint_name("mixamorig:LeftArm"), "mixamorig:RightArm");
  EXPECT_EQ(pleat::mirror_joint_name("LowerBack"), "LowerBack");
  EXPECT_EQ(pleat::mirror_joint_name("Hips"), "Hips");
  EXPECT_EQ(pleat::mirror_joint_name("hip"), "hip");
}

TEST(Mirror, ReflectsASymmetricSkeleton) {
  Motion m = walk_fixture();
  // Make the rest skeleton exactly symmetric: right offsets = mirrored left offsets.
  pleat::Skeleton& s = m.skeleton;
  for (int32_t j = 0; j < s.joint_count(); ++j) {
    const int32_t p = s.find(pleat::mirror_joint_name(s.names[j]));
    if (p > j) {
      s.rest_translation.row(p) = s.rest_translation.row(j);
      s.rest_translation(p, 0) = -s.rest_translation(j, 0);
    } else if (p == j) {
      s.rest_translation(j, 0) = 0;
    }
  }
  const Motion mirrored = pleat::mirror_motion(m);
  for (int64_t f = 0; f < m.frame_count; f += 10) {
    const Points3d a = pleat::joint_positions(m, f), b = pleat::joint_positions(mirrored, f);
    for (int32_t j = 0; j < s.joint_count(); ++j) {
      const int32_t p = s.find(pleat::mirror_joint_name(s.names[j]));
      const Eigen::RowVector3d reflected(-a(p, 0), a(p, 1), a(p, 2));
      ASSERT_LT((b.row(j) - reflected).norm(), 1e-12) << s.names[j] << " frame " << f;
    }
  }
  const Motion twice = pleat::mirror_motion(mirrored);
  for (size_t k = 0; k < m.rotations.size(); ++k)
    ASSERT_EQ(twice.rotations[k].coeffs(), m.rotations[k].coeffs());
  EXPECT_EQ(twice.root_translation, m.root_translation);
}

// A straight walk at 1 m/s turned at 90 deg/s walks a regular 120-gon
// (steps of 1/30 m) and is back where it started after 4 s; the root's global
// orientation turns with it, through a rest orientation that is not the
// identity, and the other joints keep their rotations.
TEST(Turn, AStraightWalkBecomesACircle) {
  Motion walk;
  walk.skeleton.names = {"root", "leg"};
  walk.skeleton.parents = {-1, 0};
  walk.skeleton.rest_translation = Points3d(2, 3);
  walk.skeleton.rest_translation << 0, 1, 0, 0, -0.5, 0;
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 0, 1).normalized()));
  walk.skeleton.rest_rotation = {tilt, Eigen::Quaterniond::Identity()};
  walk.frame_rate = 30;
  walk.frame_count = 121;
  const Eigen::Quaterniond sway(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  walk.root_translation = Points3d(121, 3);
  for (int64_t f = 0; f < 121; ++f) {
    walk.rotations.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * f, Eigen::Vector3d::UnitZ())));
    walk.rotations.push_back(sway);
    walk.root_translation.row(f) << 0.5, 1.0, f / 30.0;
  }
  const Motion turned = pleat::turn_motion(walk, 90.0, 0, 0);
  const Eigen::RowVector3d start = walk.root_translation.row(0);
  EXPECT_LT((turned.root_translation.row(120) - start).norm(), 1e-12);
  // Half way (180 degrees) the walker is a diameter away: |sum of 60 unit
  // steps at angles k pi / 60| = 1 / sin(pi / 120).
  EXPECT_NEAR((turned.root_translation.row(60) - start).norm(), 1.0 / 30.0 / std::sin(M_PI / 120.0), 1e-12);
  for (int64_t f : {int64_t{0}, int64_t{1}, int64_t{45}, int64_t{120}}) {
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(f * M_PI / 60.0, Eigen::Vector3d::UnitY()));
    const Eigen::Quaterniond before = tilt * walk.frame(f)[0], after = tilt * turned.frame(f)[0];
    EXPECT_LT(after.angularDistance(turn * before), 1e-12) << f;
    EXPECT_EQ(turned.frame(f)[1].coeffs(), sway.coeffs()) << f;
    EXPECT_DOUBLE_EQ(turned.root_translation(f, 1), 1.0) << f;
  }
}

// The turn eases in: nothing before ease_from, then smoothstep of the rate.
TEST(Turn, EasesInAndRefusesABadRate) {
  Motion still = walk_fixture();
  still = pleat::cut_motion(still, 0, 10);
  const Motion turned = pleat::turn_motion(still, 120.0, 2, 4);
  const double step = 120.0 * M_PI / 180.0 / still.frame_rate;
  const double expected[] = {
      0, 0, 0, step * 0.15625, step * (0.15625 + 0.5), step * (0.15625 + 0.5 + 0.84375), step * 2.5};
  for (int64_t f = 0; f < 7; ++f) {
    const Eigen::Quaterniond a = still.skeleton.rest_rotation[0] * still.frame(f)[0];
    const Eigen::Quaterniond b = still.skeleton.rest_rotation[0] * turned.frame(f)[0];
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(expected[f], Eigen::Vector3d::UnitY()));
    EXPECT_LT(b.angularDistance(turn * a), 1e-9) << f;
  }
  expect_error([&] { pleat::turn_motion(still, std::nan(""), 0, 0); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "turn_motion: rate");
  expect_error([&] { pleat::turn_motion(still, 90, 0, -1); }, PLEAT_ERROR_INVALID_ARGUMENT, "over -1 frames");
}
