// The MakeHuman open body model (src/body/makehuman.*) on the shared data
// pack (shared/data/body). The expected default and tall bodies are composed
// here from base.obj and the target files by an independent, simple reader.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "body/body.h"
#include "body/makehuman.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;

namespace {

// The asset pack must be there: a missing pack fails the test, never skips it.
#define REQUIRE_BODY_DATA() const std::string dir = pleat_test::asset_dir() + "/body"

// --- independent reference: plain line scans, no pleat code -------------------

std::vector<Eigen::Vector3d> read_obj_vertices(const std::string& path) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3d> v;
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("v ", 0) == 0) {
      std::istringstream ss(line.substr(2));
      Eigen::Vector3d p;
      ss >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    }
  return v;
}

std::string stored_name(const std::string& dir, const std::string& original) {
  std::ifstream in(dir + "/targets/macrodetails/MANIFEST.tsv");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string a, b;
    std::getline(ss, a, '\t');
    std::getline(ss, b, '\t');
    if (a == original) return b;
  }
  ADD_FAILURE() << original << " not in MANIFEST.tsv";
  return "";
}

void add_target(const std::string& dir, const std::string& original, double weight,
                std::vector<Eigen::Vector3d>* v) {
  const std::string path = dir + "/targets/macrodetails/" + stored_name(dir, original);
  gzFile f = gzopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr) << path;
  std::string text;
  char buf[65536];
  int n;
  while ((n = gzread(f, buf, sizeof(buf))) > 0) text.append(buf, static_cast<size_t>(n));
  gzclose(f);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    int i;
    double dx, dy, dz;
    ss >> i >> dx >> dy >> dz;
    (*v)[static_cast<size_t>(i)] += weight * Eigen::Vector3d(dx, dy, dz);
  }
}

// Default sliders: gender 0.5 (male = female = 0.5), age 0.5 (young = 1),
// ethnic 1/3 each, muscle and weight 0.5 (average = 1), height and
// proportions 0.5 (no height/proportion target). With tall = true the height
// slider is 1: maxheight = 1.
std::vector<Eigen::Vector3d> reference_body(const std::string& dir, bool tall) {
  auto v = read_obj_vertices(dir + "/base.obj");
  for (const char* g : {"male", "female"}) {
    for (const char* e : {"african", "asian", "caucasian"})
      add_target(dir, std::string(e) + "-" + g + "-young.target", 0.5 / 3.0, &v);
    add_target(dir, std::string("universal-") + g + "-young-averagemuscle-averageweight.target", 0.5, &v);
    if (tall)
      add_target(dir, std::string("height/") + g + "-young-averagemuscle-averageweight-maxheight.target", 0.5,
                 &v);
  }
  v.resize(13380);
  for (auto& p : v) p *= 0.1;  // decimetres -> metres
  return v;
}

double y_extent(const Points3d& x) {
  return x.col(1).maxCoeff() - x.col(1).minCoeff();
}

Eigen::VectorXd beta_with(int index, double value) {
  Eigen::VectorXd b = makehuman_default_beta();
  b[index] = value;
  return b;
}

bool inside_box(const Eigen::RowVector3d& p, const Points3d& x) {
  return (p.array() >= x.colwise().minCoeff().array()).all() &&
         (p.array() <= x.colwise().maxCoeff().array()).all();
}

}  // namespace

TEST(MakeHuman, DefaultAndTallBodiesMatchAnIndependentComposition) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  for (bool tall : {false, true}) {
    const Body body = model->body(tall ? beta_with(4, 1.0) : makehuman_default_beta());
    const auto ref = reference_body(dir, tall);
    ASSERT_EQ(body.vertex_count(), 13380);
    double worst = 0.0;
    for (int i = 0; i < 13380; ++i)
      worst = std::max(worst, (body.rest.vertices.row(i).transpose() - ref[static_cast<size_t>(i)]).norm());
    EXPECT_LT(worst, 1e-6) << (tall ? "tall" : "default");
    if (!tall) {
      const double h = y_extent(body.rest.vertices);
      EXPECT_GT(h, 1.65) << "default height " << h;  // 1.659 m: the targets shorten the raw 1.666 m mesh
      EXPECT_LT(h, 1.75);
    }
  }
  // The default body is not the raw base mesh.
  const auto raw = read_obj_vertices(dir + "/base.obj");
  const Body body = model->body(makehuman_default_beta());
  double moved = 0.0;
  for (int i = 0; i < 13380; ++i)
    moved =
        std::max(moved, (body.rest.vertices.row(i).transpose() - 0.1 * raw[static_cast<size_t>(i)]).norm());
  EXPECT_GT(moved, 1e-3);
}

