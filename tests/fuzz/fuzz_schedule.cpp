// Training schedules (JSON; training/schedule.*).
#include "fuzz_support.h"
#include "schedule.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] {
    pleat::training::parse_schedule(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
  });
}
