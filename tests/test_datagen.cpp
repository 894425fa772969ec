// pleat datagen without Blender: the config reader and its errors, the plan
// (segments, splits, held-out garments), the settling lead-in, pinning and the
// acceptance check. test_datagen_blender.cpp runs the simulator itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>

#include "blender_run.h"
#include "body/bvh.h"
#include "body/makehuman.h"
#include "config.h"
#include "core/nearest_points.h"
#include "core/topology.h"
#include "garment_check.h"
#include "io/obj_reader.h"
#include "io/sequence.h"
#include "plan.h"
#include "sequence_inputs.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;
using namespace pleat::datagen;
using pleat_test::expect_error;

namespace {

// A config with every asset real; `extra` is spliced in before the closing brace.
std::string config_text(const std::string& extra = "") {
  const std::string a = pleat_test::asset_dir();
  return "{\"name\": \"t\", \"body\": \"" + a +
         "/body\", \"sequences\": {\"train\": 4, \"test\": 2, \"held_out\": 2},\n"
         "\"garments\": [{\"name\": \"dress\", \"mhclo\": \"" +
         a +
         "/garments/female_elegantsuit01/female_elegantsuit01.mhclo\"},\n"
         "  {\"name\": \"skirt\", \"mhclo\": \"" +
         a +
         "/garments/helpers_mhclo/skirthelper.mhclo\", \"held_out\": true}],\n"
         "\"shapes\": [{\"name\": \"f\", \"values\": {\"gender\": 0.0}}, {\"name\": \"m\", \"values\": "
         "{\"gender\": 1.0}}],\n"
         "\"motions\": [{\"source\": \"" +
         a +
         "/motions/cmu_mb/12_03.bvh\"},\n"
         "  {\"source\": \"" +
         a +
         "/motions/cmu_mb/16_57.bvh\"},\n"
         "  {\"source\": \"" +
         a + "/motions/cmu_daz/02_02.bvh\", \"split\": \"test\"}]" + extra + "}";
}

Config parsed(const std::string& extra = "") {
  return parse_config(config_text(extra), "/tmp/c.json");
}

// config_text() with `motion` (a JSON object) as its second clip.
std::string with_second_motion(const std::string& motion) {
  std::string text = config_text();
  const std::string first = "/motions/cmu_mb/12_03.bvh\"}";
  return text.replace(text.find(first), first.size(), first + ",\n  " + motion);
}

// config_text() with `setting` ("key": value) added to the dress's entry.
std::string with_dress_setting(const std::string& setting) {
  std::string text = config_text();
  const std::string dress = "female_elegantsuit01.mhclo\"";
  return text.insert(text.find(dress) + dress.size(), ", " + setting);
}

// The jobs `c` plans for the clips `assets` loaded.
std::vector<Job> planned_jobs(const Config& c, const Assets& assets) {
  std::vector<int64_t> frames;
  for (const Motion& m : assets.motions) frames.push_back(m.frame_count);
  return plan_jobs(c, frames);
}

}  // namespace

TEST(DatagenConfig, ReadsEverySettingWithDefaults) {
  const Config c = parsed(", \"cloth\": {\"quality\": 7}, \"collision\": {\"self_collision\": true}");
  EXPECT_EQ(c.name, "t");
  EXPECT_EQ(c.garments.size(), 2u);
  EXPECT_EQ(c.garments[0].name, "dress");
  EXPECT_TRUE(c.garments[1].held_out);
  EXPECT_DOUBLE_EQ(c.garments[0].pin_distance, 0.01);
  EXPECT_EQ(c.motions[0].name, "12_03") << "the file stem names a clip";
  EXPECT_EQ(c.motions[2].split, "test");
  EXPECT_EQ(c.motions[0].split, "train");
  EXPECT_EQ(c.cloth.quality, 7);
  EXPECT_DOUBLE_EQ(c.cloth.mass, 0.3) << "unset keys keep their defaults";
  EXPECT_TRUE(c.collision.self_collision);
  EXPECT_EQ(c.shapes[1].values.at(0), (std::pair<std::string, double>("gender", 1.0)));
  EXPECT_EQ(c.train, 4);
  EXPECT_EQ(c.held_out, 2);
}

TEST(DatagenConfig, ShippedDemoConfigIsAsLargeAsTheDataSetMustBe) {
  // The demo data set: at least 6 garments (some held out of training), 5
  // body shapes and 15 clips, each split represented.
  const Config c = read_config(pleat_test::source_dir() + "/data/datagen/demo.json");
  EXPECT_GE(c.garments.size(), 6u);
  EXPECT_GE(
      std::count_if(c.garments.begin(), c.garments.end(), [](const GarmentSpec& g) { return g.held_out; }),
      1);
  EXPECT_GE(c.shapes.size(), 5u);
  EXPECT_GE(c.motions.size(), 15u);
  std::set<std::string> splits;
  for (const MotionSpec& m : c.motions) splits.insert(m.split);
  EXPECT_EQ(splits, (std::set<std::string>{"train", "validation", "test"}));
  EXPECT_GT(c.train, 0);
  EXPECT_GT(c.validation, 0);
  EXPECT_GT(c.test, 0);
  EXPECT_GT(c.held_out, 0);
}

