// The garment part of the C API, used as a host would: loading, the report,
// bad input, preparation, band splits, and the prepared-garment file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <thread>

#include "capi/pleat.h"
#include "support/capi_support.h"

namespace {

using Garment = pleat_test::GarmentPtr;

pleat_garment* const kSentinel = reinterpret_cast<pleat_garment*>(0x1);

Garment create(const pleat_test::SimpleMesh& m) {
  return pleat_test::create_garment(m);
}

pleat_mesh_report report_of(const pleat_garment* g) {
  pleat_mesh_report r{};
  r.struct_size = sizeof r;
  EXPECT_EQ(pleat_garment_get_report(g, &r), PLEAT_OK) << pleat_last_error();
  return r;
}

void expect_error(pleat_status status, pleat_status expected, const std::string& text) {
  EXPECT_EQ(status, expected) << pleat_status_name(status) << ": " << pleat_last_error();
  EXPECT_NE(std::string(pleat_last_error()).find(text), std::string::npos)
      << "message '" << pleat_last_error() << "' lacks '" << text << "'";
}

std::string sample_dress() {
  return pleat_test::source_dir() + "/data/garments/female_elegantsuit01.obj";
}

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Splits frames through the C API; returns low, mid, high.
std::array<std::vector<float>, 3> split(const pleat_garment* g, const std::vector<float>& x, size_t frames) {
  std::array<std::vector<float>, 3> out;
  for (auto& o : out) o.assign(x.size(), 0.0f);
  EXPECT_EQ(pleat_garment_split_bands(g, {x.data(), 0}, frames, {out[0].data(), 0}, {out[1].data(), 0},
                                      {out[2].data(), 0}),
            PLEAT_OK)
      << pleat_last_error();
  return out;
}

}  // namespace

TEST(CapiGarment, LoadsTheSampleObjAndWeldsItsSeams) {
  // The OBJ has 2205 'v' lines; assimp splits them per UV, welding rejoins them.
  pleat_garment_load_options o{};
  o.struct_size = sizeof o;
  o.unit_scale = 0.1;  // MakeHuman stores decimetres
  pleat_garment* g = nullptr;
  ASSERT_EQ(pleat_garment_load(sample_dress().c_str(), &o, &g), PLEAT_OK) << pleat_last_error();
  Garment owner(g);
  pleat_mesh_report r = report_of(g);
  EXPECT_EQ(r.vertex_count, 2205u);
  EXPECT_GT(r.input_vertex_count, r.vertex_count);
  EXPECT_EQ(r.input_vertex_count - r.welded_vertex_count, r.vertex_count);
  EXPECT_EQ(r.triangle_count, 2u * 2096u);
  EXPECT_EQ(r.units, static_cast<uint32_t>(PLEAT_UNITS_METRES));
  EXPECT_NEAR(r.bbox_min[1], -0.299f, 1e-3f);

  pleat_garment* raw = nullptr;
  ASSERT_EQ(pleat_garment_load(sample_dress().c_str(), nullptr, &raw), PLEAT_OK);
  EXPECT_EQ(report_of(raw).units, static_cast<uint32_t>(PLEAT_UNITS_LOOK_LIKE_CENTIMETRES));
  pleat_garment_destroy(raw);
}

