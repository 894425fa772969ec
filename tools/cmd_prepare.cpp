// `pleat prepare` and `pleat inspect`.
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli.h"

namespace pleat_cli {
namespace {

using GarmentPtr = std::unique_ptr<pleat_garment, decltype(&pleat_garment_destroy)>;

uint32_t parse_choice(const Args& args, const std::string& name, const std::vector<std::string>& choices) {
  const std::string value = args.get(name, choices.front());
  for (size_t i = 0; i < choices.size(); ++i)
    if (choices[i] == value) return static_cast<uint32_t>(i);
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw CliError{"option --" + name + " must be one of " + list + ", got '" + value + "'", 2};
}

GarmentPtr load(const Args& args) {
  if (args.positional.size() != 1) throw CliError{"expects exactly one mesh file", 2};
  pleat_garment_load_options o{};
  o.struct_size = sizeof o;
  o.weld_tolerance = args.number("weld-tolerance", 0.0);
  o.unit_scale = args.number("unit-scale", 0.0);
  pleat_garment* g = nullptr;
  check(pleat_garment_load(args.positional[0].c_str(), &o, &g), "loading '" + args.positional[0] + "'");
  return GarmentPtr(g, pleat_garment_destroy);
}

void print_prepared(const pleat_garment* g) {
  pleat_band_info info{};
  info.struct_size = sizeof info;
  if (pleat_garment_get_band_info(g, &info) != PLEAT_OK) {
    std::printf("bands\n  not prepared\n");
    return;
  }
  print_band_info(info);
  print_rest_band_energies(g);
}

}  // namespace

int run_prepare(const Args& args) {
  GarmentPtr garment = load(args);
  print_report(report_of(garment.get()));

  pleat_prepare_options o{};
  o.struct_size = sizeof o;
  o.solver = parse_choice(args, "solver", {"auto", "dense", "slicing", "hybrid"});
  o.projection = parse_choice(args, "projection", {"random-walk", "symmetric"});
  o.low_fraction = args.number("low-fraction", 0.0);
  o.mid_fraction = args.number("mid-fraction", 0.0);
  o.geodesic_radius = args.number("geodesic-radius", 0.0);
  const auto start = std::chrono::steady_clock::now();
  check(pleat_garment_prepare(garment.get(), &o), "preparing");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_prepared(garment.get());
  std::printf("prepared in %.3f s\n", seconds);

  if (args.has("output")) {
    check(pleat_garment_save(garment.get(), args.get("output").c_str()),
          "saving '" + args.get("output") + "'");
    std::printf("wrote %s\n", args.get("output").c_str());
  }
  return 0;
}

int run_inspect(const Args& args) {
  const std::string path = args.positional.empty() ? "" : args.positional[0];
  if (path.size() > 6 && path.compare(path.size() - 6, 6, ".pleat") == 0) {
    pleat_model* m = nullptr;
    check(pleat_model_load(path.c_str(), &m), "loading the model '" + path + "'");
    ModelPtr model(m, pleat_model_destroy);
    print_model_info(model.get());
    return 0;
  }
  GarmentPtr garment = load(args);
  print_report(report_of(garment.get()));
  print_prepared(garment.get());
  return 0;
}

}  // namespace pleat_cli