// The generic set's extra data: training sequences only, on the demo set's
// training clips and shapes, simulated as the demo set is. Its garments are
// new (the suit) or longer variants of a garment the demo set trains on (the
// long set), never a held-out one, so no test clip or held-out garment leaks
// into training.
TEST(DatagenConfig, ShippedExtraGenericConfigsAddOnlyTrainingSequences) {
  const Config demo = read_config(pleat_test::source_dir() + "/data/datagen/demo.json");
  std::set<std::string> training_clips, trained_garments, held_out_garments;
  for (const MotionSpec& m : demo.motions)
    if (m.split == "train") training_clips.insert(m.source);
  for (const GarmentSpec& g : demo.garments)
    (g.held_out ? held_out_garments : trained_garments).insert(g.mhclo);
  for (const std::string file : {"demo_suit.json", "demo_long.json", "demo_ankle.json"}) {
    const Config extra = read_config(pleat_test::source_dir() + "/data/datagen/" + file);
    for (const MotionSpec& m : extra.motions) {
      EXPECT_EQ(m.split, "train") << file << ": " << m.name;
      EXPECT_TRUE(training_clips.count(m.source))
          << file << ": " << m.name << " is not a training clip of demo.json";
    }
    EXPECT_EQ(extra.validation + extra.test + extra.held_out, 0) << file;
    for (const GarmentSpec& g : extra.garments) {
      EXPECT_FALSE(held_out_garments.count(g.mhclo)) << file << ": " << g.name;
      EXPECT_EQ(trained_garments.count(g.mhclo), g.stretched() ? 1u : 0u)
          << file << ": " << g.name << " is either new or a longer variant of a training garment";
    }
    EXPECT_EQ(extra.shapes.size(), demo.shapes.size()) << file;
    EXPECT_EQ(simulator_settings(extra, extra.garments[0]), simulator_settings(demo, demo.garments[0]))
        << file;
  }
}

// The per-asset data set (training.md): one garment on one body, every clip
// of the asset pack with a split of its own for validation and test, and
// twins of the test sequences for the noise floor.
TEST(DatagenConfig, ShippedPerAssetConfigCoversEveryClipOnce) {
  const Config c = read_config(pleat_test::source_dir() + "/data/datagen/dress.json");
  EXPECT_EQ(c.garments.size(), 1u);
  EXPECT_EQ(c.shapes.size(), 1u);
  EXPECT_TRUE(c.mirror);
  std::set<std::string> clips, splits;
  for (const MotionSpec& m : c.motions) {
    EXPECT_TRUE(clips.insert(m.name).second) << m.name << " twice";
    splits.insert(m.split);
  }
  size_t in_pack = 0;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(pleat_test::asset_dir() + "/motions"))
    in_pack +=
        entry.path().extension() == ".bvh" && entry.path().parent_path().filename() != "makehuman_poses";
  EXPECT_EQ(clips.size(), in_pack) << "every CMU clip of the pack";
  EXPECT_EQ(splits, (std::set<std::string>{"train", "validation", "test"}));
  EXPECT_EQ(c.twins.split, "test");
}

// The augmented dress sets (clips played at other speeds, clips turned or spun)
// change only the training clips of the main set, simulated as it is, so the
// test clips stay unseen.
TEST(DatagenConfig, ShippedAugmentedConfigsChangeOnlyTheTrainingClips) {
  const Config main = read_config(pleat_test::source_dir() + "/data/datagen/dress.json");
  const auto check = [&](const std::string& file, const std::set<std::pair<double, double>>& variants) {
    const Config augmented = read_config(pleat_test::source_dir() + "/data/datagen/" + file);
    std::set<std::tuple<std::string, double, double>> expected, got;
    for (const MotionSpec& m : main.motions)
      if (m.split == "train")
        for (const auto& [speed, turn] : variants) expected.insert({m.source, speed, turn});
    for (const MotionSpec& m : augmented.motions) {
      EXPECT_EQ(m.split, "train") << file << ": " << m.name;
      got.insert({m.source, m.speed, m.turn});
    }
    EXPECT_EQ(got, expected) << file;
    EXPECT_EQ(augmented.validation + augmented.test, 0) << file;
    EXPECT_EQ(augmented.cloth.quality, main.cloth.quality) << file << " is simulated as the main set is";
    EXPECT_EQ(augmented.collider, main.collider) << file;
  };
  check("dress_speed.json", {{0.8, 0.0}, {1.3, 0.0}});
  check("dress_turn.json", {{1.0, 360.0}});
  check("dress_spin.json", {{1.0, 600.0}});
}

// The pose set: every MakeHuman pose of the pack that stands within 30
// degrees of upright (not the flying, handstand, sitting or lunging ones,
// whose root tilts 34-160 degrees: a dress is not worn lying down), held
// after the lead-in, training data only, simulated as the main dress set is.
TEST(DatagenConfig, ShippedPoseConfigHoldsEveryUprightMakeHumanPose) {
  const Config main = read_config(pleat_test::source_dir() + "/data/datagen/dress.json");
  const Config poses = read_config(pleat_test::source_dir() + "/data/datagen/dress_poses.json");
  std::set<std::string> expected, got;
  for (const auto& entry :
       std::filesystem::directory_iterator(pleat_test::asset_dir() + "/motions/makehuman_poses")) {
    if (entry.path().extension() != ".bvh") continue;
    const Motion pose = read_bvh(entry.path().string()).motion;
    const double tilt = std::acos((pose.frame(0)[0] * Eigen::Vector3d::UnitY()).y()) * 180.0 / M_PI;
    if (tilt < 30.0) expected.insert(entry.path().filename().string());
  }
  EXPECT_EQ(expected.size(), 10u);
  for (const MotionSpec& m : poses.motions) {
    got.insert(std::filesystem::path(m.source).filename().string());
    EXPECT_EQ(m.split, "train") << m.name;
    EXPECT_EQ(m.hold_frames, 30) << m.name;
    EXPECT_EQ(std::filesystem::path(m.map).filename(), "makehuman_default.txt") << m.name;
  }
  EXPECT_EQ(got, expected);
  EXPECT_EQ(poses.train, 2 * static_cast<int64_t>(expected.size())) << "each pose and its mirror";
  EXPECT_EQ(simulator_settings(poses, poses.garments[0]), simulator_settings(main, main.garments[0]));
  EXPECT_EQ(poses.shapes[0].values, main.shapes[0].values);
}

