// The `pleat` CLI and the C example host, run as a user would.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "body/body_source.h"
#include "io/point_cache.h"
#include "support/rigged_export.h"
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

  // --body-collision: the dress on this body dips into it; the post-pass
  // moves those vertices out, by at most the depth of a dip.
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " bake --model " + dir + "/m.pleat --garment " +
                                        dress() + " --unit-scale 0.1 --body " + body + " --motion " + clip +
                                        " --body-collision 0.002 -o " + dir + "/pushed.pc2 2>&1",
                                    &text),
            0)
      << text;
  std::vector<float> pushed(frames[1].size());
  pleat::read_cache(dir + "/pushed.pc2", pleat::CacheFormat::automatic, pushed.data(), 0, pushed.size());
  size_t moved = 0;
  double largest = 0.0;
  for (size_t i = 0; i < pushed.size(); ++i) {
    moved += pushed[i] != frames[1][i];
    largest = std::max(largest, double(std::abs(pushed[i] - frames[1][i])));
  }
  EXPECT_GT(moved, 1000u);
  EXPECT_LT(largest, 0.1);

  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " bake --model " + dir + "/m.pleat --garment " +
                                        dress() + " --body " + body + " --motion " + clip +
                                        " --stage wet -o " + dir + "/x.pc2 2>&1",
                                    &text),
            2);
  EXPECT_NE(text.find("stage must be skinning, blend-shapes or full"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.pc2"));
}

namespace {

std::vector<std::string> files_under(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(std::filesystem::relative(e.path(), dir).string());
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// 3 garments x 2 characters (the MakeHuman body, and a rigged FBX made from
// it at another shape) x 2 clips of 8 frames, an untrained model.
std::string write_convert_manifest(const std::string& dir, const std::string& output,
                                   const std::string& extra) {
  const std::string garments = pleat_test::asset_dir() + "/garments";
  std::ofstream(dir + "/manifest.json")
      << R"({
  "output": ")" +
             output + R"(",
  "formats": ["pc2", "mdd", "obj", "gltf", "glb", "usda"],
  "model": "m.pleat",
  "threads": 2,)" +
             extra + R"(
  "garments": [
    {"name": "dress", "mesh": ")" +
             dress() + R"(", "unit_scale": 0.1},
    {"mesh": ")" +
             garments + R"(/female_casualsuit0[12]/*.obj", "unit_scale": 0.1}],
  "characters": [
    {"name": "makehuman", "body": ")" +
             pleat_test::asset_dir() + R"(/body", "shape": {"gender": 0}},
    {"name": "rigged", "body": "rigged.fbx"}],
  "clips": [
    {"name": "walk", "motion": ")" +
             pleat_test::source_dir() + R"(/tests/fixtures/motion/12_03_walk_121.bvh", "frames": 8},
    {"name": "stride", "motion": ")" +
             pleat_test::source_dir() +
             R"(/tests/fixtures/motion/12_03_walk_121.bvh", "first": 20, "frames": 8}]
})";
  return dir + "/manifest.json";
}

}  // namespace