TEST(MakeHuman, HeightSliderAndJointsFollow) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  const Body mid = model->body(makehuman_default_beta());
  const Body tall = model->body(beta_with(4, 1.0));
  const Body shorter = model->body(beta_with(4, 0.0));
  EXPECT_GT(y_extent(tall.rest.vertices), y_extent(mid.rest.vertices) + 0.03);
  EXPECT_LT(y_extent(shorter.rest.vertices), y_extent(mid.rest.vertices) - 0.03);

  const int32_t head = mid.skeleton.find("Head");
  ASSERT_GE(head, 0);
  const Points3d jm = rest_joint_positions(mid.skeleton);
  const Points3d jt = rest_joint_positions(tall.skeleton);
  const Points3d js = rest_joint_positions(shorter.skeleton);
  EXPECT_GT(jt(head, 1), jm(head, 1) + 0.02);
  EXPECT_LT(js(head, 1), jm(head, 1) - 0.02);
  for (const Body* b : {&mid, &tall, &shorter}) {
    const Points3d j = rest_joint_positions(b->skeleton);
    for (int32_t k = 0; k < b->joint_count(); ++k)
      EXPECT_TRUE(inside_box(j.row(k), b->rest.vertices)) << b->skeleton.names[k];
  }
  // rest_joint_positions agrees with the model's joint regression.
  const Points3d direct = model->joint_positions(model->shaped_vertices(beta_with(4, 1.0)));
  EXPECT_LT((direct - jt).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(tall.beta()[4], 1.0);
  EXPECT_EQ(tall.beta_names()[4], "height");
}

TEST(MakeHuman, GenderChangesChestAndHips) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  const Body female = model->body(beta_with(0, 0.0));
  const Body male = model->body(beta_with(0, 1.0));
  // Chest: the front-most point of the torso at breast height (female ahead);
  // hips: torso half-width at hip height relative to the shoulder joints'
  // distance (female larger).
  auto band = [](const Body& b, double lo, double hi, double* front, double* width) {
    const double y0 = b.rest.vertices.col(1).minCoeff(), h = y_extent(b.rest.vertices);
    *front = -1e9;
    *width = 0.0;
    for (int i = 0; i < b.vertex_count(); ++i) {
      const double t = (b.rest.vertices(i, 1) - y0) / h;
      const double x = b.rest.vertices(i, 0);
      if (t < lo || t > hi || std::abs(x) > 0.2) continue;  // torso only (arms are further out)
      *front = std::max(*front, b.rest.vertices(i, 2));
      *width = std::max(*width, std::abs(x));
    }
  };
  double ff, fw, mf, mw, fhf, fhw, mhf, mhw;  // front z and half-width per band
  band(female, 0.70, 0.74, &ff, &fw);
  band(male, 0.70, 0.74, &mf, &mw);
  band(female, 0.48, 0.54, &fhf, &fhw);
  band(male, 0.48, 0.54, &mhf, &mhw);
  auto shoulders = [](const Body& b) {
    const Points3d j = rest_joint_positions(b.skeleton);
    return (j.row(b.skeleton.find("LeftArm")) - j.row(b.skeleton.find("RightArm"))).norm();
  };
  // Measured: chest front 0.158 vs 0.146 m; hip width / shoulder joint
  // distance 0.59 (female) vs 0.48 (male).
  EXPECT_GT(ff - mf, 0.008) << "female chest front " << ff << " male " << mf;
  EXPECT_GT(fhw / shoulders(female), mhw / shoulders(male) + 0.05)
      << "hip width / shoulder width: female " << fhw / shoulders(female) << " male "
      << mhw / shoulders(male);
  EXPECT_GT(shoulders(male), shoulders(female) + 0.03);
}

