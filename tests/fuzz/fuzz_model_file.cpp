// Model files (.pleat, FlatBuffers). test_model_fuzz mutates a valid file
// with structure-aware edits; this target lets coverage drive the bytes.
#include "fuzz_support.h"
#include "runtime/model_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] { pleat::runtime::deserialize_model(data, size, "fuzz.pleat"); });
}
