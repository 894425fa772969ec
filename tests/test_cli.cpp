// The `pleat` CLI and the C example host, run as a user would.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/point_cache.h"
#include "support/test_support.h"

namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

std::string dress() {
  return pleat_test::source_dir() + "/data/garments/female_elegantsuit01.obj";
}

}  // namespace

TEST(Cli, PrepareReportsAndWritesAFileInspectReadsBack) {
  const std::string out = pleat_test::temp_dir("cli") + "/dress.pleatg";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " prepare " + dress() + " --unit-scale 0.1 -o " + out,
                                    &text),
            0)
      << text;
  EXPECT_NE(text.find("vertices            2205"), std::string::npos) << text;
  EXPECT_NE(text.find("units look like     metres"), std::string::npos) << text;
  EXPECT_NE(text.find("low eigenvectors    74 (requested 74"), std::string::npos) << text;
  EXPECT_NE(text.find("wrote " + out), std::string::npos) << text;
  ASSERT_TRUE(std::filesystem::exists(out));

  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " inspect " + out, &text), 0) << text;
  EXPECT_NE(text.find("vertices            2205"), std::string::npos) << text;
  EXPECT_NE(text.find("solver              dense"), std::string::npos) << text;

  ASSERT_EQ(pleat_test::run_command(env("PLEAT_HOST") + " " + env("PLEAT_LIBRARY") + " " + out, &text), 0)
      << text;
  EXPECT_NE(text.find("garment: 2205 vertices"), std::string::npos) << text;
  EXPECT_NE(text.find("band energy"), std::string::npos) << text;
}

// A bake that meets a full disk (ulimit -f: the write stops short, then fails
// with EFBIG, as on ENOSPC) exits 1 naming the file; the previous cache stays
// byte for byte and no temporary file is left beside it.
TEST(Cli, BakeOnAFullDiskKeepsThePreviousCache) {
  const std::string dir = pleat_test::temp_dir("cli_full_disk");
  const std::string out = dir + "/dress.pc2";
  std::ofstream(out) << "previous bake\n";
  const std::string bake = env("PLEAT_CLI") + " bake --model " + pleat_test::source_dir() +
                           "/data/models/dress.pleat --garment " + dress() + " --unit-scale 0.1 --body " +
                           pleat_test::asset_dir() + "/body --motion " + pleat_test::source_dir() +
                           "/tests/fixtures/motion/12_03_walk_121.bvh --frames 5 -o " + out;
  std::string text;
  // 5 frames of 2205 vertices are 132 KiB; the limit is 64 KiB.
  EXPECT_EQ(pleat_test::run_command("bash -c \"trap '' XFSZ; ulimit -f 64; exec " + bake + "\" 2>&1", &text),
            1)
      << text;
  EXPECT_NE(text.find("PLEAT_ERROR_IO"), std::string::npos) << text;
  EXPECT_NE(text.find("cannot write '" + out + "'"), std::string::npos) << text;
  std::ifstream in(out);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "previous bake\n");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1) << "a temporary file stayed";
}

TEST(Cli, ErrorsExitNonZeroWithTheReason) {
  std::string text;
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " prepare /no/such.obj 2>&1", &text), 1);
  EXPECT_NE(text.find("PLEAT_ERROR_IO"), std::string::npos) << text;
  EXPECT_NE(text.find("/no/such.obj"), std::string::npos) << text;
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " prepare " + dress() + " --solver magic 2>&1", &text),
            2);
  EXPECT_NE(text.find("--solver must be one of"), std::string::npos) << text;
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " frobnicate 2>&1", &text), 2);
  EXPECT_NE(text.find("unknown command"), std::string::npos) << text;
}

