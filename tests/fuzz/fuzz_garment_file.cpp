// Prepared-garment files (.pleatg, FlatBuffers).
#include "fuzz_support.h"
#include "garment/garment_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] { pleat::deserialize_garment(data, size, "fuzz.pleatg"); });
}