TEST(Cli, ConvertBakesAManifestIntoEveryFormatOnceAndInShards) {
  const std::string dir = pleat_test::temp_dir("cli_convert");
  std::string text;
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " init-model --body " + pleat_test::asset_dir() +
                                        "/body -o " + dir + "/m.pleat 2>&1",
                                    &text),
            0)
      << text;
  pleat::BodySource source =
      pleat::load_body_source(pleat_test::asset_dir() + "/body", PLEAT_BODY_MAKEHUMAN, PLEAT_RIG_CMU_MB);
  const pleat::Body male = source.reshape(pleat::shape_values(source.body, {{"gender", 1.0}}));
  ASSERT_EQ(pleat_test::export_rigged_body(male, dir + "/rigged.fbx", "fbxa"), "");

  const std::string manifest = write_convert_manifest(dir, "out", "");
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + manifest + " 2>&1", &text), 0) << text;
  EXPECT_NE(text.find("12 baked, 0 up to date, 0 failed (12 of 12 jobs"), std::string::npos) << text;
  const std::vector<std::pair<std::string, int64_t>> garments = {
      {"dress", 2205}, {"female_casualsuit01", 2197}, {"female_casualsuit02", 2876}};
  for (const auto& [garment, vertices] : garments)
    for (const char* character : {"makehuman", "rigged"})
      for (const char* clip : {"walk", "stride"}) {
        const std::string job = dir + "/out/" + garment + "-" + character + "-" + clip;
        SCOPED_TRACE(job);
        for (const std::string& path : {job + ".pc2", job + ".mdd", job + ".gltf", job + ".glb",
                                        job + "/" + garment + "-" + character + "-" + clip + "_####.obj"}) {
          const pleat::CacheHeader h = pleat::read_cache_header(path, pleat::CacheFormat::automatic);
          EXPECT_EQ(h.frame_count, 8) << path;
          EXPECT_EQ(h.vertex_count, vertices) << path;
        }
        EXPECT_NE(bytes_of(job + ".usda").find("    endTimeCode = 7\n"), std::string::npos);
      }
  // Same frames in every format; the two characters differ.
  std::vector<float> pc2(8 * 2205 * 3), glb(pc2.size()), rigged(pc2.size());
  pleat::read_cache(dir + "/out/dress-makehuman-walk.pc2", pleat::CacheFormat::automatic, pc2.data(), 0,
                    pc2.size());
  pleat::read_cache(dir + "/out/dress-makehuman-walk.glb", pleat::CacheFormat::automatic, glb.data(), 0,
                    glb.size());
  pleat::read_cache(dir + "/out/dress-rigged-walk.pc2", pleat::CacheFormat::automatic, rigged.data(), 0,
                    rigged.size());
  double format_gap = 0.0, character_gap = 0.0;
  for (size_t i = 0; i < pc2.size(); ++i) {
    format_gap = std::max(format_gap, double(std::abs(pc2[i] - glb[i])));
    character_gap = std::max(character_gap, double(std::abs(pc2[i] - rigged[i])));
  }
  EXPECT_LT(format_gap, 1e-5);
  EXPECT_GT(character_gap, 0.01);

  // A rerun bakes nothing and touches nothing.
  const auto written = std::filesystem::last_write_time(dir + "/out/dress-rigged-stride.glb");
  ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + manifest + " 2>&1", &text), 0) << text;
  EXPECT_NE(text.find("0 baked, 12 up to date"), std::string::npos) << text;
  EXPECT_EQ(std::filesystem::last_write_time(dir + "/out/dress-rigged-stride.glb"), written);

  // Two shards into a fresh folder equal the unsharded run, byte for byte.
  for (const char* shard : {"1/2", "2/2"}) {
    ASSERT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + manifest + " -o " + dir +
                                          "/sharded --shard " + shard + " 2>&1",
                                      &text),
              0)
        << text;
    EXPECT_NE(text.find("6 baked"), std::string::npos) << text;
  }
  std::vector<std::string> files = files_under(dir + "/out");
  files.erase(std::remove_if(files.begin(), files.end(),
                             [](const std::string& f) { return f.find("report-") != std::string::npos; }),
              files.end());
  EXPECT_EQ(files.size(), 12u * (5 + 8 + 1));  // 5 single files, 8 OBJ frames and a stamp per job
  for (const std::string& f : files)
    EXPECT_EQ(bytes_of(dir + "/out/" + f), bytes_of(dir + "/sharded/" + f)) << f;
}