TEST(Cli, PoseWritesABodyCacheAndRestObj) {
  const std::string dir = pleat_test::temp_dir("cli_pose");
  const std::string clip = pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " pose --body " + pleat_test::asset_dir() +
                                        "/body --motion " + clip + " --shape height=0.8,gender=1 -o " + dir +
                                        "/walk.pc2 --rest-obj " + dir + "/rest.obj 2>&1",
                                    &text),
            0)
      << text;
  // 121 frames at 120 fps resample to 31 frames at 30 fps.
  const pleat::CacheHeader h = pleat::read_cache_header(dir + "/walk.pc2", pleat::CacheFormat::automatic);
  EXPECT_EQ(h.frame_count, 31);
  EXPECT_EQ(h.vertex_count, 13380);
  EXPECT_TRUE(std::filesystem::exists(dir + "/rest.obj"));

  EXPECT_EQ(
      pleat_test::run_command(env("PLEAT_CLI") + " pose --body " + pleat_test::asset_dir() +
                                  "/body --motion " + clip + " --shape stature=2 -o " + dir + "/x.pc2 2>&1",
                              &text),
      2);
  EXPECT_NE(text.find("unknown entry 'stature'"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.pc2"));
}

// init-model + bake: the dress driven through an (untrained) model by the
// walk. Its skinning prior makes the first frame of the skinning stage the
// body's LBS of the dress in the rest pose of frame 0, so the dress stays on
// the body; later stages stay close to it (their heads start at millimetres).
TEST(Cli, InitModelAndBakeWriteAGarmentCache) {
  const std::string dir = pleat_test::temp_dir("cli_bake");
  const std::string clip = pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh";
  const std::string body = pleat_test::asset_dir() + "/body";
  std::string text;
  ASSERT_EQ(
      pleat_test::run_command(
          env("PLEAT_CLI") + " init-model --body " + body + " -o " + dir + "/m.pleat --seed 3 2>&1", &text),
      0)
      << text;
  EXPECT_NE(text.find("joints              31 (Hips ... RightToeBase)"), std::string::npos) << text;
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " inspect " + dir + "/m.pleat", &text), 0) << text;
  EXPECT_NE(text.find("variant             flexigat"), std::string::npos) << text;
  EXPECT_NE(text.find("skinning prior      nearest body vertex, floor 1e-06"), std::string::npos) << text;

  std::vector<std::vector<float>> frames;
  for (const char* stage : {"skinning", "full"}) {
    const std::string out = dir + "/" + stage + ".pc2";
    ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " bake --model " + dir + "/m.pleat --garment " +
                                          dress() + " --unit-scale 0.1 --body " + body + " --motion " + clip +
                                          " --stage " + stage + " --threads 2 -o " + out + " 2>&1",
                                      &text),
              0)
        << text;
    EXPECT_NE(text.find("31 frames of 2205 vertices at 30 fps"), std::string::npos) << text;
    std::vector<float> data(31 * 2205 * 3);
    const pleat::CacheHeader h =
        pleat::read_cache(out, pleat::CacheFormat::automatic, data.data(), 0, data.size());
    EXPECT_EQ(h.frame_count, 31);
    frames.push_back(data);
  }
  // The walk moves the dress forward; full and skinning differ by at most
  // a few centimetres for an untrained model.
  double travel = 0.0, difference = 0.0;
  for (size_t i = 0; i < 2205 * 3; i += 3)
    travel = std::max(travel, double(std::abs(frames[0][30 * 2205 * 3 + i + 2] - frames[0][i + 2])));
  for (size_t i = 0; i < frames[0].size(); ++i)
    difference = std::max(difference, double(std::abs(frames[0][i] - frames[1][i])));
  EXPECT_GT(travel, 0.3) << "a second of walking";
  EXPECT_GT(difference, 0.0);
  EXPECT_LT(difference, 0.05);

  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " bake --model " + dir + "/m.pleat --garment " +
                                        dress() + " --body " + body + " --motion " + clip +
                                        " --stage wet -o " + dir + "/x.pc2 2>&1",
                                    &text),
            2);
  EXPECT_NE(text.find("--stage must be"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.pc2"));
}