TEST(DatagenConfig, ErrorsNameTheField) {
  const auto I = PLEAT_ERROR_FORMAT;
  expect_error([] { parsed(", \"cloth\": {\"qualty\": 7}"); }, I, "'cloth.qualty' is not a known setting");
  expect_error([] { parsed(", \"cloth\": {\"mass\": \"heavy\"}"); }, I, "'cloth.mass' must be a number");
  expect_error([] { parsed(", \"frame_rate\": -3"); }, I, "'frame_rate' must be in [1, 1000]");
  expect_error([] { parse_config("{", "c.json"); }, I, "datagen config 'c.json': not valid JSON");
  std::string text = config_text();
  text.replace(text.find("skirthelper.mhclo"), 17, "nothere.mhclo");
  expect_error([&] { parse_config(text, "c.json"); }, I, "'garments[1].mhclo' names '");
  text = config_text();
  text.replace(text.find("\"name\": \"skirt\""), 15, "\"name\": \"dress\"");
  expect_error([&] { parse_config(text, "c.json"); }, I, "'garments[1]' repeats the name 'dress'");
  text = config_text();
  text.replace(text.find("\"test\": 2"), 9, "\"validation\": 2");
  expect_error([&] { parse_config(text, "c.json"); }, I,
               "validation sequences, but no motion has that split");
  text = config_text();
  text.replace(text.find("\"name\": \"f\""), 11, "\"name\": \"f/x\"");
  expect_error([&] { parse_config(text, "c.json"); }, I, "'shapes[0].name' 'f/x' may hold only");
  expect_error([] { read_config("/nonexistent/c.json"); }, PLEAT_ERROR_IO, "/nonexistent/c.json");
}

TEST(DatagenConfig, ColliderIsAnAssetFileAndPartOfTheJobHashOnlyWhenSet) {
  const std::string a = pleat_test::asset_dir();
  const Config body = parsed();
  EXPECT_TRUE(body.collider.empty()) << "the body itself collides by default";
  EXPECT_FALSE(simulator_settings(body, body.garments[0]).contains("collider"))
      << "data sets made before the option keep their hashes";
  const Config proxy = parsed(", \"collider\": \"" + a + "/body/proxies/female1605/female1605.proxy\"");
  EXPECT_EQ(simulator_settings(proxy, proxy.garments[0]).at("collider"), "female1605.proxy");
  expect_error([] { parsed(", \"collider\": \"/nonexistent.proxy\""); }, PLEAT_ERROR_FORMAT,
               "'collider' names '/nonexistent.proxy', which is not a file");
}

TEST(DatagenConfig, DefaultOutputIsTheCacheFolder) {
  setenv("PLEAT_DATA_DIR", "/data/sets", 1);
  EXPECT_EQ(default_dataset_dir("x"), "/data/sets/x");
  unsetenv("PLEAT_DATA_DIR");
  setenv("XDG_CACHE_HOME", "/c", 1);
  EXPECT_EQ(default_dataset_dir("x"), "/c/pleat/datasets/x");
  unsetenv("XDG_CACHE_HOME");
  setenv("HOME", "/home/u", 1);
  EXPECT_EQ(default_dataset_dir("x"), "/home/u/.cache/pleat/datasets/x");
}

TEST(DatagenPlan, SegmentsAreSpreadOverTheClipAndMirrored) {
  Config c = parsed();
  c.segment_frames = 120;
  c.segments_per_clip = 2;
  c.min_segment_frames = 40;
  c.mirror = false;
  std::vector<Segment> s = clip_segments(c, 3, 300);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].first, 0);
  EXPECT_EQ(s[1].first, 180) << "the last segment ends with the clip";
  EXPECT_EQ(s[1].count, 120);
  EXPECT_EQ(s[1].motion, 3u);
  EXPECT_EQ(clip_segments(c, 0, 200).size(), 1u) << "room for one segment only";
  s = clip_segments(c, 0, 50);
  ASSERT_EQ(s.size(), 1u) << "a short clip is one shorter segment";
  EXPECT_EQ(s[0].count, 50);
  EXPECT_TRUE(clip_segments(c, 0, 39).empty()) << "below min_segment_frames";
  c.mirror = true;
  s = clip_segments(c, 0, 300);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_FALSE(s[1].mirrored);
  EXPECT_TRUE(s[2].mirrored);
  EXPECT_EQ(s[3].first, 180);
}

TEST(DatagenPlan, FirstSequencesOfASplitUseDifferentClips) {
  Config c = parsed();
  c.train = 2;
  c.validation = c.test = c.held_out = 0;
  c.min_segment_frames = 40;
  // Training clips 0 and 1 give one segment each, and its mirror.
  const std::vector<Job> jobs = plan_jobs(c, {141, 66, 75});
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].segment.motion, 0u);
  EXPECT_EQ(jobs[1].segment.motion, 1u) << "not clip 0's mirror before clip 1";
  EXPECT_FALSE(jobs[1].segment.mirrored);
}

TEST(DatagenPlan, SplitsFollowTheProtocol) {
  Config c = parsed();
  c.train = 6;
  c.test = 3;
  c.held_out = 3;
  c.min_segment_frames = 40;
  const std::vector<int64_t> frames = {141, 66, 75};  // the clips at 30 fps: one segment each, and its mirror
  const std::vector<Job> jobs = plan_jobs(c, frames);
  ASSERT_EQ(jobs.size(), 12u);
  std::set<std::string> names;
  std::set<size_t> train_motions, test_motions, shapes;
  for (const Job& j : jobs) {
    EXPECT_TRUE(names.insert(j.name).second) << j.name << " planned twice";
    if (j.held_out_garment) {
      EXPECT_EQ(j.split, "test");
      EXPECT_EQ(j.garment, 1u) << "only the held-out garment";
      continue;
    }
    EXPECT_EQ(j.garment, 0u) << "a held-out garment is never trained on";
    (j.split == "train" ? train_motions : test_motions).insert(j.segment.motion);
    shapes.insert(j.shape);
    EXPECT_LE(j.segment.first + j.segment.count, frames[j.segment.motion]);
  }
  EXPECT_EQ(train_motions, (std::set<size_t>{0, 1}));
  EXPECT_EQ(test_motions, (std::set<size_t>{2})) << "a clip is on one side of the split only";
  EXPECT_EQ(shapes.size(), 2u);
  EXPECT_EQ(jobs[0].name, "dress-f-12_03-0000");
  const std::vector<Job> again = plan_jobs(c, frames);
  for (size_t i = 0; i < jobs.size(); ++i) EXPECT_EQ(again[i].name, jobs[i].name) << "deterministic";
  // Asking for more than exists gives every combination once: 2 shapes x 2
  // test segments (plain, mirrored) of the one test clip.
  c.test = 100;
  int test = 0;
  for (const Job& j : plan_jobs(c, frames)) test += j.split == "test" && !j.held_out_garment;
  EXPECT_EQ(test, 4);
  expect_error(
      [&] {
        plan_jobs(c, {141, 66, 10});
      },
      PLEAT_ERROR_INVALID_ARGUMENT, "the test clips give no segment of at least 40 frames");
}