TEST(Cli, ConvertRefusesABadManifestBeforeWritingAnything) {
  const std::string dir = pleat_test::temp_dir("cli_convert_bad");
  std::string text;
  std::ofstream(dir + "/m.pleat") << "x";
  std::ofstream(dir + "/rigged.fbx") << "x";
  const std::string missing = write_convert_manifest(dir, "missing", R"( "stage": "full", "top_k": 4,)");
  std::string m = bytes_of(missing);
  m.replace(m.find("female_casualsuit0[12]"), 22, "no_such_garment");
  std::ofstream(missing) << m;
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + missing + " 2>&1", &text), 2);
  EXPECT_NE(text.find("manifest.json: garments[1].mesh: no file matches"), std::string::npos) << text;

  write_convert_manifest(dir, "typo", R"( "fromats": ["pc2"],)");
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + dir + "/manifest.json 2>&1", &text), 2);
  EXPECT_NE(text.find("manifest.json: manifest.fromats: is not a known setting"), std::string::npos) << text;

  // A model that is not a model: named with its manifest entry, exit 2.
  write_convert_manifest(dir, "broken", "");
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + dir + "/manifest.json 2>&1", &text), 2);
  EXPECT_NE(text.find("manifest.json: model '" + dir + "/m.pleat': loading failed (PLEAT_ERROR_FORMAT)"),
            std::string::npos)
      << text;
  EXPECT_EQ(pleat_test::run_command(env("PLEAT_CLI") + " convert " + dir + "/manifest.json --shard 3/2 2>&1",
                                    &text),
            2);
  EXPECT_NE(text.find("--shard expects i/n"), std::string::npos) << text;
  for (const char* out : {"missing", "typo"}) EXPECT_FALSE(std::filesystem::exists(dir + "/" + out)) << out;
  EXPECT_EQ(files_under(dir + "/broken"), std::vector<std::string>{}) << "only the empty state folder";
}

// Blender (Debian's 3.4, as scripts/setup.sh installs it) imports a baked
// .glb as shape-key animation: same vertex count, one key per frame, and at
// every frame the positions of the OBJ bake (glTF's Y up is Blender's Z up).
TEST(Cli, BlenderPlaysTheGltfBakeFrameForFrame) {
  const std::string dir = pleat_test::temp_dir("cli_blender_gltf");
  const std::string bake = env("PLEAT_CLI") + " bake --model " + pleat_test::source_dir() +
                           "/data/models/dress.pleat --garment " + dress() + " --unit-scale 0.1 --body " +
                           pleat_test::asset_dir() + "/body --motion " + pleat_test::source_dir() +
                           "/tests/fixtures/motion/12_03_walk_121.bvh --frames 12 -o ";
  std::string text;
  ASSERT_EQ(pleat_test::run_command(bake + dir + "/dress.glb 2>&1", &text), 0) << text;
  ASSERT_EQ(pleat_test::run_command(bake + dir + "/dress_##.obj 2>&1", &text), 0) << text;
  ASSERT_EQ(
      pleat_test::run_command("blender -b --factory-startup -noaudio --python-exit-code 3 -P " +
                                  pleat_test::source_dir() + "/tests/blender/read_gltf_animation.py -- " +
                                  dir + "/dress.glb " + dir + "/blender.json 2>&1",
                              &text),
      0)
      << text;
  const nlohmann::json b = nlohmann::json::parse(bytes_of(dir + "/blender.json"));
  EXPECT_EQ(b["meshes"], 1);
  EXPECT_EQ(b["vertices"], 2205);
  EXPECT_EQ(b["shape_keys"], 12);  // the basis and one per later frame
  ASSERT_EQ(b["frames"].size(), 12u);
  std::vector<float> obj(12 * 2205 * 3);
  pleat::read_cache(dir + "/dress_##.obj", pleat::CacheFormat::automatic, obj.data(), 0, obj.size());
  for (int f = 0; f < 12; ++f) {
    EXPECT_EQ(b["frames"][f], f);
    for (size_t p = 0; p < b["probe"].size(); ++p) {
      const size_t v = b["probe"][p];
      const float* x = &obj[(f * 2205 + v) * 3];
      const nlohmann::json& y = b["positions"][f][p];
      EXPECT_NEAR(y[0].get<double>(), x[0], 1e-5) << "frame " << f << " vertex " << v;
      EXPECT_NEAR(y[1].get<double>(), -x[2], 1e-5) << "frame " << f << " vertex " << v;
      EXPECT_NEAR(y[2].get<double>(), x[1], 1e-5) << "frame " << f << " vertex " << v;
    }
  }
}
