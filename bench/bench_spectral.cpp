// Band basis preparation per solver and band split throughput.
// Usage: bench_spectral [--quick | --large-only] [--hybrid-large] [obj files...]  (prints medians)
// --quick skips the 20k mesh; --large-only runs only the 20k mesh; --hybrid-large
// adds the hybrid solver at 20k, which takes over 10 minutes (docs/spectral.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/topology.h"
#include "garment/garment.h"
#include "io/mesh_import.h"
#include "spectral/band_split.h"
#include "spectral/bands.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A garment-like test mesh: a torso tube and two mirrored sleeve tubes (the
// sleeves make exactly repeated eigenvalues, like real symmetric garments).
struct Mesh {
  std::vector<pleat::Edge> edges;
  std::vector<float> positions;
  int32_t vertex_count = 0;
};

void add_tube(Mesh* mesh, int around, int along, float radius, float x0, float mirror) {
  const int32_t base = mesh->vertex_count;
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const float a = 6.2831853f * static_cast<float>(i) / static_cast<float>(around);
      mesh->positions.insert(mesh->positions.end(), {mirror * (x0 + radius * std::cos(a)),
                                                     0.02f * static_cast<float>(j), radius * std::sin(a)});
    }
  auto id = [&](int i, int j) { return base + j * around + (i % around); };
  for (int j = 0; j + 1 < along; ++j)
    for (int i = 0; i < around; ++i) {
      for (auto [a, b] : {std::pair{id(i, j), id(i + 1, j)}, std::pair{id(i, j), id(i, j + 1)},
                          std::pair{id(i, j), id(i + 1, j + 1)}})
        mesh->edges.push_back({std::min(a, b), std::max(a, b)});
    }
  for (int i = 0; i < around; ++i) {
    const int32_t a = id(i, along - 1), b = id(i + 1, along - 1);
    mesh->edges.push_back({std::min(a, b), std::max(a, b)});
  }
  mesh->vertex_count += around * along;
}

Mesh garment(int scale) {  // scale 1: 5000 vertices, scale 2: 20000
  Mesh m;
  add_tube(&m, 60 * scale, 50 * scale, 1.0f, 0.0f, 1.0f);
  add_tube(&m, 20 * scale, 50 * scale, 0.3f, 1.5f, 1.0f);
  add_tube(&m, 20 * scale, 50 * scale, 0.3f, 1.5f, -1.0f);
  std::sort(m.edges.begin(), m.edges.end());
  m.edges.erase(std::unique(m.edges.begin(), m.edges.end()), m.edges.end());
  return m;
}

// A garment file through the project's own loader (welded, triangulated).
bool read_garment(const std::string& path, Mesh* mesh) {
  try {
    const pleat::ImportedMesh imported = pleat::import_mesh(path);
    const pleat::Garment g = pleat::build_garment(imported.vertices, imported.triangles, {}, path);
    mesh->edges = g.edges;
    mesh->vertex_count = g.rest.vertex_count();
    const pleat::Points3f x = g.rest.vertices.cast<float>();
    mesh->positions.assign(x.data(), x.data() + x.size());
    return true;
  } catch (const pleat::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return false;
  }
}

const char* solver_name(pleat::SolverKind k) {
  switch (k) {
    case pleat::SolverKind::dense: return "dense";
    case pleat::SolverKind::slicing: return "slicing";
    case pleat::SolverKind::hybrid: return "hybrid";
    default: return "auto";
  }
}

pleat::BandBasis<double> prepare(const std::string& name, const Mesh& mesh, pleat::SolverKind kind) {
  const pleat::Csr graph = pleat::edge_graph(mesh.edges, mesh.vertex_count);
  pleat::BandOptions options;
  options.solver = kind;
  const auto start = Clock::now();
  pleat::BandBasis<double> basis = pleat::compute_band_basis(graph, options);
  std::printf("prepare  %-22s N %6d  %-8s %8.2f s  low %d/%d mid %d/%d  gaps %.2e %.2e\n", name.c_str(),
              mesh.vertex_count, solver_name(kind), seconds_since(start), basis.low_count,
              basis.low_requested, basis.mid_count, basis.mid_requested, basis.low_gap, basis.mid_gap);
  std::fflush(stdout);
  return basis;
}