// One garment on one shape (the per-asset data set): the stride 2i mod S of
// the first pass reaches only even segments, so the plan must still take
// every segment of every clip, plain and mirrored, once.
TEST(DatagenPlan, OneGarmentOnOneShapeTakesEverySegment) {
  Config c = parsed();
  c.garments.pop_back();
  c.shapes.pop_back();
  c.train = 100;
  c.test = 100;
  c.held_out = 0;
  c.segment_frames = 30;
  c.segments_per_clip = 4;
  c.min_segment_frames = 20;
  // Clips 0 and 1 train (4 and 2 segments, each mirrored), clip 2 tests (2, mirrored).
  const std::vector<Job> jobs = plan_jobs(c, {141, 66, 75});
  std::set<std::string> train, test;
  for (const Job& j : jobs) (j.split == "train" ? train : test).insert(j.name);
  EXPECT_EQ(train.size(), 12u);
  EXPECT_EQ(test.size(), 4u);
  EXPECT_EQ(jobs.size(), 16u) << "no job twice";
  EXPECT_TRUE(train.count("dress-f-12_03-0037m")) << "an odd segment of the pool";
}

// The noise floor's twins: every test job once more, after all the others,
// with a heavier cloth and a longer rest lead-in.
TEST(DatagenPlan, TwinsRepeatTheirSplitPerturbed) {
  Config c = parsed(R"(, "twins": {"split": "test", "mass_scale": 1.01, "extra_rest_frames": 7})");
  c.min_segment_frames = 40;
  const std::vector<Job> jobs = plan_jobs(c, {141, 66, 75});
  std::vector<std::string> test;
  size_t first_twin = jobs.size();
  for (size_t i = 0; i < jobs.size(); ++i) {
    if (jobs[i].twin_of.empty()) {
      EXPECT_EQ(first_twin, jobs.size()) << "twins come after every other job";
      if (jobs[i].split == "test") test.push_back(jobs[i].name);
    } else {
      first_twin = std::min(first_twin, i);
      EXPECT_EQ(jobs[i].name, jobs[i].twin_of + ".twin");
    }
  }
  ASSERT_EQ(jobs.size() - first_twin, test.size());
  for (size_t k = 0; k < test.size(); ++k) EXPECT_EQ(jobs[first_twin + k].twin_of, test[k]);
  const Config twin = twin_config(c);
  EXPECT_DOUBLE_EQ(twin.cloth.mass, c.cloth.mass * 1.01);
  EXPECT_EQ(twin.rest_frames, c.rest_frames + 7);
  EXPECT_EQ(twin.blend_frames, c.blend_frames);
  expect_error([] { parsed(R"(, "twins": {"split": "held_out"})"); }, PLEAT_ERROR_FORMAT, "twins.split");
  expect_error([] { parsed(R"(, "twins": {"split": "test", "mass_scale": 1, "extra_rest_frames": 0})"); },
               PLEAT_ERROR_FORMAT, "perturbs nothing");
}

// A clip played faster is resampled from a time-warped source: frame k at
// speed 2 is frame 2k at speed 1, and it is another clip, named by its rate.
TEST(DatagenInputs, SpeedTimeWarpsTheClip) {
  std::string text = with_second_motion("{\"source\": \"" + pleat_test::asset_dir() +
                                        "/motions/cmu_mb/12_03.bvh\", \"speed\": 2}");
  const Config c = parse_config(text, "/tmp/c.json");
  ASSERT_EQ(c.motions.size(), 4u);
  EXPECT_EQ(c.motions[1].name, "12_03x2");
  EXPECT_DOUBLE_EQ(c.motions[1].speed, 2.0);
  EXPECT_DOUBLE_EQ(c.motions[0].speed, 1.0);
  const Assets a = load_assets(c);
  const Motion &normal = a.motions[0], &fast = a.motions[1];
  EXPECT_NEAR(static_cast<double>(fast.frame_count), (normal.frame_count - 1) / 2.0 + 1, 1.0);
  for (int64_t k : {int64_t{0}, int64_t{7}, fast.frame_count - 1}) {
    EXPECT_NEAR((fast.root_translation.row(k) - normal.root_translation.row(2 * k)).norm(), 0.0, 1e-9) << k;
    for (size_t j = 0; j < fast.skeleton.names.size(); ++j)
      EXPECT_NEAR(fast.frame(k)[j].angularDistance(normal.frame(2 * k)[j]), 0.0, 1e-9) << k << " " << j;
  }
  text.replace(text.find("\"speed\": 2"), 10, "\"speed\": 0");
  expect_error([&] { parse_config(text, "c.json"); }, PLEAT_ERROR_FORMAT, "'motions[1].speed' must be in");
}

