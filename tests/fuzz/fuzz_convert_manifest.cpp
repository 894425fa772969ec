// `pleat convert` manifests (JSON, tools/convert_manifest.*). The files a
// seed names exist (empty) beside the input, so mutations reach the checks
// past the paths; CliError is the tool's documented refusal.
#include <filesystem>
#include <fstream>

#include "cli.h"
#include "convert_manifest.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pleat_fuzz::input_file(data, size, "in.json");
  static const bool placed = [&] {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::filesystem::create_directories(dir / "body");
    for (const char* name : {"m.pleat", "a.obj", "b.obj", "walk.bvh", "map.txt", "hero.fbx"})
      std::ofstream(dir / name);
    return true;
  }();
  (void)placed;
  try {
    const pleat_cli::ConvertManifest m = pleat_cli::read_convert_manifest(path);
    for (const pleat_cli::ConvertJob& job : pleat_cli::convert_jobs(m))
      for (const std::string& format : m.formats) pleat_cli::convert_output(m, job, format);
  } catch (const pleat_cli::CliError&) {
  }
  return 0;
}
