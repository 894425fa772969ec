// Datagen configurations (JSON).
#include "config.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] { pleat::datagen::read_config(pleat_fuzz::input_file(data, size, "in.json")); });
}