TEST(MakeHuman, WeightsSumToOneAndBodyValidates) {
  REQUIRE_BODY_DATA();
  for (MakeHumanRig rig : {MakeHumanRig::cmu_mb, MakeHumanRig::default_rig}) {
    const auto model = MakeHumanModel::load(dir, rig);
    EXPECT_TRUE(model->unweighted_vertices().empty());
    const SkinWeights& w = model->all_weights();
    ASSERT_EQ(w.vertex_count(), kMakeHumanVertexCount);
    for (int32_t v = 0; v < w.vertex_count(); ++v) {
      double s = 0.0;
      for (int32_t k = w.offsets[v]; k < w.offsets[v + 1]; ++k) s += w.weights[k];
      ASSERT_NEAR(s, 1.0, 1e-9) << "vertex " << v;
    }
    const Body body = model->body(makehuman_default_beta());
    EXPECT_NO_THROW(validate_body(body, body.source));
    EXPECT_EQ(body.joint_count(), rig == MakeHumanRig::cmu_mb ? 31 : 163);
    EXPECT_EQ(body.rest.triangle_count(), 2 * 13378);
  }
}

TEST(MakeHuman, CmuRigMatchesTheCmuBvhSkeleton) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  const Skeleton& s = model->skeleton();
  // Joint names and parents from a BVH header (a tiny line scan).
  const std::string bvh = dir + "/../motions/cmu_mb/12_03.bvh";
  if (!std::filesystem::exists(bvh)) FAIL() << bvh << " not present";
  std::ifstream in(bvh);
  std::string line;
  std::vector<std::string> stack;
  std::map<std::string, std::string> parent_of;
  std::string pending;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string word, name;
    ss >> word;
    if (word == "ROOT" || word == "JOINT") {
      ss >> name;
      pending = name;
      parent_of[name] = stack.empty() ? "" : stack.back();
    } else if (word == "End") {
      pending = "End";
    } else if (word == "{") {
      stack.push_back(pending);
    } else if (word == "}") {
      stack.pop_back();
    } else if (word == "MOTION") {
      break;
    }
  }
  // 12_03 names the finger bone LeftHandIndex1; the rig LeftHandFinger1 (MOTIONS.md).
  auto rig_name = [](std::string n) {
    if (n == "LeftHandIndex1" || n == "LFingers") return std::string("LeftHandFinger1");
    if (n == "RightHandIndex1" || n == "RFingers") return std::string("RightHandFinger1");
    return n;
  };
  ASSERT_EQ(parent_of.size(), 31u);
  ASSERT_EQ(s.joint_count(), 31);
  for (const auto& [name, parent] : parent_of) {
    const int32_t j = s.find(rig_name(name));
    ASSERT_GE(j, 0) << name;
    if (parent.empty())
      EXPECT_EQ(s.parents[j], -1);
    else
      EXPECT_EQ(s.names[s.parents[j]], rig_name(parent)) << name;
  }
  EXPECT_EQ(s.names[0], "Hips");
}

// MPFB2's cmu_mb rig file stores each bone head's position on the default
// MakeHuman body (Blender axes: Z up, metres). Our default-β joints must land
// there: this checks the default shape and the joint regression together.
TEST(MakeHuman, DefaultJointsMatchMpfb2RigPositions) {
  REQUIRE_BODY_DATA();
  std::ifstream in(dir + "/rigs/mpfb2_rig.cmu_mb.json");
  if (!in) FAIL() << "mpfb2_rig.cmu_mb.json not present";
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto model = MakeHumanModel::load(dir);
  const Body body = model->body(makehuman_default_beta());
  const Points3d joints = rest_joint_positions(body.skeleton);
  int checked = 0;
  for (int32_t j = 0; j < body.joint_count(); ++j) {
    // "<bone>": { "head": { ... "default_position": [x, y, z] (a plain scan).
    const size_t bone = text.find("\"" + body.skeleton.names[j] + "\": {");
    ASSERT_NE(bone, std::string::npos) << body.skeleton.names[j];
    const size_t head = text.find("\"head\"", bone);
    const size_t position = text.find("\"default_position\"", head);
    ASSERT_LT(position, text.find('}', head)) << body.skeleton.names[j];
    std::string numbers = text.substr(text.find('[', position) + 1);
    numbers = numbers.substr(0, numbers.find(']'));
    std::replace(numbers.begin(), numbers.end(), ',', ' ');
    std::istringstream ss(numbers);
    double bx, by, bz;
    ss >> bx >> by >> bz;
    const Eigen::RowVector3d expected(bx, bz, -by);  // Blender (x, y, z) -> Y up (x, z, -y)
    EXPECT_LT((joints.row(j) - expected).norm(), 1e-5)
        << body.skeleton.names[j] << ": " << joints.row(j) << " vs " << expected;
    ++checked;
  }
  EXPECT_EQ(checked, 31);
}