// take_frames splits one take by time: the second entry is source frames
// [120, 360) of the walk, 240 frames at 120 fps, so 60 frames at 30: one
// segment (and its mirror), the poses of the whole clip from frame 30 (to
// the millimetre: the file's frame time is 0.0083333 s, not 1/120).
TEST(DatagenInputs, TakeFramesCutsAClipByTime) {
  std::string text = with_second_motion("{\"source\": \"" + pleat_test::asset_dir() +
                                        "/motions/cmu_mb/12_03.bvh\", \"name\": \"12_03_late\", "
                                        "\"skip_frames\": 120, \"take_frames\": 240}");
  const Config c = parse_config(text, "/tmp/c.json");
  ASSERT_EQ(c.motions.size(), 4u);
  EXPECT_EQ(c.motions[1].take_frames, 240);
  EXPECT_EQ(c.motions[0].take_frames, 0) << "0: to the clip's end";
  const Assets a = load_assets(c);
  const Motion &whole = a.motions[0], &late = a.motions[1];
  ASSERT_EQ(late.frame_count, 60);
  for (int64_t k : {int64_t{0}, int64_t{59}}) {
    EXPECT_NEAR((late.root_translation.row(k) - whole.root_translation.row(30 + k)).norm(), 0.0, 1e-3) << k;
    for (size_t j = 0; j < late.skeleton.names.size(); ++j)
      EXPECT_NEAR(late.frame(k)[j].angularDistance(whole.frame(30 + k)[j]), 0.0, 1e-3) << k << " " << j;
  }
  EXPECT_EQ(clip_segments(c, 1, late.frame_count).size(), 2u) << "one segment and its mirror";
  text.replace(text.find("\"take_frames\": 240"), 18, "\"take_frames\": 999");
  expect_error([&] { load_assets(parse_config(text, "/tmp/c.json")); }, PLEAT_ERROR_INVALID_ARGUMENT,
               "motion '12_03_late' takes 999 frames after 120 of its 566 (take_frames)");
}

// A single-frame MakeHuman pose, mapped onto the body's rig and held: a
// static clip of 1 + hold_frames frames, cut into segments like any clip of
// that length.
TEST(DatagenInputs, HoldFramesMakeAPoseFileAStaticClip) {
  std::string text = with_second_motion(
      "{\"source\": \"" + pleat_test::asset_dir() + "/motions/makehuman_poses/fight02.bvh\", \"map\": \"" +
      pleat_test::source_dir() + "/data/retarget/makehuman_default.txt\", \"hold_frames\": 59}");
  const Config c = parse_config(text, "/tmp/c.json");
  ASSERT_EQ(c.motions.size(), 4u);
  EXPECT_EQ(c.motions[1].name, "fight02");
  EXPECT_EQ(c.motions[1].hold_frames, 59);
  EXPECT_EQ(c.motions[0].hold_frames, 0);
  const Assets a = load_assets(c);
  const Motion& pose = a.motions[1];
  ASSERT_EQ(pose.frame_count, 60);
  for (size_t j = 0; j < pose.skeleton.names.size(); ++j)
    EXPECT_EQ(pose.frame(59)[j].coeffs(), pose.frame(0)[j].coeffs()) << j;
  EXPECT_GT(pose.frame(0)[pose.skeleton.find("upperleg01.R")].angularDistance(Eigen::Quaterniond::Identity()),
            0.1)
      << "the pose is not the rest pose";
  const std::vector<Segment> segments = clip_segments(c, 1, pose.frame_count);
  ASSERT_EQ(segments.size(), 2u) << "the clip and its mirror";
  for (const Segment& s : segments) EXPECT_EQ(s.count, 60);
  text.replace(text.find("\"hold_frames\": 59"), 17, "\"hold_frames\": -1");
  expect_error([&] { parse_config(text, "c.json"); }, PLEAT_ERROR_FORMAT, "'motions[1].hold_frames' must be");
}

// A turned clip is another clip, named by its rate. Its sequence is the
// plain one with the root turned about the vertical: not at all while the
// body stands at rest, easing in over the blend, then at the full rate.
TEST(DatagenInputs, TurnSpinsTheSequenceFromTheBlendOn) {
  std::string text = config_text();
  const std::string first = "/motions/cmu_mb/12_03.bvh\"}";
  text.replace(text.find(first), first.size(), first.substr(0, first.size() - 1) + ", \"turn\": -180}");
  Config c = parse_config(text, "/tmp/c.json");
  ASSERT_EQ(c.motions[0].name, "12_03t-180");
  EXPECT_DOUBLE_EQ(c.motions[0].turn, -180.0);
  EXPECT_DOUBLE_EQ(c.motions[1].turn, 0.0);
  c.segment_frames = 20;
  const Assets assets = load_assets(c);
  const std::vector<Job> jobs = planned_jobs(c, assets);
  const auto job = std::find_if(jobs.begin(), jobs.end(), [](const Job& j) { return j.segment.motion == 0; });
  ASSERT_NE(job, jobs.end());
  Config plain = c;
  plain.motions[0].turn = 0;
  const SequenceInputs turned = prepare_sequence(c, assets, *job),
                       straight = prepare_sequence(plain, assets, *job);
  ASSERT_EQ(turned.motion.frame_count, straight.motion.frame_count);
  const int32_t n = turned.motion.skeleton.joint_count();
  const Eigen::Quaterniond rest = turned.motion.skeleton.rest_rotation[0];
  const double step = -M_PI / c.frame_rate;
  double theta = 0;
  for (int64_t f = 0; f < turned.motion.frame_count; ++f) {
    const double u = std::clamp(double(f - c.rest_frames) / double(c.blend_frames), 0.0, 1.0);
    theta += step * u * u * (3 - 2 * u);
    const Eigen::Quaterniond yaw(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()));
    EXPECT_LT((rest * turned.motion.frame(f)[0]).angularDistance(yaw * rest * straight.motion.frame(f)[0]),
              1e-9)
        << f;
    for (int32_t j = 1; j < n; ++j)
      ASSERT_EQ(turned.motion.frame(f)[j].coeffs(), straight.motion.frame(f)[j].coeffs());
  }
  // Smoothstep is symmetric, so the blend's B frames turn as far as B / 2 + 1 / 2 at the full rate.
  EXPECT_NEAR(theta, step * (turned.motion.frame_count - 1 - c.rest_frames - c.blend_frames / 2.0 + 0.5),
              1e-9);
  text.replace(text.find("-180"), 4, "2000");
  expect_error([&] { parse_config(text, "c.json"); }, PLEAT_ERROR_FORMAT, "'motions[0].turn' must be in");
}