TEST(CapiGarment, BadInputGetsStatusAndMessage) {
  auto m = pleat_test::grid(3, 3, 0.1f);
  pleat_garment* g = kSentinel;
  expect_error(pleat_garment_load(nullptr, nullptr, &g), PLEAT_ERROR_INVALID_ARGUMENT, "'path' is NULL");
  expect_error(pleat_garment_load("/no/such/file.obj", nullptr, &g), PLEAT_ERROR_IO, "/no/such/file.obj");

  const std::string dir = pleat_test::temp_dir("capi_bad");
  write_bytes(dir + "/garbage.obj", {'h', 'e', 'l', 'l', 'o', '\n'});
  pleat_status s = pleat_garment_load((dir + "/garbage.obj").c_str(), nullptr, &g);
  EXPECT_TRUE(s == PLEAT_ERROR_FORMAT || s == PLEAT_ERROR_INVALID_MESH) << pleat_status_name(s);
  EXPECT_NE(std::string(pleat_last_error()).find("garbage.obj"), std::string::npos) << pleat_last_error();
  write_bytes(dir + "/empty.obj", {});
  s = pleat_garment_load((dir + "/empty.obj").c_str(), nullptr, &g);
  EXPECT_TRUE(s == PLEAT_ERROR_FORMAT || s == PLEAT_ERROR_INVALID_MESH) << pleat_status_name(s);

  expect_error(
      pleat_garment_create(m.positions.data(), 0, m.triangles.data(), m.triangle_count(), nullptr, &g),
      PLEAT_ERROR_INVALID_ARGUMENT, "triangles[0]");
  expect_error(pleat_garment_create(m.positions.data(), m.vertex_count(), m.triangles.data(), 0, nullptr, &g),
               PLEAT_ERROR_INVALID_MESH, "no triangles");
  auto nan = m;
  nan.positions[3 * 5 + 2] = std::numeric_limits<float>::quiet_NaN();
  expect_error(pleat_garment_create(nan.positions.data(), nan.vertex_count(), nan.triangles.data(),
                                    nan.triangle_count(), nullptr, &g),
               PLEAT_ERROR_INVALID_MESH, "vertex 5 has a non-finite z");
  auto huge = m;
  huge.positions[0] = 3e30f;
  expect_error(pleat_garment_create(huge.positions.data(), huge.vertex_count(), huge.triangles.data(),
                                    huge.triangle_count(), nullptr, &g),
               PLEAT_ERROR_INVALID_MESH, "vertex 0 x coordinate");
  auto out_of_range = m;
  out_of_range.triangles[7] = 42;
  expect_error(
      pleat_garment_create(out_of_range.positions.data(), out_of_range.vertex_count(),
                           out_of_range.triangles.data(), out_of_range.triangle_count(), nullptr, &g),
      PLEAT_ERROR_INVALID_ARGUMENT, "triangles[7] = 42");
  pleat_garment_load_options zero{};
  expect_error(pleat_garment_create(m.positions.data(), m.vertex_count(), m.triangles.data(),
                                    m.triangle_count(), &zero, &g),
               PLEAT_ERROR_INVALID_ARGUMENT, "struct_size");
  pleat_garment_load_options negative_scale{};
  negative_scale.struct_size = sizeof negative_scale;
  negative_scale.unit_scale = -1.0;
  expect_error(pleat_garment_create(m.positions.data(), m.vertex_count(), m.triangles.data(),
                                    m.triangle_count(), &negative_scale, &g),
               PLEAT_ERROR_INVALID_ARGUMENT, "unit_scale");
  EXPECT_EQ(g, kSentinel) << "outputs must stay untouched on failure";
}

TEST(CapiGarment, DisconnectedAndDuplicatedMeshesLoad) {
  auto panels = pleat_test::concat(pleat_test::grid(4, 4, 0.05f), pleat_test::grid(3, 3, 0.05f, {1, 0, 0}));
  // Duplicate the first panel's last row as a separate strip sharing positions.
  Garment g = create(panels);
  pleat_mesh_report r = report_of(g.get());
  EXPECT_EQ(r.component_count, 2u);
  EXPECT_EQ(r.boundary_loop_count, 2u);
}

