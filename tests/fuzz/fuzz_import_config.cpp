// import-sequences configurations (JSON). The files a seed names exist (empty)
// beside the input, so mutations reach the checks past the paths.
#include <filesystem>
#include <fstream>

#include "fuzz_support.h"
#include "import_sequences.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = pleat_fuzz::input_file(data, size, "in.json");
  static const bool placed = [&] {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::filesystem::create_directories(dir / "body");
    for (const char* name : {"garment.obj", "walk.bvh", "walk.pc2", "map.txt"}) std::ofstream(dir / name);
    return true;
  }();
  (void)placed;
  return pleat_fuzz::run([&] { pleat::datagen::read_import_config(path); });
}
