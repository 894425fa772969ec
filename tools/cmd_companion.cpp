// `pleat train` and `pleat export`: handed to pleat-train beside this binary.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli.h"

namespace pleat_cli {

int run_trainer(int argc, char** argv) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::filesystem::path trainer =
      (error ? std::filesystem::path(argv[0]) : self).parent_path() / "pleat-train";
  if (!std::filesystem::exists(trainer))
    throw CliError{"the trainer is not built ('" + trainer.string() +
                       "' is missing): configure with -DPLEAT_BUILD_TRAINING=ON and libtorch-dev installed",
                   2};
  std::vector<std::string> args{trainer.string()};
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  std::vector<char*> pointers;
  for (std::string& a : args) pointers.push_back(a.data());
  pointers.push_back(nullptr);
  execv(trainer.c_str(), pointers.data());
  throw CliError{"cannot run '" + trainer.string() + "': " + std::strerror(errno), 1};
}

}  // namespace pleat_cli