TEST(MakeHuman, PosingMovesOnlyTheChain) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  const Body body = model->body(makehuman_default_beta());
  Quaternions pose(static_cast<size_t>(body.joint_count()), Eigen::Quaterniond::Identity());
  const Eigen::Vector3d root = body.skeleton.rest_translation.row(0).transpose();
  const Points3d rest = pose_body(body, pose, root);
  EXPECT_LT((rest - body.rest.vertices).cwiseAbs().maxCoeff(), 1e-12);

  const int32_t forearm = body.skeleton.find("LeftForeArm");
  ASSERT_GE(forearm, 0);
  pose[static_cast<size_t>(forearm)] = Eigen::Quaterniond(Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitX()));
  const Points3d bent = pose_body(body, pose, root + Eigen::Vector3d(0, 0, 0.5));
  // Vertices with no forearm-chain weight only translate with the root.
  const SkinWeights& w = body.weights;
  std::vector<bool> chain(static_cast<size_t>(body.joint_count()), false);
  for (int32_t j = 0; j < body.joint_count(); ++j)
    for (int32_t k = j; k >= 0; k = body.skeleton.parents[k])
      if (k == forearm) chain[static_cast<size_t>(j)] = true;
  int moved = 0;
  for (int32_t v = 0; v < body.vertex_count(); ++v) {
    bool in_chain = false;
    for (int32_t k = w.offsets[v]; k < w.offsets[v + 1]; ++k)
      in_chain |= chain[static_cast<size_t>(w.joints[k])];
    const Eigen::RowVector3d d = bent.row(v) - body.rest.vertices.row(v) - Eigen::RowVector3d(0, 0, 0.5);
    if (!in_chain)
      ASSERT_LT(d.norm(), 1e-9) << "vertex " << v;
    else if (d.norm() > 0.01)
      ++moved;
  }
  EXPECT_GT(moved, 100);
}

TEST(MakeHuman, HelpersAreKeptAndShaped) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  const Points3d all = model->shaped_vertices(beta_with(4, 1.0));
  ASSERT_EQ(all.rows(), kMakeHumanVertexCount);
  const auto tights = model->group_vertices("helper-tights");
  ASSERT_EQ(tights.size(), 2674u);
  EXPECT_EQ(tights.front(), 15328);
  EXPECT_EQ(tights.back(), 18001);
  EXPECT_EQ(model->group_vertices("helper-skirt").size(), 720u);
  EXPECT_EQ(model->group_triangles("helper-tights").rows(), 2 * 2650);
  // The tights shell follows the height target like the body does.
  const Points3d mid = model->shaped_vertices(makehuman_default_beta());
  double top_tall = -1e9, top_mid = -1e9;
  for (int32_t v : tights) {
    top_tall = std::max(top_tall, all(v, 1));
    top_mid = std::max(top_mid, mid(v, 1));
  }
  EXPECT_GT(top_tall, top_mid + 0.02);

  // The body with helpers keeps base.obj numbering and poses the tights too.
  const Body full = model->body_with_helpers(makehuman_default_beta());
  ASSERT_EQ(full.vertex_count(), kMakeHumanVertexCount);
  EXPECT_NO_THROW(validate_body(full, full.source));
  EXPECT_LT((full.rest.vertices - mid).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(full.rest.triangle_count(), 2 * (18486 - 750));  // all quads but the joint cubes'
  Quaternions pose(static_cast<size_t>(full.joint_count()), Eigen::Quaterniond::Identity());
  pose[static_cast<size_t>(full.skeleton.find("LeftUpLeg"))] =
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.8, Eigen::Vector3d::UnitX()));
  const Points3d posed = pose_body(full, pose, full.skeleton.rest_translation.row(0).transpose());
  double moved = 0.0;
  for (int32_t v : tights) moved = std::max(moved, (posed.row(v) - full.rest.vertices.row(v)).norm());
  EXPECT_GT(moved, 0.2);  // the left leg of the tights swings forward with the thigh
}

