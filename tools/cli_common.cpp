#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "cli.h"

namespace pleat_cli {

std::string Args::get(const std::string& name, const std::string& fallback) const {
  auto it = options.find(name);
  return it == options.end() ? fallback : it->second;
}

double Args::number(const std::string& name, double fallback) const {
  auto it = options.find(name);
  if (it == options.end()) return fallback;
  char* end = nullptr;
  double value = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !std::isfinite(value))
    throw CliError{"option --" + name + " expects a number, got '" + it->second + "'", 2};
  return value;
}

Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& flags) {
  Args args;
  for (int i = first; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-o") a = "--output";
    if (a.rfind("--", 0) == 0 && a.size() > 2) {
      std::string name = a.substr(2);
      bool is_flag = false;
      for (const auto& f : flags) is_flag |= (f == name);
      if (is_flag) {
        args.options[name] = "1";
      } else {
        if (i + 1 >= argc) throw CliError{"option --" + name + " needs a value", 2};
        args.options[name] = argv[++i];
      }
    } else {
      args.positional.push_back(a);
    }
  }
  return args;
}

void check(pleat_status status, const std::string& what) {
  if (status != PLEAT_OK)
    throw CliError{what + " failed (" + pleat_status_name(status) + "): " + pleat_last_error()};
}

pleat_mesh_report report_of(const pleat_garment* garment) {
  pleat_mesh_report r{};
  r.struct_size = sizeof r;
  check(pleat_garment_get_report(garment, &r), "reading the report");
  return r;
}

void print_report(const pleat_mesh_report& r) {
  static const char* units[] = {"metres", "centimetres? (use --unit-scale 0.01)",
                                "millimetres? (use --unit-scale 0.001)"};
  std::printf("mesh\n");
  std::printf("  vertices            %u (from %u in the file, %u welded)\n", r.vertex_count,
              r.input_vertex_count, r.welded_vertex_count);
  std::printf("  triangles           %u (%u degenerate dropped)\n", r.triangle_count,
              r.degenerate_triangle_count);
  std::printf("  components          %u\n", r.component_count);
  std::printf("  boundary loops      %u\n", r.boundary_loop_count);
  std::printf("  non-manifold edges  %u\n", r.non_manifold_edge_count);
  std::printf("  isolated vertices   %u\n", r.isolated_vertex_count);
  std::printf("  bounding box        [%.4g %.4g %.4g] .. [%.4g %.4g %.4g]\n", r.bbox_min[0], r.bbox_min[1],
              r.bbox_min[2], r.bbox_max[0], r.bbox_max[1], r.bbox_max[2]);
  std::printf("  area                %.6g m^2\n", r.total_area);
  std::printf("  units look like     %s\n", r.units <= 2 ? units[r.units] : "?");
}

void print_band_info(const pleat_band_info& b) {
  static const char* solvers[] = {"auto", "dense", "slicing", "hybrid"};
  static const char* forms[] = {"random-walk", "symmetric"};
  std::printf("bands\n");
  std::printf("  solver              %s\n", b.solver <= 3 ? solvers[b.solver] : "?");
  std::printf("  projection          %s\n", b.projection <= 1 ? forms[b.projection] : "?");
  std::printf("  low eigenvectors    %u (requested %u, gap %.3g)\n", b.low_count, b.low_count_requested,
              b.low_gap);
  std::printf("  mid eigenvectors    %u (requested %u, gap %.3g)\n", b.mid_count, b.mid_count_requested,
              b.mid_gap);
  std::printf("  geodesic radius     %.3g m, %llu neighbour pairs\n", b.geodesic_radius,
              static_cast<unsigned long long>(b.geodesic_pair_count));
}

void print_rest_band_energies(const pleat_garment* garment) {
  const pleat_mesh_report r = report_of(garment);
  const size_t n = r.vertex_count * size_t{3};
  std::vector<float> rest(n), low(n), mid(n), high(n);
  check(pleat_garment_get_mesh(garment, rest.data(), n, nullptr, 0), "reading the mesh");
  check(pleat_garment_split_bands(garment, {rest.data(), 0}, 1, {low.data(), 0}, {mid.data(), 0},
                                  {high.data(), 0}),
        "splitting the rest shape into bands");
  auto rms = [&](const std::vector<float>& x) {
    double s = 0.0;
    for (float v : x) s += double(v) * v;
    return std::sqrt(s / r.vertex_count);
  };
  std::printf("rest shape band energy (RMS per vertex, m)\n");
  std::printf("  low %.6g   mid %.6g   high %.6g\n", rms(low), rms(mid), rms(high));
}

}  // namespace pleat_cli
