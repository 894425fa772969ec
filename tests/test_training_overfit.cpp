// Can the model fit the simulator at all? One short sequence simulated by
// Blender (pleat datagen: a skirt in a walk), the plain vertex loss, trained
// and scored on that same sequence: the error must fall below a fifth of
// LBS's. A model that cannot beat LBS on its own training data is
// underfitting; this is the check that it can (issue 22).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "evaluation.h"
#include "support/test_support.h"
#include "trainer.h"

using namespace pleat;
using namespace pleat::training;

namespace {

// The skirt on the default body in 24 frames of the 02_02 walk, after a
// short lead-in, at a low (cheap) quality: a real simulation with a swinging
// hem, in seconds.
std::string simulate_skirt(const std::string& dir) {
  const std::string a = pleat_test::asset_dir();
  std::ofstream(dir + "/datagen.json")
      << "{\"name\": \"overfit\", \"body\": \"" << a << "/body\", \"output\": \"" << dir << "/set\",\n"
      << " \"collider\": \"" << a << "/body/proxies/female1605/female1605.proxy\",\n"
      << " \"segment_frames\": 24, \"segments_per_clip\": 1, \"mirror\": false, \"rest_frames\": 3,"
      << " \"blend_frames\": 10, \"sequences\": {\"train\": 1},\n"
      << " \"garments\": [{\"name\": \"skirt\", \"mhclo\": \"" << a
      << "/garments/helpers_mhclo/skirthelper.mhclo\"}],\n"
      << " \"shapes\": [{\"name\": \"female\", \"values\": {\"gender\": 0.0}}],\n"
      << " \"motions\": [{\"source\": \"" << a << "/motions/cmu_daz/02_02.bvh\", \"map\": \""
      << pleat_test::source_dir() << "/data/retarget/cmu_daz.txt\"}],\n"
      << " \"cloth\": {\"quality\": 8}, \"collision\": {\"quality\": 1},"
      // 02_02's frame 0 is its reference pose: the body jumps past the default speed limit.
      << " \"check\": {\"max_distance\": 0.5, \"max_body_speed\": 40}}";
  std::string output;
  const std::string command =
      std::string(std::getenv("PLEAT_CLI")) + " datagen " + dir + "/datagen.json --jobs 1 --quiet 2>&1";
  EXPECT_EQ(pleat_test::run_command(command, &output), 0) << output;
  return dir + "/set/skirt-female-02_02-0000";
}

}  // namespace

TEST(TrainingOverfit, OneSimulatedSequenceFallsBelowAFifthOfLbs) {
  const std::string root = pleat_test::temp_dir("training_overfit");
  const std::string sequence = simulate_skirt(root);
  TrainerConfig c;
  c.train = {sequence};
  c.validation = {sequence};
  c.schedule = parse_schedule(R"({"phases": [{"name": "supervised", "weights": {"vertex": 100}}]})", "test");
  c.frequency_division = false;
  c.output = root + "/run";
  c.epochs = 150;
  c.batch_frames = 4;
  c.learning_rate = 3e-2;
  c.progress = false;
  c.plot = false;
  c.model.code_width = 32;
  c.model.body_widths = {32, 32};
  c.model.body_vertex_stride = 8;
  c.model.garment_widths = {32, 32};
  c.model.gru_layers = 2;
  c.model.blend_widths = {32, 3};
  c.model.refinement_widths = {32, 16, 3};
  Trainer trainer(c);
  const double lbs = trainer.validation_baseline().e_verts_cm;
  trainer.run();
  const double fitted = trainer.best_validation().e_verts_cm;
  std::printf("one simulated skirt sequence: LBS %.3f cm, fitted %.3f cm (%.2f of LBS) after %lld epochs\n",
              lbs, fitted, fitted / lbs, static_cast<long long>(trainer.epoch()));
  EXPECT_GT(lbs, 0.5) << "the simulation moves the skirt off its skinned shape";
  EXPECT_LT(fitted, 0.2 * lbs);
}
