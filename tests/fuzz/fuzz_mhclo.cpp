// MakeHuman clothes bindings (.mhclo).
#include "body/mhclo.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] { pleat::read_mhclo(pleat_fuzz::input_file(data, size, "in.mhclo")); });
}
