// Joint-name maps for retargeting (data/retarget/*.txt).
#include "body/motion_ops.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run(
      [&] { pleat::parse_joint_map(std::string(reinterpret_cast<const char*>(data), size), "fuzz.txt"); });
}