TEST(DatagenInputs, LeadInStartsAtRestAndEasesIntoTheClip) {
  Motion clip;
  clip.skeleton.names = {"root", "arm"};
  clip.skeleton.parents = {-1, 0};
  clip.skeleton.rest_translation = Points3d(2, 3);
  clip.skeleton.rest_translation << 0, 1, 0, 0.5, 0, 0;
  clip.skeleton.rest_rotation.assign(2, Eigen::Quaterniond::Identity());
  clip.frame_count = 2;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  clip.rotations = {Eigen::Quaterniond::Identity(), q, Eigen::Quaterniond::Identity(), q};
  clip.root_translation = Points3d(2, 3);
  clip.root_translation << 0, 0.8, 0, 0.1, 0.8, 0;
  const Motion m = with_lead_in(clip, 2, 4);
  ASSERT_EQ(m.frame_count, 8);
  // The clip starts at 3 m/s along x; the blend lasts T = 4/30 s, so the root
  // stands still at x = -3 T / 2 = -0.2 and eases in.
  for (int f = 0; f < 3; ++f) {  // rest frames, then the blend's first frame (u = 0)
    EXPECT_NEAR(m.frame(f)[1].angularDistance(Eigen::Quaterniond::Identity()), 0.0, 1e-12) << f;
    EXPECT_NEAR(m.root_translation(f, 0), -0.2, 1e-12) << f;
    EXPECT_NEAR(m.root_translation(f, 1), 0.8, 1e-12) << f;
  }
  // Blend frame 2 of 4: u = 0.5, smoothstep 0.5: half the 90 degrees; the
  // root at -3 T (1/2 - 1/8 + 1/32).
  EXPECT_NEAR(m.frame(4)[1].angularDistance(Eigen::Quaterniond::Identity()), M_PI / 4, 1e-12);
  EXPECT_NEAR(m.root_translation(4, 0), -0.4 * 0.40625, 1e-12);
  // u = 0.25: smoothstep 0.15625.
  EXPECT_NEAR(m.frame(3)[1].angularDistance(Eigen::Quaterniond::Identity()), 0.15625 * M_PI / 2, 1e-12);
  EXPECT_NEAR(m.frame(6)[1].angularDistance(q), 0.0, 1e-12) << "then the clip, unchanged";
  EXPECT_DOUBLE_EQ(m.root_translation(7, 0), 0.1);
}

// The MakeHuman low-poly proxy as the collider: fitted to the shape like a
// garment and skinned with it, it stays on the posed body's surface.
TEST(DatagenInputs, ProxyColliderIsFittedToTheShapeAndFollowsTheBody) {
  const std::string a = pleat_test::asset_dir();
  Config c = parsed(", \"collider\": \"" + a + "/body/proxies/female1605/female1605.proxy\"");
  c.segment_frames = 20;
  const Assets assets = load_assets(c);
  const std::vector<Job> jobs = planned_jobs(c, assets);
  ASSERT_FALSE(jobs.empty());
  const Job& job = jobs.back();
  const SequenceInputs in = prepare_sequence(c, assets, job);
  const int64_t nc = in.collider_rest.vertex_count(), nb = in.body->vertex_count();
  ASSERT_EQ(nc, 1605);
  ASSERT_EQ(in.collider_frames.size(), size_t(in.motion.frame_count * nc * 3));
  for (int64_t f : {int64_t(0), in.motion.frame_count - 1}) {
    const Points3d body = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                              in.body_frames.data() + f * nb * 3, nb, 3)
                              .cast<double>();
    const Points3d collider = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                                  in.collider_frames.data() + f * nc * 3, nc, 3)
                                  .cast<double>();
    const std::vector<int32_t> nearest = nearest_points(body, collider);
    double mean = 0, largest = 0;
    for (int64_t v = 0; v < nc; ++v) {
      const double d = (collider.row(v) - body.row(nearest[size_t(v)])).norm();
      mean += d / double(nc);
      largest = std::max(largest, d);
    }
    EXPECT_LT(mean, 0.01) << "frame " << f;
    EXPECT_LT(largest, 0.04) << "frame " << f;
  }
  Config plain = c;
  plain.collider.clear();
  EXPECT_TRUE(prepare_sequence(plain, load_assets(plain), job).collider_frames.empty())
      << "without a proxy the body collides";
}

// Hand-computed: heights 0, 1, 2, 4; the lower half (below y = 2) three
// times as long: 0 -> 2 - 3 * 2 = -4, 1 -> -1; 2 and 4 stay, x and z too.
TEST(DatagenInputs, StretchHemLengthensOnlyTheLowerPart) {
  Points3d v(4, 3);
  v << 0.5, 0, 0.1, -0.5, 1, 0.2, 0.3, 2, -0.3, 0, 4, 0;
  const Points3d before = v;
  stretch_hem(&v, 0.5, 3.0);
  EXPECT_DOUBLE_EQ(v(0, 1), -4.0);
  EXPECT_DOUBLE_EQ(v(1, 1), -1.0);
  EXPECT_DOUBLE_EQ(v(2, 1), 2.0);
  EXPECT_DOUBLE_EQ(v(3, 1), 4.0);
  EXPECT_EQ(v.col(0), before.col(0));
  EXPECT_EQ(v.col(2), before.col(2));
}

