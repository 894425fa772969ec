// .npz reading (src/io/npz.*) and SMPL-layout bodies (src/body/smpl_npz.*)
// against tests/body/make_synthetic_smpl.py: random synthetic models written
// by numpy (compressed and stored, mixed dtypes, Fortran order) with
// reference posed vertices from an independent numpy implementation.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "body/body.h"
#include "body/smpl_npz.h"
#include "io/npz.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;

namespace {

class SmplNpz : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const char* python = std::getenv("PLEAT_PYTHON");
    if (!python) return;
    dir_ = pleat_test::temp_dir("smpl_npz");
    std::string output;
    const std::string cmd = std::string(python) + " " + pleat_test::source_dir() +
                            "/tests/body/make_synthetic_smpl.py " + dir_ + " 2>&1";
    if (pleat_test::run_command(cmd, &output) != 0) {
      failure_ = "fixture script failed: " + output;
      dir_.clear();
    }
  }
  void SetUp() override {
    if (!failure_.empty()) FAIL() << failure_;
    if (dir_.empty()) FAIL() << "PLEAT_PYTHON not set (run through ctest)";
  }
  static std::string path(const std::string& name) { return dir_ + "/" + name; }
  static inline std::string dir_;
  static inline std::string failure_;
};

Eigen::MatrixXd matrix(const NpyArray& a) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return Eigen::Map<const RowMajor>(a.values.data(), a.shape[0], a.shape.size() > 1 ? a.shape[1] : 1);
}

}  // namespace

TEST_F(SmplNpz, NpyDtypesOrdersAndVersions) {
  const NpzArchive a = read_npz(path("dtypes.npz"));
  for (const char* dt : {"f4", "f8", "i4", "i8", "u4", "u8", "i2", "u2", "i1", "u1"}) {
    for (const char* order : {"c_", "f_"}) {
      const std::string name = std::string(order) + dt;
      ASSERT_TRUE(a.count(name)) << name;
      const NpyArray& x = a.at(name);
      ASSERT_EQ(x.shape, (std::vector<int64_t>{2, 3, 4})) << name;
      const double shift = (dt[0] == 'f' || dt[0] == 'i') ? 5.0 : 0.0;
      for (int k = 0; k < 24; ++k) ASSERT_EQ(x.values[static_cast<size_t>(k)], k - shift) << name << " " << k;
      EXPECT_EQ(x.integer, dt[0] != 'f') << name;
      if (x.integer) {
        EXPECT_EQ(x.integers[23], static_cast<int64_t>(23 - shift)) << name;
      }
    }
  }
  EXPECT_EQ(a.at("b1").values, (std::vector<double>{0, 1, 0, 1, 0, 1}));
  EXPECT_TRUE(a.at("scalar").shape.empty());
  EXPECT_EQ(a.at("scalar").values, std::vector<double>{2.5});
  EXPECT_EQ(a.at("empty").size(), 0);
  const NpyArray v2 = read_npy(path("v2.npy"));
  EXPECT_EQ(v2.values, a.at("c_f8").values);
  EXPECT_EQ(shape_string(v2.shape), "(2, 3, 4)");
  // Only the named entries are parsed.
  EXPECT_EQ(read_npz(path("dtypes.npz"), {"scalar", "nothing"}).size(), 1u);
}

TEST_F(SmplNpz, PosedVerticesMatchNumpyReference) {
  const NpzArchive ref = read_npz(path("reference.npz"));
  const Eigen::VectorXd beta = matrix(ref.at("beta"));
  const Eigen::MatrixXd pose = matrix(ref.at("pose"));
  const Eigen::Vector3d trans = matrix(ref.at("trans"));
  for (const char* variant : {"compressed", "plain"}) {
    const SmplModel m = load_smpl_npz(path(std::string("smpl_") + variant + ".npz"));
    EXPECT_EQ(m.vertex_count(), 60);
    EXPECT_EQ(m.joint_count(), 5);
    EXPECT_EQ(m.shape_count(), 4);
    EXPECT_EQ(m.parents, (std::vector<int32_t>{-1, 0, 1, 1, 3}));
    const Points3d shaped = smpl_shaped_vertices(m, beta);
    EXPECT_LT((shaped - matrix(ref.at(std::string("shaped_") + variant))).cwiseAbs().maxCoeff(), 1e-9)
        << variant;
    EXPECT_LT(
        (smpl_joints(m, shaped) - matrix(ref.at(std::string("joints_") + variant))).cwiseAbs().maxCoeff(),
        1e-9)
        << variant;
    const Points3d posed = smpl_posed_vertices(m, beta, pose, trans);
    const Eigen::MatrixXd expected = matrix(ref.at(std::string("posed_") + variant));
    EXPECT_LT((posed - expected).cwiseAbs().maxCoeff(), 1e-6) << variant;

    // The generic Body carries the same model: rest pose = v_shaped.
    const Body body = smpl_body(m, beta);
    EXPECT_NO_THROW(validate_body(body, variant));
    Quaternions identity(5, Eigen::Quaterniond::Identity());
    const Points3d rest = pose_body(body, identity, body.skeleton.rest_translation.row(0).transpose());
    EXPECT_LT((rest - shaped).cwiseAbs().maxCoeff(), 1e-6);  // float32 weights sum to 1 +- 1e-7
    EXPECT_EQ(body.shape.size(), 4u);
    EXPECT_EQ(body.beta()[3], 0.0);
  }
}

