// Metrics and point caches through the C API, as a host uses them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "capi/pleat.h"
#include "support/capi_support.h"

namespace {

using Garment = pleat_test::GarmentPtr;

Garment create(const pleat_test::SimpleMesh& m) {
  return pleat_test::create_garment(m);
}

pleat_metrics metrics(const pleat_garment* g, const std::vector<float>& pred, const std::vector<float>& truth,
                      size_t frames, uint32_t flags, pleat_status expected = PLEAT_OK) {
  pleat_metrics_options o{};
  o.struct_size = sizeof o;
  o.flags = flags;
  pleat_metrics m{};
  m.struct_size = sizeof m;
  EXPECT_EQ(pleat_metrics_compute(g, {pred.data(), 0}, {truth.data(), 0}, frames, &o, &m), expected)
      << pleat_last_error();
  return m;
}

}  // namespace

TEST(CapiMetrics, TranslationIsAllVertexErrorAndAllLowBand) {
  auto mesh = pleat_test::grid(15, 12, 0.02f);
  Garment g = create(mesh);
  std::vector<float> truth = mesh.positions, pred = mesh.positions;
  for (size_t i = 0; i < pred.size(); i += 3) pred[i + 1] += 0.03f;  // 3 cm up

  pleat_metrics same = metrics(g.get(), truth, truth, 1, 0);
  EXPECT_EQ(same.e_verts_cm, 0.0);
  EXPECT_EQ(same.e_edge_percent, 0.0);
  EXPECT_EQ(same.computed & PLEAT_METRIC_BANDS, 0u) << "bands need a prepared garment";

  pleat_metrics moved = metrics(g.get(), pred, truth, 1, 0);
  EXPECT_NEAR(moved.e_verts_cm, 3.0, 1e-4);
  EXPECT_NEAR(moved.e_fnorm_deg, 0.0, 1e-3);
  EXPECT_NEAR(moved.e_edge_percent, 0.0, 1e-3);
  EXPECT_EQ(moved.frame_count, 1u);

  metrics(g.get(), pred, truth, 1, PLEAT_METRIC_BANDS, PLEAT_ERROR_NOT_PREPARED);
  ASSERT_EQ(pleat_garment_prepare(g.get(), nullptr), PLEAT_OK) << pleat_last_error();
  pleat_metrics banded = metrics(g.get(), pred, truth, 1, 0);
  ASSERT_NE(banded.computed & PLEAT_METRIC_BANDS, 0u);
  EXPECT_NEAR(banded.e_low_cm, 3.0, 1e-3) << "a rigid shift is pure low band (random-walk form)";
  EXPECT_NEAR(banded.e_mid_cm, 0.0, 1e-3);
  EXPECT_NEAR(banded.e_high_cm, 0.0, 1e-3);
}

TEST(CapiMetrics, BadInputIsNamed) {
  auto mesh = pleat_test::grid(4, 4, 0.1f);
  Garment g = create(mesh);
  std::vector<float> pred = mesh.positions;
  pred[3 * 6 + 1] = NAN;
  metrics(g.get(), pred, mesh.positions, 1, 0, PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("vertex 6"), std::string::npos) << pleat_last_error();
  pleat_metrics out{};
  EXPECT_EQ(pleat_metrics_compute(g.get(), {nullptr, 0}, {mesh.positions.data(), 0}, 1, nullptr, &out),
            PLEAT_ERROR_INVALID_ARGUMENT);
}

TEST(CapiCache, Pc2RoundTripAndInfo) {
  auto mesh = pleat_test::grid(5, 4, 0.1f);
  const size_t n = mesh.vertex_count(), frames = 3;
  std::vector<float> x;
  for (size_t f = 0; f < frames; ++f)
    for (size_t i = 0; i < n * 3; ++i) x.push_back(mesh.positions[i] + 0.01f * static_cast<float>(f));
  const std::string dir = pleat_test::temp_dir("capi_cache");
  for (const char* name : {"/anim.pc2", "/anim.mdd"}) {
    const std::string path = dir + name;
    ASSERT_EQ(pleat_cache_write(path.c_str(), PLEAT_CACHE_AUTO, nullptr, {x.data(), 0}, frames, n, 24.0),
              PLEAT_OK)
        << pleat_last_error();
    pleat_cache_info info{};
    info.struct_size = sizeof info;
    ASSERT_EQ(pleat_cache_get_info(path.c_str(), PLEAT_CACHE_AUTO, &info), PLEAT_OK) << pleat_last_error();
    EXPECT_EQ(info.frame_count, frames);
    EXPECT_EQ(info.vertex_count, n);
    // PC2 stores no rate (its "sample rate" is frames per sample): 30 fps is
    // assumed. MDD stores float32 times, so the rate comes back to ~1e-7.
    if (std::string(name) == "/anim.pc2")
      EXPECT_DOUBLE_EQ(info.frame_rate, 30.0);
    else
      EXPECT_NEAR(info.frame_rate, 24.0, 1e-5);
    std::vector<float> back(x.size());
    ASSERT_EQ(pleat_cache_read(path.c_str(), PLEAT_CACHE_AUTO, {back.data(), 0}, back.size()), PLEAT_OK)
        << pleat_last_error();
    EXPECT_EQ(back, x) << name;
    std::vector<float> small(x.size() - 1);
    EXPECT_EQ(pleat_cache_read(path.c_str(), PLEAT_CACHE_AUTO, {small.data(), 0}, small.size()),
              PLEAT_ERROR_BUFFER_TOO_SMALL);
  }
}

TEST(CapiCache, ObjSequenceNeedsTheGarmentsFaces) {
  auto mesh = pleat_test::grid(3, 3, 0.1f);
  Garment g = create(mesh);
  const std::string pattern = pleat_test::temp_dir("capi_objseq") + "/frame_###.obj";
  EXPECT_EQ(pleat_cache_write(pattern.c_str(), PLEAT_CACHE_AUTO, nullptr, {mesh.positions.data(), 0}, 1,
                              mesh.vertex_count(), 30.0),
            PLEAT_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pleat_last_error()).find("garment"), std::string::npos);
  std::vector<float> two = mesh.positions;
  two.insert(two.end(), mesh.positions.begin(), mesh.positions.end());
  ASSERT_EQ(pleat_cache_write(pattern.c_str(), PLEAT_CACHE_AUTO, g.get(), {two.data(), 0}, 2,
                              mesh.vertex_count(), 30.0),
            PLEAT_OK)
      << pleat_last_error();
  pleat_cache_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_cache_get_info(pattern.c_str(), PLEAT_CACHE_AUTO, &info), PLEAT_OK) << pleat_last_error();
  EXPECT_EQ(info.frame_count, 2u);
  EXPECT_EQ(info.format, static_cast<uint32_t>(PLEAT_CACHE_OBJ_SEQUENCE));
  // A garment-loaded OBJ frame has the garment's topology.
  pleat_garment* frame = nullptr;
  ASSERT_EQ(pleat_garment_load(std::filesystem::path(pattern).replace_filename("frame_000.obj").c_str(),
                               nullptr, &frame),
            PLEAT_OK)
      << pleat_last_error();
  Garment owner(frame);
  pleat_mesh_report r{};
  r.struct_size = sizeof r;
  pleat_garment_get_report(frame, &r);
  EXPECT_EQ(r.vertex_count, mesh.vertex_count());
  EXPECT_EQ(r.triangle_count, mesh.triangle_count());
}
