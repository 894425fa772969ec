// The `pleat` CLI and the C example host, run as a user would.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

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
