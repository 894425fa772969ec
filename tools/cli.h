#pragma once
// Shared pieces of the `pleat` command-line tool. The CLI is a client of the
// public C API only, like any host.
#include <functional>
#include <map>
#include <memory>
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

using BodyPtr = std::unique_ptr<pleat_body, decltype(&pleat_body_destroy)>;
using MotionPtr = std::unique_ptr<pleat_motion, decltype(&pleat_motion_destroy)>;
using ModelPtr = std::unique_ptr<pleat_model, decltype(&pleat_model_destroy)>;
using GarmentPtr = std::unique_ptr<pleat_garment, decltype(&pleat_garment_destroy)>;

// --body (+ --rig, --shape).
BodyPtr load_body(const Args& args);
// --motion (+ --map), resampled to fps and retargeted onto the body.
MotionPtr load_motion_for(const Args& args, const pleat_body* body, double fps);
// --first / --frames within the motion (default: all frames); throws when empty
// or out of range.
struct FrameRange {
  size_t first = 0, count = 0, total = 0;
};
FrameRange frame_range(const Args& args, const pleat_motion* motion, double fps);

// A garment file or mesh (unit_scale 0: the file's own unit).
GarmentPtr load_garment(const std::string& path, double unit_scale);

// "skinning", "blend-shapes" or "full" as PLEAT_STAGE_*; CliError (exit 2) otherwise.
uint32_t stage_of(const std::string& name);

struct BakeSettings {
  uint32_t stage = PLEAT_STAGE_FULL;
  uint32_t threads = 0;         // 0: the library's default
  uint32_t top_k = 0;           // 0: the model's
  float body_collision = 0.0f;  // metres; > 0: the body-collision post-pass
};

// The garment driven through the model by frames [range.first, + count) of
// the motion (earlier frames are history): count * vertices * 3 floats.
// progress(frames done) after every chunk. A fresh instance each call, so
// the result depends on nothing evaluated before.
std::vector<float> bake_frames(const pleat_model* model, const pleat_garment* garment, const pleat_body* body,
                               const pleat_motion* motion, const FrameRange& range,
                               const BakeSettings& settings, const std::function<void(size_t)>& progress);

pleat_model_info model_info(const pleat_model* model);
void print_model_info(const pleat_model* model);

int run_prepare(const Args& args);
int run_inspect(const Args& args);
int run_pose(const Args& args);
int run_init_model(const Args& args);
int run_bake(const Args& args);
int run_convert(const Args& args);
// Replaces this process with `tool` from the same folder, passing argv[first..]
// (see cmd_companion.cpp); `how_to_build` is the hint when it is missing.
int run_companion(const std::string& tool, const std::string& how_to_build, int argc, char** argv, int first);

}  // namespace pleat_cli
