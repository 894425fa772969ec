// Metrics cost per frame on a ~5k-vertex garment-like sheet, and the gain of
// the self-collision pre-filter (BVH over face boxes) over the brute-force
// edge x face scan. Prints medians; not a test.
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "core/topology.h"
#include "metrics/metrics.h"
#include "metrics/self_collision.h"

namespace {

using Clock = std::chrono::steady_clock;

// Median wall time of `runs` calls, in milliseconds.
double median_ms(int runs, const std::function<void()>& fn) {
  std::vector<double> times;
  for (int i = 0; i < runs; ++i) {
    auto start = Clock::now();
    fn();
    times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

// A 71 x 71 sheet at 1 cm spacing (5041 vertices) draped in folds; `frames`
// frames of it with a few millimetres of noise as the "prediction", enough to
// fold some faces through each other.
struct Scene {
  pleat::Triangles triangles;
  int32_t vertex_count = 0;
  std::vector<float> truth, predicted;
};

Scene make_scene(int side, size_t frames) {
  Scene s;
  s.vertex_count = side * side;
  std::vector<int32_t> tri;
  for (int j = 0; j + 1 < side; ++j)
    for (int i = 0; i + 1 < side; ++i) {
      int32_t a = j * side + i, b = a + 1, c = a + side + 1, d = a + side;
      tri.insert(tri.end(), {a, b, c, a, c, d});
    }
  s.triangles = Eigen::Map<pleat::Triangles>(tri.data(), static_cast<Eigen::Index>(tri.size() / 3), 3);
  std::mt19937 rng(1);
  std::normal_distribution<float> noise(0.0f, 0.003f);
  for (size_t f = 0; f < frames; ++f)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        float x = 0.01f * static_cast<float>(i), y = 0.01f * static_cast<float>(j);
        float z = 0.05f * std::sin(12.0f * x + 0.1f * static_cast<float>(f)) * std::cos(7.0f * y);
        for (float v : {x, y, z}) {
          s.truth.push_back(v);
          s.predicted.push_back(v + noise(rng));
        }
      }
  return s;
}

}  // namespace

int main() {
  const size_t frames = 16;
  Scene s = make_scene(71, frames);
  std::printf("mesh: %d vertices, %ld triangles, %zu frames\n", s.vertex_count,
              static_cast<long>(s.triangles.rows()), frames);

  auto per_frame = [&](uint32_t flags) {
    pleat::MetricsOptions options;
    options.flags = flags;
    return median_ms(7,
                     [&] {
                       pleat::compute_metrics(s.triangles, s.vertex_count, s.predicted.data(), 0,
                                              s.truth.data(), 0, frames, options, nullptr);
                     }) /
           static_cast<double>(frames);
  };
  struct Row {
    const char* name;
    uint32_t flags;
  };
  for (Row row : {Row{"all (no bands)", 0u}, Row{"E_verts", PLEAT_METRIC_VERTEX},
                  Row{"E_vnorm + E_fnorm", PLEAT_METRIC_NORMALS}, Row{"E_edge", PLEAT_METRIC_EDGES},
                  Row{"E_curv", PLEAT_METRIC_CURVATURE}, Row{"self-collision", PLEAT_METRIC_SELF_COLLISION}})
    std::printf("%-20s %8.3f ms/frame\n", row.name, per_frame(row.flags));

  pleat::Points3d x = Eigen::Map<const pleat::Points3f>(s.predicted.data(), s.vertex_count, 3).cast<double>();
  std::vector<pleat::Edge> edges = pleat::unique_edges(s.triangles);
  std::vector<uint8_t> hit_tree, hit_brute;
  double tree = median_ms(9, [&] { hit_tree = pleat::self_intersected_faces(x, s.triangles, edges, 0.015); });
  double brute = median_ms(3, [&] {
    hit_brute =
        pleat::self_intersected_faces(x, s.triangles, edges, 0.015, pleat::CollisionSearch::brute_force);
  });
  std::printf(
      "self-collision, one frame: BVH pre-filter %.3f ms, brute force %.1f ms "
      "(%.0fx); %ld faces hit, %s\n",
      tree, brute, brute / tree, static_cast<long>(std::count(hit_tree.begin(), hit_tree.end(), 1)),
      hit_tree == hit_brute ? "same faces" : "DIFFERENT FACES");
  return hit_tree == hit_brute ? 0 : 1;
}