TEST(MakeHuman, LoadIsCachedAndBlendingIsFast) {
  REQUIRE_BODY_DATA();
  const auto a = MakeHumanModel::load(dir);
  const auto t0 = std::chrono::steady_clock::now();
  const auto b = MakeHumanModel::load(dir);
  EXPECT_EQ(a.get(), b.get());
  Eigen::VectorXd beta = makehuman_default_beta();
  beta << 0.3, 0.6, 0.7, 0.4, 0.8, 0.9, 0.2, 0.5, 0.3;  // needs targets not yet read
  (void)a->body(beta);
  const auto t1 = std::chrono::steady_clock::now();
  beta[3] = 0.45;
  (void)a->body(beta);
  const auto t2 = std::chrono::steady_clock::now();
  const double first = std::chrono::duration<double>(t1 - t0).count();
  const double again = std::chrono::duration<double>(t2 - t1).count();
  EXPECT_LT(first, 2.0);
  EXPECT_LT(again, 0.25);
  std::cout << "first blend (reads targets) " << first << " s, cached blend " << again << " s\n";
  const auto weights = a->target_weights(beta);
  double ethnic = 0.0;
  for (const auto& [name, w] : weights)
    if (name.find('/') == std::string::npos && name.rfind("universal", 0) != 0) ethnic += w;
  EXPECT_NEAR(ethnic, 1.0, 1e-12);  // ethnic x gender x age weights sum to one
}

TEST(MakeHuman, BadInputsAreNamed) {
  REQUIRE_BODY_DATA();
  const auto model = MakeHumanModel::load(dir);
  pleat_test::expect_error([&] { model->body(Eigen::VectorXd::Constant(3, 0.5)); },
                           PLEAT_ERROR_INVALID_ARGUMENT, "9");
  pleat_test::expect_error([&] { model->body(beta_with(4, 1.5)); }, PLEAT_ERROR_INVALID_ARGUMENT, "height");
  pleat_test::expect_error([&] { model->body(beta_with(1, std::nan(""))); }, PLEAT_ERROR_INVALID_ARGUMENT,
                           "age");
  Eigen::VectorXd no_ethnic = makehuman_default_beta();
  no_ethnic.tail(3).setZero();
  pleat_test::expect_error([&] { model->body(no_ethnic); }, PLEAT_ERROR_INVALID_ARGUMENT, "ethnic");
  pleat_test::expect_error([&] { MakeHumanModel::load(dir + "/nowhere"); }, PLEAT_ERROR_IO, "nowhere");
  pleat_test::expect_error([&] { model->group_vertices("helper-cape"); }, PLEAT_ERROR_INVALID_ARGUMENT,
                           "helper-cape");

  // A damaged copy: a target file that is not gzip data, a truncated rig.
  const std::string bad = pleat_test::temp_dir("makehuman_bad");
  std::filesystem::copy(dir + "/base.obj", bad + "/base.obj");
  std::filesystem::create_directories(bad + "/rigs");
  std::filesystem::create_directories(bad + "/targets/macrodetails");
  {
    std::ofstream(bad + "/targets/macrodetails/MANIFEST.tsv")
        << "# header\nuniversal-male-young-averagemuscle-averageweight.target\tu.target.gz\n"
           "universal-female-young-averagemuscle-averageweight.target\tu.target.gz\n"
           "african-male-young.target\tbroken.target.gz\n";
    std::ofstream(bad + "/targets/macrodetails/u.target.gz") << "# plain text is read as is\n0 0.0 0.1 0.0\n";
    std::ofstream(bad + "/targets/macrodetails/broken.target.gz") << "0 0.0 zero 0.0\n";
    std::string rig((std::istreambuf_iterator<char>(std::ifstream(dir + "/rigs/cmu_mb.mhskel").rdbuf())), {});
    std::ofstream(bad + "/rigs/cmu_mb.mhskel") << rig.substr(0, rig.size() / 2);
    std::filesystem::copy(dir + "/rigs/mpfb2_weights.cmu_mb.json", bad + "/rigs/mpfb2_weights.cmu_mb.json");
  }
  pleat_test::expect_error([&] { MakeHumanModel::load(bad); }, PLEAT_ERROR_FORMAT, "cmu_mb.mhskel");
  std::filesystem::copy(dir + "/rigs/cmu_mb.mhskel", bad + "/rigs/cmu_mb.mhskel",
                        std::filesystem::copy_options::overwrite_existing);
  pleat_test::expect_error([&] { MakeHumanModel::load(bad); }, PLEAT_ERROR_FORMAT,
                           "broken.target.gz: line 1");
}