// A garment's "stretch" reaches the fitted rest garment of every sequence:
// the dress's hem drops by (factor - 1) times the stretched part's height,
// its shoulders stay where the plain fit put them.
TEST(DatagenInputs, StretchedGarmentIsTheFittedOneWithALongerHem) {
  Config plain = parsed();
  plain.segment_frames = 20;
  Config stretched =
      parse_config(with_dress_setting(R"("stretch": {"below": 0.35, "factor": 1.8})"), "/tmp/c.json");
  stretched.segment_frames = 20;
  ASSERT_DOUBLE_EQ(stretched.garments[0].stretch_factor, 1.8);
  ASSERT_DOUBLE_EQ(stretched.garments[0].stretch_below, 0.35);
  EXPECT_DOUBLE_EQ(stretched.garments[1].stretch_factor, 1.0) << "only the garment that asks";
  const Assets assets = load_assets(plain);
  const std::vector<Job> jobs = planned_jobs(plain, assets);
  const auto job = std::find_if(jobs.begin(), jobs.end(), [](const Job& j) { return j.garment == 0; });
  ASSERT_NE(job, jobs.end());
  const Points3d a = prepare_sequence(plain, assets, *job).garment_rest.vertices;
  const Points3d b = prepare_sequence(stretched, assets, *job).garment_rest.vertices;
  const double lowest = a.col(1).minCoeff(), cut = lowest + 0.35 * (a.col(1).maxCoeff() - lowest);
  EXPECT_NEAR(b.col(1).minCoeff(), cut - 1.8 * (cut - lowest), 1e-12);
  EXPECT_GT(cut - lowest, 0.2) << "a dress's skirt is longer than 20 cm";
  for (Eigen::Index v = 0; v < a.rows(); ++v)
    if (a(v, 1) >= cut) {
      EXPECT_EQ(a.row(v), b.row(v)) << "vertex " << v;
    }
  expect_error(
      [] { parse_config(with_dress_setting(R"("stretch": {"below": 0.3, "factor": 9})"), "c.json"); },
      PLEAT_ERROR_FORMAT, "'garments[0].stretch.factor' must be in [1, 8], is 9");
  expect_error([] { parse_config(with_dress_setting(R"("stretch": {"factor": 2})"), "c.json"); },
               PLEAT_ERROR_FORMAT, "'garments[0].stretch' needs 'below' > 0 and 'factor' > 1");
}

// Three pieces: a strip whose top touches the body (pinned where it touches),
// a strip hanging clear of it (pinned along its whole top band) and a small
// button (pinned whole).
TEST(DatagenInputs, PinsEachPieceByItsTopBand) {
  Body body;
  body.rest.vertices = Points3d(2, 3);
  body.rest.vertices << 0, 1.0, 0, 5, 1.0, 0;
  TriMesh g;
  std::vector<double> xyz;
  std::vector<int32_t> tri;
  const auto strip = [&](double x0, double y0, int columns, int rows, double step) {
    const auto first = static_cast<int32_t>(xyz.size() / 3);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < columns; ++c) xyz.insert(xyz.end(), {x0 + c * step, y0 - r * step, 0.0});
    for (int r = 0; r + 1 < rows; ++r)
      for (int c = 0; c + 1 < columns; ++c) {
        const int32_t a = first + r * columns + c, b = a + 1, d = a + columns, e = d + 1;
        tri.insert(tri.end(), {a, d, b, b, d, e});
      }
  };
  strip(-0.045, 1.005, 10, 10, 0.01);  // 100 vertices: top row at y 1.005, x -0.045 .. 0.045
  strip(2.0, 1.0, 10, 10, 0.02);       // 100 vertices, far from the body
  strip(3.0, 0.0, 2, 2, 0.01);         // a 4-vertex button
  g.vertices = Eigen::Map<const Points3d>(xyz.data(), Eigen::Index(xyz.size() / 3), 3);
  g.triangles = Eigen::Map<const Triangles>(tri.data(), Eigen::Index(tri.size() / 3), 3);
  const std::vector<int32_t> pinned = pinned_vertices(body, g, 0.01, 0.05);
  std::vector<int32_t> expected;
  for (int32_t v = 0; v < 100; ++v) {  // within 5 cm of the top row and 1 cm of (0, 1, 0)
    const double x = -0.045 + 0.01 * (v % 10), y = 1.005 - 0.01 * (v / 10);
    if (y > 1.005 - 0.05 && std::hypot(x, y - 1.0) < 0.01) expected.push_back(v);
  }
  for (int32_t v = 100; v < 130; ++v)
    expected.push_back(v);  // rows 0-2 of the hanging strip: within 5 cm of its top
  for (int32_t v = 200; v < 204; ++v) expected.push_back(v);  // the button
  EXPECT_EQ(pinned, expected);
  EXPECT_TRUE(pinned_vertices(body, g, 0.0, 0.05).empty()) << "0 pins nothing";
}

// Every piece of a real garment holds on somewhere, and most of it is free.
TEST(DatagenInputs, EveryPieceOfAGarmentIsPinned) {
  const auto model = MakeHumanModel::load(pleat_test::asset_dir() + "/body");
  const Eigen::VectorXd beta = makehuman_default_beta();
  const Body body = model->body(beta);
  const std::string dir = pleat_test::asset_dir() + "/garments/female_casualsuit02/";
  TriMesh g = read_obj_file_order(dir + "female_casualsuit02.obj");
  g.vertices = fit_clothes(read_mhclo(dir + "female_casualsuit02.mhclo"), model->shaped_vertices(beta));
  std::vector<int32_t> label;
  const int32_t pieces =
      connected_components(edge_graph(unique_edges(g.triangles), g.vertex_count()), &label);
  ASSERT_EQ(pieces, 3) << "top, skirt, belt";
  const std::vector<int32_t> pinned = pinned_vertices(body, g, 0.01, 0.05);
  std::set<int32_t> held;
  for (int32_t v : pinned) held.insert(label[size_t(v)]);
  EXPECT_EQ(held.size(), 3u);
  EXPECT_LT(pinned.size(), size_t(g.vertex_count()) / 4);
}

// A sphere of radius 0.5 m as the body, and as the garment every body vertex
// pushed out 5 cm along its radius, for `frames` frames.
struct SphereCheckScene {
  Triangles triangles;
  int64_t nb = 0, frames = 3;
  std::vector<float> body, garment;
  Points3d body_rest, garment_rest;
  SphereCheckScene() {
    const pleat_test::SimpleMesh sphere = pleat_test::icosphere(2, 0.5f);
    triangles.resize(static_cast<Eigen::Index>(sphere.triangles.size() / 3), 3);
    for (size_t i = 0; i < sphere.triangles.size(); ++i)
      triangles.data()[i] = static_cast<int32_t>(sphere.triangles[i]);
    nb = static_cast<int64_t>(sphere.positions.size() / 3);
    for (int64_t f = 0; f < frames; ++f)
      body.insert(body.end(), sphere.positions.begin(), sphere.positions.end());
    for (float x : body) garment.push_back(x * 1.1f);
    body_rest = Eigen::Map<const Points3f>(body.data(), nb, 3).cast<double>();
    garment_rest = body_rest * 1.1;
  }
  CheckReport check(const std::vector<float>& g, const CheckSettings& s) const {
    return check_simulation(g, garment_rest, body, body_rest, triangles, frames, 30.0, s);
  }
};

