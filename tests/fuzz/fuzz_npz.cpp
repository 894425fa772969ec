// SMPL-layout bodies from .npz (zip of .npy arrays).
#include "body/smpl_npz.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pleat_fuzz::run([&] { pleat::load_smpl_npz(pleat_fuzz::input_file(data, size, "in.npz")); });
}
