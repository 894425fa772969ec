// The demo model shipped in data/models (trained on the Blender data sets of
// data/datagen/demo.json, dress.json and demo_long.json; report: data/models/demo.md):
// it loads, it is trained (its learned stages move the garment away from
// plain skinning, which an initialised model never does), and it drives the
// sample dress through a walk on the MakeHuman body without leaving the body.
#include <gtest/gtest.h>

#include "body/body_source.h"
#include "body/bvh.h"
#include "body/motion_ops.h"
#include "core/nearest_points.h"
#include "garment/garment.h"
#include "io/mesh_import.h"
#include "runtime/instance.h"
#include "runtime/model_file.h"
#include "support/stage_outputs.h"
#include "support/test_support.h"

using namespace pleat;
using namespace pleat::runtime;

TEST(DemoModel, IsTrainedAndDrivesTheSampleDress) {
  const std::shared_ptr<const Model> model =
      load_model_file(pleat_test::source_dir() + "/data/models/demo.pleat");
  EXPECT_GE(model->training.epochs, 1);
  EXPECT_EQ(model->default_top_k, 8) << "the MakeHuman body's largest influence count (decision 0007)";
  EXPECT_TRUE(refinement_reads_code(*model)) << "the per-asset recipe's refinement reads F^t (decision 0015)";
  EXPECT_NE(model->training.dataset.find("training sequences"), std::string::npos) << model->training.dataset;

  ImportedMesh mesh = import_mesh(pleat_test::source_dir() + "/data/garments/female_elegantsuit01.obj");
  mesh.vertices *= 0.1;  // decimetres
  const auto garment =
      std::make_shared<const Garment>(build_garment(mesh.vertices, mesh.triangles, {}, "dress"));
  const Body body =
      load_body_source(pleat_test::asset_dir() + "/body", PLEAT_BODY_MAKEHUMAN, PLEAT_RIG_CMU_MB).body;
  const JointMap map = read_joint_map(pleat_test::source_dir() + "/data/retarget/cmu_mb.txt");
  RetargetOptions options;
  options.map = &map;
  const Motion walk = retarget_motion(
      resample_motion(read_bvh(pleat_test::source_dir() + "/tests/fixtures/motion/12_03_walk_121.bvh").motion,
                      30.0),
      body.skeleton, options);
  const int64_t frames = std::min<int64_t>(walk.frame_count, 30);
  std::vector<float> rotations, roots;
  for (int64_t f = 0; f < frames; ++f) {
    for (int32_t j = 0; j < body.joint_count(); ++j)
      for (int k = 0; k < 4; ++k) rotations.push_back(static_cast<float>(walk.frame(f)[j].coeffs()[k]));
    for (int k = 0; k < 3; ++k) roots.push_back(static_cast<float>(walk.root_translation(f, k)));
  }
  Instance instance(model, garment, body, InstanceOptions{});
  const int n = instance.vertex_count();
  const PoseSequence poses{rotations.data(), roots.data(), frames, body.joint_count(), 30.0};
  const std::vector<float> skin = pleat_test::evaluate_stage(instance, poses, frames, Stage::skinning);
  const std::vector<float> full = pleat_test::evaluate_stage(instance, poses, frames, Stage::refinement);
  double moved = 0;
  for (size_t i = 0; i < full.size(); i += 3)
    moved += std::sqrt(std::pow(full[i] - skin[i], 2) + std::pow(full[i + 1] - skin[i + 1], 2) +
                       std::pow(full[i + 2] - skin[i + 2], 2));
  moved /= double(full.size() / 3);
  EXPECT_GT(moved, 0.001) << "the trained stages add a displacement to skinning (metres, mean)";
  EXPECT_LT(moved, 0.10) << "and a plausible one";
  // The dress stays on the body: every vertex within 30 cm of the posed body.
  const Points3d posed = pose_body_frames(body, walk, frames - 1, 1);
  const Points3d last = Eigen::Map<const Points3f>(full.data() + (frames - 1) * n * 3, n, 3).cast<double>();
  const std::vector<int32_t> nearest = nearest_points(posed, last);
  double farthest = 0;
  for (int v = 0; v < n; ++v)
    farthest = std::max(farthest, (last.row(v) - posed.row(nearest[size_t(v)])).norm());
  EXPECT_LT(farthest, 0.3);
}
