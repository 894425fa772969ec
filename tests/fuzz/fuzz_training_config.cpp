// Training configurations (JSON; training/trainer_config.*).
#include "fuzz_support.h"
#include "trainer_config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run(
      [&] { pleat::training::read_trainer_config(pleat_fuzz::input_file(data, size, "in.json")); });
}