TEST(CapiGarment, SplitBandsSumsToInputAndIgnoresTranslation) {
  auto m = pleat_test::concat(pleat_test::grid(12, 10, 0.03f),
                              pleat_test::mirrored_x(pleat_test::grid(12, 10, 0.03f, {0.1f, 0, 0})));
  Garment g = create(m);
  std::vector<float> x = m.positions;
  std::vector<float> dummy(x.size());
  expect_error(
      pleat_garment_split_bands(g.get(), {x.data(), 0}, 1, {dummy.data(), 0}, {nullptr, 0}, {nullptr, 0}),
      PLEAT_ERROR_NOT_PREPARED, "pleat_garment_prepare");
  ASSERT_EQ(pleat_garment_prepare(g.get(), nullptr), PLEAT_OK) << pleat_last_error();

  pleat_band_info info{};
  info.struct_size = sizeof info;
  ASSERT_EQ(pleat_garment_get_band_info(g.get(), &info), PLEAT_OK);
  EXPECT_EQ(info.vertex_count, 240u);
  EXPECT_EQ(info.low_count_requested, 8u);   // ceil(240 / 30)
  EXPECT_EQ(info.mid_count_requested, 48u);  // ceil(240 / 5)
  EXPECT_EQ(info.projection, static_cast<uint32_t>(PLEAT_PROJECTION_RANDOM_WALK));
  EXPECT_GT(info.geodesic_pair_count, 0u);

  // Two frames: the rest shape and a bumped copy, batched.
  std::vector<float> frames = x;
  for (size_t i = 0; i < x.size(); i += 3)
    frames.push_back(x[i]), frames.push_back(x[i + 1]),
        frames.push_back(x[i + 2] + 0.01f * std::sin(40.0f * x[i]));
  auto bands = split(g.get(), frames, 2);
  for (size_t i = 0; i < frames.size(); ++i)
    EXPECT_NEAR(bands[0][i] + bands[1][i] + bands[2][i], frames[i], 1e-6f) << i;

  std::vector<float> moved = frames;
  for (size_t i = 0; i < moved.size(); i += 3) moved[i] += 10.0f, moved[i + 1] -= 3.0f, moved[i + 2] += 7.0f;
  auto moved_bands = split(g.get(), moved, 2);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_NEAR(moved_bands[1][i], bands[1][i], 2e-5f) << "mid band moved with the garment at " << i;
    EXPECT_NEAR(moved_bands[2][i], bands[2][i], 2e-5f) << "high band moved with the garment at " << i;
  }
}

TEST(CapiGarment, SplitBandsHonoursStridesAndSkipsNullOutputs) {
  auto m = pleat_test::grid(10, 10, 0.03f);
  Garment g = create(m);
  ASSERT_EQ(pleat_garment_prepare(g.get(), nullptr), PLEAT_OK) << pleat_last_error();
  const size_t n = m.positions.size(), stride = n + 5;
  std::vector<float> in(2 * stride, -1.0f), high(2 * stride, 123.0f);
  std::copy(m.positions.begin(), m.positions.end(), in.begin());
  std::copy(m.positions.begin(), m.positions.end(), in.begin() + static_cast<long>(stride));
  ASSERT_EQ(pleat_garment_split_bands(g.get(), {in.data(), stride}, 2, {nullptr, 0}, {nullptr, 0},
                                      {high.data(), stride}),
            PLEAT_OK)
      << pleat_last_error();
  auto packed = split(g.get(), m.positions, 1);
  for (size_t i = 0; i < n; ++i) {
    // Same values up to round-off: a two-frame GEMM may sum in another order.
    EXPECT_NEAR(high[i], packed[2][i], 1e-6f);
    EXPECT_NEAR(high[stride + i], packed[2][i], 1e-6f);
  }
  EXPECT_EQ(high[n], 123.0f) << "padding between frames must stay untouched";
  std::vector<float> bad = m.positions;
  bad[17] = std::numeric_limits<float>::infinity();
  expect_error(
      pleat_garment_split_bands(g.get(), {bad.data(), 0}, 1, {high.data(), 0}, {nullptr, 0}, {nullptr, 0}),
      PLEAT_ERROR_INVALID_ARGUMENT, "frame 0 vertex 5");
  expect_error(
      pleat_garment_split_bands(g.get(), {in.data(), 7}, 1, {high.data(), 0}, {nullptr, 0}, {nullptr, 0}),
      PLEAT_ERROR_INVALID_ARGUMENT, "positions.frame_stride");
}