TEST_F(SmplNpz, BadModelsAreNamed) {
  using pleat_test::expect_error;
  expect_error([&] { load_smpl_npz(path("missing_weights.npz")); }, PLEAT_ERROR_FORMAT,
               "missing array 'weights'");
  expect_error([&] { load_smpl_npz(path("bad_shapedirs.npz")); }, PLEAT_ERROR_FORMAT,
               "'shapedirs' has shape (59, 3, 4)");
  expect_error([&] { load_smpl_npz(path("bad_posedirs.npz")); }, PLEAT_ERROR_FORMAT,
               "'posedirs' has shape (60, 3, 27)");
  expect_error([&] { load_smpl_npz(path("nan_template.npz")); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "'v_template' has a non-finite value at vertex 7");
  expect_error([&] { load_smpl_npz(path("weights_sum.npz")); }, PLEAT_ERROR_INVALID_ARGUMENT, "vertex 13");
  expect_error([&] { load_smpl_npz(path("kintree_cycle.npz")); }, PLEAT_ERROR_INVALID_ARGUMENT, "cycle");
  expect_error([&] { load_smpl_npz(path("face_range.npz")); }, PLEAT_ERROR_INVALID_ARGUMENT, "face 5");
  expect_error([&] { load_smpl_npz(path("bad_dtype.npz")); }, PLEAT_ERROR_FORMAT, "'<c8'");
  expect_error([&] { load_smpl_npz(path("absent.npz")); }, PLEAT_ERROR_IO, "absent.npz");

  const SmplModel m = load_smpl_npz(path("smpl_compressed.npz"));
  expect_error([&] { smpl_shaped_vertices(m, Eigen::VectorXd::Zero(7)); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "7 entries");
  expect_error(
      [&] {
        smpl_posed_vertices(m, Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Zero(4, 3),
                            Eigen::Vector3d::Zero());
      },
      PLEAT_ERROR_INVALID_ARGUMENT, "pose has 4 joints");
  Eigen::MatrixXd nan_pose = Eigen::MatrixXd::Zero(5, 3);
  nan_pose(2, 1) = std::nan("");
  expect_error([&] { smpl_posed_vertices(m, Eigen::VectorXd::Zero(2), nan_pose, Eigen::Vector3d::Zero()); },
               PLEAT_ERROR_INVALID_ARGUMENT, "joint 2");
}

TEST_F(SmplNpz, TruncatedAndCorruptArchives) {
  using pleat_test::expect_error;
  std::ifstream in(path("smpl_compressed.npz"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string out = path("damaged.npz");
  auto write = [&](const std::string& b) { std::ofstream(out, std::ios::binary) << b; };

  write(bytes.substr(0, bytes.size() / 2));  // central directory gone
  expect_error([&] { load_smpl_npz(out); }, PLEAT_ERROR_FORMAT, "damaged.npz");
  write(bytes.substr(0, 10));
  expect_error([&] { read_npz(out); }, PLEAT_ERROR_FORMAT, "damaged.npz");
  write("");
  expect_error([&] { read_npz(out); }, PLEAT_ERROR_FORMAT, "damaged.npz");

  // Flip bytes inside the first entry's deflate stream: inflate error or CRC.
  std::string flipped = bytes;
  for (size_t i = 200; i < 400; ++i) flipped[i] = static_cast<char>(flipped[i] ^ 0x5A);
  write(flipped);
  expect_error([&] { read_npz(out); }, PLEAT_ERROR_FORMAT, "entry 'v_template.npy'");

  // A stored (uncompressed) archive with a changed payload byte: CRC mismatch.
  std::ifstream in2(path("smpl_plain.npz"), std::ios::binary);
  std::string plain((std::istreambuf_iterator<char>(in2)), std::istreambuf_iterator<char>());
  plain[300] = static_cast<char>(plain[300] ^ 0x01);
  write(plain);
  expect_error([&] { read_npz(out); }, PLEAT_ERROR_FORMAT, "CRC");

  // .npy level: bad magic, truncated payload.
  expect_error([&] { parse_npy("hello world", "x.npy"); }, PLEAT_ERROR_FORMAT, "bad magic");
  std::ifstream in3(path("v2.npy"), std::ios::binary);
  std::string npy((std::istreambuf_iterator<char>(in3)), std::istreambuf_iterator<char>());
  expect_error([&] { parse_npy(npy.substr(0, npy.size() - 8), "v2.npy"); }, PLEAT_ERROR_FORMAT, "truncated");
}
