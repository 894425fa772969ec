// Training sequences (io/sequence.*): the fuzzed meta.json sits beside a
// valid garment.obj, garment.pc2, body.pc2 and poses.bin (2 frames, 2 joints),
// so the counts it claims meet real files.
#include <filesystem>
#include <fstream>

#include "fuzz_support.h"
#include "io/sequence.h"

namespace {

std::string sequence_folder() {
  pleat::SequenceData d;
  d.meta.frame_count = 2;
  d.meta.garment_name = "square";
  d.meta.joint_names = {"Hips", "Spine"};
  d.meta.simulator_json = "{\"engine\":\"none\"}";
  d.garment_rest.vertices.resize(4, 3);
  d.garment_rest.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  d.garment_rest.triangles.resize(2, 3);
  d.garment_rest.triangles << 0, 1, 2, 0, 2, 3;
  d.garment_frames.assign(2 * 4 * 3, 0.5f);
  d.body_frames.assign(2 * 3 * 3, 0.25f);
  d.rotations = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  d.root_positions = {0, 1, 0, 0, 1, 0.1f};
  const std::string dir =
      std::filesystem::path(pleat_fuzz::input_file(nullptr, 0, "x")).parent_path() / "sequence";
  pleat::write_sequence(dir, d);
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string dir = sequence_folder();
  std::ofstream(dir + "/meta.json", std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return pleat_fuzz::run([&] { pleat::read_sequence(dir); });
}
