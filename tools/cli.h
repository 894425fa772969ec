#pragma once
// Shared pieces of the `pleat` command-line tool. The CLI is a client of the
// public C API only, like any host.
#include <map>
#include <string>
#include <vector>

#include "capi/pleat.h"

namespace pleat_cli {

// Thrown to end a command with a message and an exit code.
struct CliError {
  std::string message;
  int exit_code = 1;
};

// --name value / --flag arguments and the positional rest.
struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;
  bool has(const std::string& name) const { return options.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  double number(const std::string& name, double fallback) const;
};

// Parses argv; `flags` are options that take no value.
Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& flags);

// Throws CliError with pleat_last_error() if status is not PLEAT_OK.
void check(pleat_status status, const std::string& what);

pleat_mesh_report report_of(const pleat_garment* garment);
void print_report(const pleat_mesh_report& report);
void print_band_info(const pleat_band_info& info);
// Prints the energy (RMS over vertices) of the rest shape in each band.
void print_rest_band_energies(const pleat_garment* garment);

int run_prepare(const Args& args);
int run_inspect(const Args& args);
int run_pose(const Args& args);

}  // namespace pleat_cli