void bench_split(const std::string& name, const pleat::BandBasis<double>& basis, const Mesh& mesh) {
  const pleat::BandBasis<float> b = basis.cast<float>();
  const size_t n3 = 3 * static_cast<size_t>(mesh.vertex_count);
  pleat::BandSplitScratch<float> scratch;
  for (size_t frames : {1, 8, 32}) {
    std::vector<float> in(frames * n3), low(in.size()), mid(in.size()), high(in.size());
    for (size_t f = 0; f < frames; ++f)
      std::copy(mesh.positions.begin(), mesh.positions.end(), in.begin() + f * n3);
    std::vector<double> per_frame;
    for (int repeat = 0; repeat < 15; ++repeat) {
      const auto start = Clock::now();
      pleat::split_bands<float>(b, in.data(), frames, n3, low.data(), n3, mid.data(), n3, high.data(), n3,
                                &scratch);
      per_frame.push_back(seconds_since(start) * 1e3 / static_cast<double>(frames));
    }
    std::printf("split    %-22s N %6d  float  %2zu frames  %7.3f ms/frame (median of 15)\n", name.c_str(),
                mesh.vertex_count, frames, median(per_frame));
  }
}

// Largest difference of the low and mid bands of the rest positions,
// relative to the largest coordinate.
void compare(const pleat::BandBasis<double>& reference, const pleat::BandBasis<double>& other,
             const Mesh& mesh) {
  const size_t n3 = 3 * static_cast<size_t>(mesh.vertex_count);
  std::vector<double> x(mesh.positions.begin(), mesh.positions.end()), a(2 * n3), b(2 * n3);
  pleat::split_bands<double>(reference, x.data(), 1, n3, a.data(), n3, a.data() + n3, n3, nullptr, 0);
  pleat::split_bands<double>(other, x.data(), 1, n3, b.data(), n3, b.data() + n3, n3, nullptr, 0);
  double diff = 0.0, norm = 0.0;
  for (size_t i = 0; i < 2 * n3; ++i) diff = std::max(diff, std::abs(a[i] - b[i]));
  for (double v : x) norm = std::max(norm, std::abs(v));
  std::printf("         bands vs dense: max difference / max |x| = %.2e\n", diff / norm);
}

// The 5k mesh with every solver (checked against dense) and the split; then
// each OBJ with dense and slicing.
void run_small(const std::vector<std::string>& objs) {
  const Mesh small = garment(1);
  const pleat::BandBasis<double> dense = prepare("synthetic-5k", small, pleat::SolverKind::dense);
  for (auto kind : {pleat::SolverKind::slicing, pleat::SolverKind::hybrid})
    compare(dense, prepare("synthetic-5k", small, kind), small);
  bench_split("synthetic-5k", dense, small);
  for (const std::string& path : objs) {
    Mesh mesh;
    if (!read_garment(path, &mesh)) {
      std::printf("cannot read %s\n", path.c_str());
      continue;
    }
    const std::string name = path.substr(path.find_last_of('/') + 1);
    const pleat::BandBasis<double> reference = prepare(name, mesh, pleat::SolverKind::dense);
    compare(reference, prepare(name, mesh, pleat::SolverKind::slicing), mesh);
    bench_split(name, reference, mesh);
  }
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, large_only = false, hybrid_large = false;
  std::vector<std::string> objs;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--large-only") == 0) {
      large_only = true;
    } else if (std::strcmp(argv[i], "--hybrid-large") == 0) {
      hybrid_large = true;
    } else {
      objs.push_back(argv[i]);
    }
  }
  if (!large_only) run_small(objs);
  if (!quick) {
    const Mesh large = garment(2);
    prepare("synthetic-20k", large, pleat::SolverKind::slicing);
    if (hybrid_large) prepare("synthetic-20k", large, pleat::SolverKind::hybrid);
  }
  return 0;
}