TEST(DatagenCheck, RejectsExplosionsPenetrationAndNaN) {
  const SphereCheckScene scene;
  const std::vector<float>& body = scene.body;
  const std::vector<float>& garment = scene.garment;
  const int64_t nb = scene.nb;
  CheckSettings s;
  CheckReport r = scene.check(garment, s);
  EXPECT_TRUE(r.passed) << r.reason;
  EXPECT_NEAR(r.max_distance, 0.05, 1e-5);
  EXPECT_EQ(r.max_penetrating_fraction, 0.0);

  std::vector<float> exploded = garment;
  exploded[(2 * nb + 7) * 3] += 1.0f;  // frame 2, vertex 7 a metre out
  r = scene.check(exploded, s);
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.reason.find("frame 2, vertex 7"), std::string::npos) << r.reason;
  EXPECT_EQ(r.max_distance_frame, 2);

  std::vector<float> sunk = garment;
  for (int64_t v = 0; v < nb / 10; ++v)  // 10% of frame 1's vertices 5 cm inside
    for (int k = 0; k < 3; ++k) sunk[(nb + v) * 3 + k] = body[(nb + v) * 3 + k] * 0.9f;
  r = scene.check(sunk, s);
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.reason.find("frame 1:"), std::string::npos) << r.reason;
  EXPECT_NEAR(r.max_penetrating_fraction, double(nb / 10) / double(nb), 1e-9);

  std::vector<float> broken = garment;
  broken[5] = std::numeric_limits<float>::quiet_NaN();
  r = scene.check(broken, s);
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.reason.find("frame 0, vertex 1 is not finite"), std::string::npos) << r.reason;
}

// A garment that the body leaves behind (a sleeve the arm went through) is
// rejected; one that moves with the body, however far, is not.
TEST(DatagenCheck, RejectsAGarmentTheBodyCameOutOf) {
  SphereCheckScene scene;
  const int64_t nb = scene.nb, frames = scene.frames;
  CheckSettings s;
  s.max_slipped_fraction = 0.10;  // off by default
  s.max_body_speed = 100.0;       // the body travels 1 m a frame here (30 m/s)
  // Body and garment travel 2 m together: nothing slipped.
  std::vector<float> body = scene.body, garment = scene.garment;
  for (int64_t f = 1; f < frames; ++f)
    for (int64_t v = 0; v < nb; ++v) {
      body[(f * nb + v) * 3] += 1.0f * float(f);
      garment[(f * nb + v) * 3] += 1.0f * float(f);
    }
  scene.body = body;
  CheckReport r = scene.check(garment, s);
  EXPECT_TRUE(r.passed) << r.reason;
  EXPECT_EQ(r.mean_slipped_fraction, 0.0);

  // A quarter of the garment stays 2 m behind on frame 2 and 1 m behind on
  // frame 1: slipped on two of three frames, 1/6 of the vertices on average.
  // It also lies more than max_distance from the body, so loosen that check to
  // see the slip check alone.
  std::vector<float> left_behind = garment;
  const int64_t quarter = nb / 4;
  for (int64_t f = 1; f < frames; ++f)
    for (int64_t v = 0; v < quarter; ++v) left_behind[(f * nb + v) * 3] -= 1.0f * float(f);
  s.max_distance = 10.0;
  r = scene.check(left_behind, s);
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.mean_slipped_fraction, 2.0 / 3.0 * double(quarter) / double(nb), 1e-12);
  EXPECT_NEAR(r.max_slipped_fraction, double(quarter) / double(nb), 1e-12);
  EXPECT_NE(r.reason.find("body came out of the garment"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("worst frame 1"), std::string::npos) << r.reason;

  // Just under the limit passes; 0.9 m behind is under a 1 m slip distance.
  s.max_slipped_fraction = r.mean_slipped_fraction + 1e-9;
  EXPECT_TRUE(scene.check(left_behind, s).passed);
  s.max_slipped_fraction = 0.10;
  s.slip_distance = 1.05;  // only frame 2's 2 m counts
  r = scene.check(left_behind, s);
  EXPECT_TRUE(r.passed) << r.reason;
  EXPECT_NEAR(r.mean_slipped_fraction, 1.0 / 3.0 * double(quarter) / double(nb), 1e-12);
  EXPECT_NEAR(r.max_slipped_fraction, double(quarter) / double(nb), 1e-12);
}

// A body that jumps between two frames (a clip whose first frame is a
// reference pose) is rejected, naming the frame; walking speed is not.
TEST(DatagenCheck, RejectsABodyThatJumps) {
  SphereCheckScene scene;
  const int64_t nb = scene.nb;
  std::vector<float> body = scene.body, garment = scene.garment;
  for (int64_t v = 0; v < nb; ++v) {  // frame 1: 5 cm on (1.5 m/s); frame 2: 0.7 m on (21 m/s)
    body[(nb + v) * 3] += 0.05f;
    garment[(nb + v) * 3] += 0.05f;
    body[(2 * nb + v) * 3] += 0.75f;
    garment[(2 * nb + v) * 3] += 0.75f;
  }
  scene.body = body;
  CheckSettings s;
  CheckReport r = scene.check(garment, s);
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.max_body_speed, 0.70 * 30.0, 1e-4);
  EXPECT_NE(r.reason.find("frame 2: body vertex"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("skip_frames"), std::string::npos) << r.reason;
  s.max_body_speed = 22.0;
  r = scene.check(garment, s);
  EXPECT_TRUE(r.passed) << r.reason;
  EXPECT_NEAR(r.max_body_speed, 21.0, 1e-4);
}
