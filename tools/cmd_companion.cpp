// Commands served by companion executables beside this binary: `train`,
// `export`, `ablation` by pleat-train (it links libtorch) and `datagen` by
// pleat-datagen (internal library, Blender). This CLI itself stays a pure C
// API client.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli.h"

namespace pleat_cli {

int run_companion(const std::string& tool, const std::string& how_to_build, int argc, char** argv,
                  int first) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path path = (error ? std::filesystem::path(argv[0]) : self).parent_path() / tool;
  if (!std::filesystem::exists(path))
    throw CliError{"'" + path.string() + "' is missing: " + how_to_build, 2};
  std::vector<std::string> args{path.string()};
  for (int i = first; i < argc; ++i) args.emplace_back(argv[i]);
  std::vector<char*> pointers;
  for (std::string& a : args) pointers.push_back(a.data());
  pointers.push_back(nullptr);
  execv(path.c_str(), pointers.data());
  throw CliError{"cannot run '" + path.string() + "': " + std::strerror(errno), 1};
}

}  // namespace pleat_cli
