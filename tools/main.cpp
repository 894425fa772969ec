// `pleat`: prepare and inspect garments, pose bodies, initialise models, bake, convert.
#include <cstdio>
#include <cstring>

#include "cli.h"

namespace {

const char* kUsage =
    "usage: pleat <command> [options]\n"
    "\n"
    "commands:\n"
    "  prepare <mesh> [-o out.pleatg]   weld, validate, compute spectral bands and\n"
    "                                   geodesic neighbourhoods; print the report\n"
    "      --solver auto|dense|slicing|hybrid   (default auto)\n"
    "      --projection random-walk|symmetric   (default random-walk)\n"
    "      --low-fraction F --mid-fraction F    (defaults 1/30, 1/5)\n"
    "      --geodesic-radius M                  (metres, default 0.10)\n"
    "      --weld-tolerance M --unit-scale S    (load options)\n"
    "  inspect <mesh|file.pleatg|model.pleat>   print the report (and bands, if prepared),\n"
    "                                   or a model's architecture\n"
    "  pose --body B --motion M -o body.pc2   a body driven by a motion, as a point cache\n"
    "      --body DIR|file.npz|rig.fbx     MakeHuman assets folder, SMPL-layout .npz, rigged mesh\n"
    "      --rig cmu_mb|default            MakeHuman skeleton (default cmu_mb)\n"
    "      --shape name=value,...          shape entries (MakeHuman: gender, age, muscle, ...)\n"
    "      --motion clip.bvh|clip.fbx      --map joints.txt (names differ)  --fps F (30)\n"
    "      --first N --frames N            frame range  --rest-obj rest.obj  (rest body)\n"
    "  init-model --body B -o model.pleat   a model with the paper's initialisation for\n"
    "                                   the body's skeleton (untrained: for testing pipelines)\n"
    "      --variant flexigat|gat|lgat  --window N (8)  --fps F (30)  --seed N (1)\n"
    "  bake --model M --garment G --body B --motion clip -o out.pc2|.mdd|.glb|.gltf|.usda|frame_####.obj\n"
    "                                   the garment driven through the model by the motion\n"
    "      --garment file.pleatg|mesh   (--unit-scale S for meshes)  --map joints.txt\n"
    "      --stage skinning|blend-shapes|full (full)  --threads N (1)  --top-k K (model's)\n"
    "      --body-collision M           push the garment out of the body to M metres (0: off)\n"
    "      --first N --frames N         frame range (earlier frames are history)\n"
    "  convert manifest.json            bake garments x characters x clips into PC2, MDD, OBJ,\n"
    "                                   glTF and USD (docs/pipeline.md); a rerun skips what is done\n"
    "      -o DIR  --shard i/n (one of n farm tasks)  --force (redo all)  --report FILE\n"
    "  train config.json [--epochs N]   train a model (docs/training.md; runs pleat-train)\n"
    "  export config.json -o m.pleat    the kept epoch as a model file (pleat-train)\n"
    "  ablation config.json [--only R]  the four runs of the paper's Table I (pleat-train)\n"
    "  bench config.json --model M -o DIR  run time against error on the test split: every\n"
    "                                   host setting, libtorch and LBS (pleat-train; docs/benchmarks.md)\n"
    "      --threads N --repeats N --no-libtorch\n"
    "      --against-blender datagen.json   + Blender re-simulating the first test sequence\n"
    "  datagen config.json [--jobs N]   simulate a training data set in Blender (docs/datagen.md;\n"
    "                                   runs pleat-datagen; --help for its options)\n"
    "  import-sequences config.json     training sequences from any simulator's point caches\n"
    "                                   (PC2, MDD, OBJ, glTF; docs/pipeline.md; runs pleat-datagen)\n"
    "  preview <sequence | cache> -o sheet.png   a PNG contact sheet, front and side, of a\n"
    "                                   training sequence or a bake (--garment G.obj --body B\n"
    "                                   --motion M for a cache; runs pleat-datagen)\n"
    "  version                          print the library version\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace pleat_cli;
  if (argc < 2 || !std::strcmp(argv[1], "help") || !std::strcmp(argv[1], "--help") ||
      !std::strcmp(argv[1], "-h")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  try {
    if (command == "version" || command == "--version") {
      std::printf("pleat %s (library %u.%u.%u)\n", PLEAT_VERSION_STRING, pleat_version() >> 16,
                  (pleat_version() >> 8) & 0xff, pleat_version() & 0xff);
      return 0;
    }
    if (command == "prepare") return run_prepare(parse_args(argc, argv, 2, {}));
    if (command == "inspect") return run_inspect(parse_args(argc, argv, 2, {}));
    if (command == "pose") return run_pose(parse_args(argc, argv, 2, {}));
    if (command == "init-model") return run_init_model(parse_args(argc, argv, 2, {}));
    if (command == "bake") return run_bake(parse_args(argc, argv, 2, {}));
    if (command == "convert") return run_convert(parse_args(argc, argv, 2, {"force"}));
    if (command == "train" || command == "export" || command == "ablation" || command == "bench")
      return run_companion("pleat-train",
                           "configure with -DPLEAT_BUILD_TRAINING=ON and libtorch-dev installed", argc, argv,
                           1);
    if (command == "datagen")
      return run_companion("pleat-datagen", "build the datagen target", argc, argv, 2);
    if (command == "import-sequences" || command == "preview")
      return run_companion("pleat-datagen", "build the datagen target", argc, argv, 1);
    throw CliError{"unknown command '" + command + "'\n\n" + kUsage, 2};
  } catch (const CliError& e) {
    std::fprintf(stderr, "pleat %s: %s\n", command.c_str(), e.message.c_str());
    return e.exit_code;
  }
}
