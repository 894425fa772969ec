// MakeHuman macro targets (targets/macrodetails: MANIFEST.tsv and gzipped
// .target files) on a 64-vertex base. The input is the target file's text,
// gzipped here so that mutations reach the parser rather than zlib's checks;
// an input holding a NUL byte is a manifest (before it) and a target (after).
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <string_view>

#include "body/makehuman.h"
#include "body/makehuman_targets.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const size_t nul = input.find('\0');
  const std::string_view manifest =
      nul == std::string_view::npos ? "african-female-young.target\tt.target.gz\n" : input.substr(0, nul);
  const std::string_view target = nul == std::string_view::npos ? input : input.substr(nul + 1);
  const std::filesystem::path body =
      std::filesystem::path(pleat_fuzz::input_file(nullptr, 0, "probe")).parent_path() / "body";
  const std::filesystem::path folder = body / "targets" / "macrodetails";
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "MANIFEST.tsv", std::ios::binary | std::ios::trunc)
      .write(manifest.data(), static_cast<std::streamsize>(manifest.size()));
  gzFile gz = gzopen((folder / "t.target.gz").c_str(), "wb");
  if (gz == nullptr) return 0;
  if (!target.empty()) gzwrite(gz, target.data(), static_cast<unsigned>(target.size()));
  gzclose(gz);
  return pleat_fuzz::run([&] {
    pleat::MakeHumanTargets targets(body.string(), 64);
    pleat::Points3d base = pleat::Points3d::Zero(64, 3);
    targets.add_to(pleat::makehuman_default_beta(), &base);
    pleat_fuzz::require(base.allFinite(), "targeted vertices are finite");
  });
}