TEST(CapiGarment, PreparedFileRoundTripsBitExactly) {
  pleat_garment_load_options o{};
  o.struct_size = sizeof o;
  o.unit_scale = 0.1;
  pleat_garment* g = nullptr;
  ASSERT_EQ(pleat_garment_load(sample_dress().c_str(), &o, &g), PLEAT_OK) << pleat_last_error();
  Garment original(g);
  ASSERT_EQ(pleat_garment_prepare(g, nullptr), PLEAT_OK) << pleat_last_error();
  const std::string dir = pleat_test::temp_dir("capi_roundtrip");
  const std::string a = dir + "/a.pleatg", b = dir + "/b.pleatg";
  ASSERT_EQ(pleat_garment_save(g, a.c_str()), PLEAT_OK) << pleat_last_error();

  pleat_garment* loaded = nullptr;
  ASSERT_EQ(pleat_garment_load(a.c_str(), nullptr, &loaded), PLEAT_OK) << pleat_last_error();
  Garment reloaded(loaded);
  ASSERT_EQ(pleat_garment_save(loaded, b.c_str()), PLEAT_OK) << pleat_last_error();
  EXPECT_EQ(read_bytes(a), read_bytes(b));

  pleat_band_info i1{}, i2{};
  i1.struct_size = i2.struct_size = sizeof i1;
  pleat_garment_get_band_info(g, &i1);
  pleat_garment_get_band_info(loaded, &i2);
  EXPECT_EQ(std::memcmp(&i1, &i2, sizeof i1), 0);
  const pleat_mesh_report r1 = report_of(g), r2 = report_of(loaded);
  EXPECT_EQ(std::memcmp(&r1, &r2, sizeof r1), 0);

  const size_t n = report_of(g).vertex_count * 3;
  std::vector<float> rest(n);
  ASSERT_EQ(pleat_garment_get_mesh(g, rest.data(), n, nullptr, 0), PLEAT_OK);
  EXPECT_EQ(split(g, rest, 1), split(loaded, rest, 1));
}

TEST(CapiGarment, HostilePreparedFilesAreRefusedWithoutCrash) {
  auto m = pleat_test::grid(8, 8, 0.05f);
  Garment g = create(m);
  ASSERT_EQ(pleat_garment_prepare(g.get(), nullptr), PLEAT_OK) << pleat_last_error();
  const std::string dir = pleat_test::temp_dir("capi_hostile");
  const std::string good = dir + "/good.pleatg", bad = dir + "/bad.pleatg";
  ASSERT_EQ(pleat_garment_save(g.get(), good.c_str()), PLEAT_OK);
  const std::vector<char> bytes = read_bytes(good);

  // Every truncation is refused as a format error.
  for (size_t len = 8; len < bytes.size(); len += 7) {
    write_bytes(bad, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(len)));
    pleat_garment* h = kSentinel;
    pleat_status s = pleat_garment_load(bad.c_str(), nullptr, &h);
    ASSERT_NE(s, PLEAT_OK) << "truncated to " << len;
    EXPECT_EQ(h, kSentinel);
  }
  // Random bit flips: refused, or (a flip inside float data) loaded and usable.
  std::mt19937 rng(7);
  int refused = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<char> flipped = bytes;
    size_t at = rng() % flipped.size();
    flipped[at] = static_cast<char>(flipped[at] ^ (1 << (rng() % 8)));
    write_bytes(bad, flipped);
    pleat_garment* h = nullptr;
    pleat_status s = pleat_garment_load(bad.c_str(), nullptr, &h);
    if (s != PLEAT_OK) {
      ++refused;
      EXPECT_TRUE(s == PLEAT_ERROR_FORMAT || s == PLEAT_ERROR_UNSUPPORTED_VERSION)
          << pleat_status_name(s) << " at byte " << at << ": " << pleat_last_error();
      continue;
    }
    Garment owner(h);
    pleat_mesh_report r = report_of(h);
    std::vector<float> rest(r.vertex_count * 3);
    ASSERT_EQ(pleat_garment_get_mesh(h, rest.data(), rest.size(), nullptr, 0), PLEAT_OK);
    auto out = split(h, rest, 1);
    for (const auto& band : out)
      for (float v : band) ASSERT_TRUE(std::isfinite(v)) << "flip at byte " << at;
  }
  EXPECT_GT(refused, 0);
}

TEST(CapiGarment, SharedGarmentSplitsIdenticallyOnManyThreads) {
  auto m = pleat_test::grid(20, 20, 0.02f);
  Garment g = create(m);
  ASSERT_EQ(pleat_garment_prepare(g.get(), nullptr), PLEAT_OK);
  const auto expected = split(g.get(), m.positions, 1);
  std::vector<std::thread> threads;
  std::vector<int> same(4, 0);
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 20; ++k) same[t] += split(g.get(), m.positions, 1) == expected;
    });
  for (auto& t : threads) t.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(same[t], 20);
}
