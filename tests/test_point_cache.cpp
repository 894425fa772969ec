// Point caches (PC2, MDD, OBJ sequence) and the atomic writes behind them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/obj_writer.h"
#include "io/point_cache.h"
#include "support/expect_error.h"
#include "support/test_support.h"

namespace pleat {
namespace {

namespace fs = std::filesystem;

using pleat_test::expect_error;

std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// Byte builders written independently of the library's encoder.
void put_le(std::vector<unsigned char>* b, uint32_t u) {
  for (int k = 0; k < 4; ++k) b->push_back(static_cast<unsigned char>((u >> (8 * k)) & 0xff));
}
void put_be(std::vector<unsigned char>* b, uint32_t u) {
  for (int k = 3; k >= 0; --k) b->push_back(static_cast<unsigned char>((u >> (8 * k)) & 0xff));
}
uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

std::vector<unsigned char> pc2_bytes(int32_t points, float start, float rate, int32_t samples,
                                     const std::vector<float>& values) {
  const char magic[12] = "POINTCACHE2";  // the 12th byte is the terminating NUL
  std::vector<unsigned char> b(magic, magic + 12);
  put_le(&b, 1);
  put_le(&b, static_cast<uint32_t>(points));
  put_le(&b, bits(start));
  put_le(&b, bits(rate));
  put_le(&b, static_cast<uint32_t>(samples));
  for (float v : values) put_le(&b, bits(v));
  return b;
}

std::vector<unsigned char> mdd_bytes(int32_t frames, int32_t points, const std::vector<float>& times,
                                     const std::vector<float>& values) {
  std::vector<unsigned char> b;
  put_be(&b, static_cast<uint32_t>(frames));
  put_be(&b, static_cast<uint32_t>(points));
  for (float t : times) put_be(&b, bits(t));
  for (float v : values) put_be(&b, bits(v));
  return b;
}

// Random frames with awkward floats (negative zero, subnormals, large values)
// so that any lossy step breaks bit equality.
std::vector<float> random_frames(size_t frames, size_t vertices, size_t stride) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::vector<float> x(frames * stride, 12345.0f);  // padding between frames
  for (size_t f = 0; f < frames; ++f)
    for (size_t i = 0; i < 3 * vertices; ++i) x[f * stride + i] = u(rng);
  x[0] = -0.0f;
  x[1] = std::numeric_limits<float>::denorm_min();
  x[2] = 3.0e38f;
  return x;
}

Triangles two_triangles() {
  Triangles t(2, 3);
  t << 0, 1, 2, 0, 2, 3;
  return t;
}

void expect_bit_equal(const float* a, size_t a_stride, const float* b, size_t b_stride, size_t frames,
                      size_t vertices) {
  for (size_t f = 0; f < frames; ++f)
    ASSERT_EQ(0, std::memcmp(a + f * a_stride, b + f * b_stride, 12 * vertices)) << "frame " << f;
}

class PointCache : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = pleat_test::temp_dir("point_cache"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  std::string dir_;
};

// ---- Round trips -----------------------------------------------------------

TEST_F(PointCache, RoundTripsEveryFormatBitExact) {
  const size_t frames = 5, vertices = 4, in_stride = 14, out_stride = 13;
  std::vector<float> x = random_frames(frames, vertices, in_stride);
  Triangles tri = two_triangles();
  for (auto [name, format] : {std::pair{"a.pc2", CacheFormat::pc2}, std::pair{"a.mdd", CacheFormat::mdd},
                              std::pair{"seq/a_###.obj", CacheFormat::obj_sequence}}) {
    SCOPED_TRACE(name);
    fs::create_directories(path("seq"));
    write_cache(path(name), CacheFormat::automatic, x.data(), frames, vertices, in_stride, 30.0, &tri);
    CacheHeader h = read_cache_header(path(name), CacheFormat::automatic);
    EXPECT_EQ(h.format, format);
    EXPECT_EQ(h.frame_count, 5);
    EXPECT_EQ(h.vertex_count, 4);
    EXPECT_NEAR(h.frame_rate, 30.0, 1e-4);
    EXPECT_EQ(h.start_time, 0.0);
    std::vector<float> y(frames * out_stride, -1.0f);
    read_cache(path(name), format, y.data(), out_stride, y.size());
    expect_bit_equal(x.data(), in_stride, y.data(), out_stride, frames, vertices);
    EXPECT_EQ(y[12], -1.0f) << "padding between frames must stay untouched";
  }
  EXPECT_EQ(files_in(path("seq")),
            (std::vector<std::string>{"a_000.obj", "a_001.obj", "a_002.obj", "a_003.obj", "a_004.obj"}));
}

TEST_F(PointCache, MddKeepsTheFrameRateInItsTimes) {
  std::vector<float> x = random_frames(50, 3, 9);
  write_cache(path("b.mdd"), CacheFormat::mdd, x.data(), 50, 3, 0, 24.0, nullptr);
  EXPECT_NEAR(read_cache_header(path("b.mdd"), CacheFormat::automatic).frame_rate, 24.0, 1e-4);
}

TEST_F(PointCache, PackedStrideZeroAndExactCapacity) {
  std::vector<float> x = random_frames(3, 2, 6);
  write_cache(path("c.pc2"), CacheFormat::pc2, x.data(), 3, 2, 0, 30.0, nullptr);
  std::vector<float> y(18);
  read_cache(path("c.pc2"), CacheFormat::pc2, y.data(), 0, y.size());
  expect_bit_equal(x.data(), 6, y.data(), 6, 3, 2);
}

// ---- Files built by hand ----------------------------------------------------

TEST_F(PointCache, ReadsAHandBuiltPc2) {
  // 2 points, 2 samples, start frame 12, a sample every half frame.
  std::vector<float> v = {1, 2, 3, 4, 5, 6, -1, -2, -3, 0.5f, 0.25f, 0.125f};
  write_bytes(path("h.pc2"), pc2_bytes(2, 12.0f, 0.5f, 2, v));
  CacheHeader h = read_cache_header(path("h.pc2"), CacheFormat::automatic);
  EXPECT_EQ(h.format, CacheFormat::pc2);
  EXPECT_EQ(h.frame_count, 2);
  EXPECT_EQ(h.vertex_count, 2);
  EXPECT_DOUBLE_EQ(h.frame_rate, 60.0);  // 30 fps frames / 0.5 frames per sample
  EXPECT_DOUBLE_EQ(h.start_time, 0.4);   // frame 12 at 30 fps
  std::vector<float> y(12);
  read_cache(path("h.pc2"), CacheFormat::pc2, y.data(), 0, y.size());
  EXPECT_EQ(y, v);
}

TEST_F(PointCache, ReadsAHandBuiltMdd) {
  std::vector<float> v = {1, 2, 3, -4, 5.5f, 6, 7, 8, 9, 10, 11, -12.25f};
  write_bytes(path("h.mdd"), mdd_bytes(2, 2, {1.0f, 1.04f}, v));
  CacheHeader h = read_cache_header(path("h.mdd"), CacheFormat::mdd);
  EXPECT_EQ(h.frame_count, 2);
  EXPECT_EQ(h.vertex_count, 2);
  EXPECT_NEAR(h.frame_rate, 25.0, 1e-3);
  EXPECT_NEAR(h.start_time, 1.0, 1e-7);
  std::vector<float> y(12);
  read_cache(path("h.mdd"), CacheFormat::mdd, y.data(), 0, y.size());
  EXPECT_EQ(y, v);
}

TEST_F(PointCache, WriterMatchesTheHandBuiltLayout) {
  std::vector<float> v = {1, 2, 3, 4, 5, 6};
  write_cache(path("w.pc2"), CacheFormat::pc2, v.data(), 2, 1, 0, 30.0, nullptr);
  write_cache(path("w.mdd"), CacheFormat::mdd, v.data(), 2, 1, 0, 25.0, nullptr);
  auto file_bytes = [](const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(file_bytes(path("w.pc2")), pc2_bytes(1, 0.0f, 1.0f, 2, v));
  EXPECT_EQ(file_bytes(path("w.mdd")), mdd_bytes(2, 1, {0.0f, 0.04f}, v));
}

// ---- Hostile and broken files -----------------------------------------------

TEST_F(PointCache, RejectsBrokenPc2) {
  std::vector<float> v(6, 1.0f);
  std::vector<unsigned char> good = pc2_bytes(1, 0, 1, 2, v);
  float y[6];
  auto read = [&](const std::string& name) {
    return [&, name] { read_cache(path(name), CacheFormat::pc2, y, 0, 6); };
  };
  std::vector<unsigned char> b = good;
  b.pop_back();
  write_bytes(path("trunc.pc2"), b);
  expect_error(read("trunc.pc2"), PLEAT_ERROR_FORMAT, "truncated");
  write_bytes(path("short.pc2"), {'P', 'O', 'I'});
  expect_error(read("short.pc2"), PLEAT_ERROR_FORMAT, "header");
  b = good;
  b.push_back(0);
  write_bytes(path("long.pc2"), b);
  expect_error(read("long.pc2"), PLEAT_ERROR_FORMAT, "trailing");
  b = good;
  b[0] = 'X';
  write_bytes(path("magic.pc2"), b);
  expect_error(read("magic.pc2"), PLEAT_ERROR_FORMAT, "magic");
  b = good;
  b[12] = 2;
  write_bytes(path("version.pc2"), b);
  expect_error(read("version.pc2"), PLEAT_ERROR_FORMAT, "version 2");
  write_bytes(path("huge.pc2"), pc2_bytes(INT32_MAX, 0, 1, INT32_MAX, {}));
  expect_error(read("huge.pc2"), PLEAT_ERROR_FORMAT, "exceed");
  write_bytes(path("big.pc2"), pc2_bytes(1 << 30, 0, 1, 1 << 20, {}));
  expect_error(read("big.pc2"), PLEAT_ERROR_FORMAT, "truncated");
  write_bytes(path("neg.pc2"), pc2_bytes(-3, 0, 1, 2, v));
  expect_error(read("neg.pc2"), PLEAT_ERROR_FORMAT, "points is -3");
  write_bytes(path("rate.pc2"), pc2_bytes(1, 0, 0.0f, 2, v));
  expect_error(read("rate.pc2"), PLEAT_ERROR_FORMAT, "sample rate");
  v[4] = std::nanf("");
  write_bytes(path("nan.pc2"), pc2_bytes(1, 0, 1, 2, v));
  expect_error(read("nan.pc2"), PLEAT_ERROR_FORMAT, "frame 1 vertex 0");
  expect_error(read("missing.pc2"), PLEAT_ERROR_IO, "missing.pc2");
  fs::create_directories(path("folder.pc2"));
  expect_error(read("folder.pc2"), PLEAT_ERROR_IO, "not a regular file");
}

TEST_F(PointCache, RejectsBrokenMdd) {
  std::vector<float> v(6, 1.0f);
  float y[6];
  auto read = [&](const std::string& name) {
    return [&, name] { read_cache(path(name), CacheFormat::mdd, y, 0, 6); };
  };
  std::vector<unsigned char> b = mdd_bytes(2, 1, {0, 1}, v);
  b.resize(b.size() - 3);
  write_bytes(path("trunc.mdd"), b);
  expect_error(read("trunc.mdd"), PLEAT_ERROR_FORMAT, "truncated");
  write_bytes(path("huge.mdd"), mdd_bytes(INT32_MAX, INT32_MAX, {}, {}));
  expect_error(read("huge.mdd"), PLEAT_ERROR_FORMAT, "exceed");
  write_bytes(path("neg.mdd"), mdd_bytes(-1, 1, {}, {}));
  expect_error(read("neg.mdd"), PLEAT_ERROR_FORMAT, "frames is -1");
  write_bytes(path("time.mdd"), mdd_bytes(2, 1, {0, INFINITY}, v));
  expect_error(read("time.mdd"), PLEAT_ERROR_FORMAT, "times[1]");
  v[5] = -INFINITY;
  write_bytes(path("inf.mdd"), mdd_bytes(2, 1, {0, 1}, v));
  expect_error(read("inf.mdd"), PLEAT_ERROR_FORMAT, "frame 1 vertex 0");
}

// No frames: nothing in the file bounds the point count, so reading must not
// size anything by it (found by fuzz_point_cache: 2^31 - 1 points made 24 GB
// of buffers for a 9-byte file).
TEST_F(PointCache, AnEmptyCacheOfManyPointsAllocatesNothing) {
  write_bytes(path("empty.mdd"), mdd_bytes(0, INT32_MAX, {}, {}));
  const CacheHeader h = read_cache(path("empty.mdd"), CacheFormat::mdd, nullptr, 0, 0);
  EXPECT_EQ(h.frame_count, 0);
  EXPECT_EQ(h.vertex_count, INT32_MAX);
}

TEST_F(PointCache, FailedReadsLeaveTheBufferUntouched) {
  std::vector<float> v = {1, 2, 3, 4, 5, 6, 7, 8, std::nanf("")};
  write_bytes(path("nan.pc2"), pc2_bytes(1, 0, 1, 3, v));
  std::vector<float> y(9, 42.0f);
  expect_error([&] { read_cache(path("nan.pc2"), CacheFormat::pc2, y.data(), 0, 9); }, PLEAT_ERROR_FORMAT,
               "frame 2");
  EXPECT_EQ(y, std::vector<float>(9, 42.0f));
  v[8] = 9;
  write_bytes(path("ok.pc2"), pc2_bytes(1, 0, 1, 3, v));
  expect_error([&] { read_cache(path("ok.pc2"), CacheFormat::pc2, y.data(), 4, 9); },
               PLEAT_ERROR_BUFFER_TOO_SMALL, "11 floats");
  expect_error([&] { read_cache(path("ok.pc2"), CacheFormat::pc2, y.data(), 2, 9); },
               PLEAT_ERROR_INVALID_ARGUMENT, "stride");
  EXPECT_EQ(y, std::vector<float>(9, 42.0f));
}

// ---- Writing ----------------------------------------------------------------

TEST_F(PointCache, RejectedWritesLeaveNothingBehind) {
  std::vector<float> x = random_frames(3, 4, 12);
  x[2 * 12 + 7] = std::nanf("");
  Triangles tri = two_triangles();
  for (const char* name : {"n.pc2", "n.mdd", "n_##.obj"})
    expect_error([&] { write_cache(path(name), CacheFormat::automatic, x.data(), 3, 4, 0, 30, &tri); },
                 PLEAT_ERROR_INVALID_ARGUMENT, "frame 2 vertex 2");
  x[2 * 12 + 7] = 0.0f;
  expect_error(
      [&] { write_cache(path("t_#.obj"), CacheFormat::obj_sequence, x.data(), 3, 4, 0, 30, nullptr); },
      PLEAT_ERROR_INVALID_ARGUMENT, "triangles");
  Triangles bad = tri;
  bad(1, 2) = 4;
  expect_error([&] { write_cache(path("t_#.obj"), CacheFormat::obj_sequence, x.data(), 3, 4, 0, 30, &bad); },
               PLEAT_ERROR_INVALID_ARGUMENT, "triangle 1 corner 2");
  expect_error([&] { write_cache(path("r.mdd"), CacheFormat::mdd, x.data(), 3, 4, 0, 0.0, nullptr); },
               PLEAT_ERROR_INVALID_ARGUMENT, "frame_rate");
  expect_error([&] { write_cache(path("z.pc2"), CacheFormat::pc2, x.data(), 0, 4, 0, 30, nullptr); },
               PLEAT_ERROR_INVALID_ARGUMENT, "0 frames");
  expect_error(
      [&] { write_cache(path("no_pattern.obj"), CacheFormat::automatic, x.data(), 3, 4, 0, 30, &tri); },
      PLEAT_ERROR_INVALID_ARGUMENT, "'#'");
  expect_error([&] { write_cache(path("nodir/a.pc2"), CacheFormat::pc2, x.data(), 3, 4, 0, 30, nullptr); },
               PLEAT_ERROR_IO, "nodir/a.pc2");
  EXPECT_TRUE(files_in(dir_).empty()) << "left behind: " << files_in(dir_).front();
}

TEST_F(PointCache, AtomicFileCommitsOrLeavesNothing) {
  {
    AtomicFile file(path("a.txt"));
    file.write("half");
    EXPECT_TRUE(fs::exists(file.temp_path()));
    EXPECT_FALSE(fs::exists(path("a.txt")));
  }  // no commit: the temporary goes away
  EXPECT_TRUE(files_in(dir_).empty());
  write_bytes(path("a.txt"), {'o', 'l', 'd'});
  {
    AtomicFile file(path("a.txt"));
    file.write(std::string(3 << 20, 'x'));  // larger than the buffer
    file.write("!");
    file.commit();
  }
  EXPECT_EQ(fs::file_size(path("a.txt")), (3u << 20) + 1);
  EXPECT_EQ(files_in(dir_), std::vector<std::string>{"a.txt"});
  expect_error([&] { AtomicFile file(path("missing/a.txt")); }, PLEAT_ERROR_IO, "missing/a.txt");
}

TEST_F(PointCache, ObjWriterWritesNormalsAndOneBasedFaces) {
  std::vector<float> x = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  std::vector<float> n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  write_obj(path("m.obj"), x.data(), 4, two_triangles(), n.data());
  std::ifstream in(path("m.obj"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("v 1 1 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("vn 0 0 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("f 1//1 3//3 4//4\n"), std::string::npos) << text;
}

// ---- OBJ sequences ----------------------------------------------------------

TEST_F(PointCache, ObjSequencePattern) {
  EXPECT_EQ(obj_sequence_frame_path("out/shirt_####.obj", 7), "out/shirt_0007.obj");
  EXPECT_EQ(obj_sequence_frame_path("out/shirt_##.obj", 12345), "out/shirt_12345.obj");
  EXPECT_EQ(obj_sequence_frame_path("take#2/shirt_#.obj", 3), "take#2/shirt_3.obj");
  expect_error([] { obj_sequence_frame_path("shirt.obj", 0); }, PLEAT_ERROR_INVALID_ARGUMENT, "shirt.obj");
  EXPECT_EQ(resolve_cache_format("A.PC2", CacheFormat::automatic), CacheFormat::pc2);
  EXPECT_EQ(resolve_cache_format("a.Mdd", CacheFormat::automatic), CacheFormat::mdd);
  EXPECT_EQ(resolve_cache_format("a_##.obj", CacheFormat::automatic), CacheFormat::obj_sequence);
  EXPECT_EQ(resolve_cache_format("a.pc2", CacheFormat::mdd), CacheFormat::mdd);
  expect_error([] { resolve_cache_format("a.pc2", static_cast<CacheFormat>(9)); },
               PLEAT_ERROR_INVALID_ARGUMENT, "9");
}

TEST_F(PointCache, ShorterObjSequenceReplacesALongerOne) {
  std::vector<float> x = random_frames(4, 4, 12);
  Triangles tri = two_triangles();
  write_cache(path("s_#.obj"), CacheFormat::obj_sequence, x.data(), 4, 4, 0, 30, &tri);
  write_cache(path("s_#.obj"), CacheFormat::obj_sequence, x.data(), 2, 4, 0, 30, &tri);
  EXPECT_EQ(read_cache_header(path("s_#.obj"), CacheFormat::obj_sequence).frame_count, 2);
  EXPECT_EQ(files_in(dir_), (std::vector<std::string>{"s_0.obj", "s_1.obj"}));
}

TEST_F(PointCache, ObjSequenceStartingAtFrameOne) {
  // As Blender exports them: from the scene's first frame, with other lines.
  for (int f = 1; f <= 3; ++f) {
    std::ofstream out(obj_sequence_frame_path(path("b_######.obj"), f));
    out << "# Blender\nmtllib b.mtl\no Shirt\nv 1.5 +2 " << f << "\r\n\tv -1e-3 0 0 1.0\n"
        << "vt 0.5 0.5\nvn 0 0 1\nf 1/1/1 2/1/1 1/1/1\n";
  }
  CacheHeader h = read_cache_header(path("b_######.obj"), CacheFormat::automatic);
  EXPECT_EQ(h.frame_count, 3);
  EXPECT_EQ(h.vertex_count, 2);
  EXPECT_DOUBLE_EQ(h.start_time, 1.0 / 30.0);
  std::vector<float> y(18);
  read_cache(path("b_######.obj"), CacheFormat::obj_sequence, y.data(), 0, y.size());
  EXPECT_EQ(y[12], 1.5f);
  EXPECT_EQ(y[14], 3.0f);
  EXPECT_EQ(y[15], -1e-3f);
}

TEST_F(PointCache, RejectsBrokenObjSequences) {
  float y[64];
  expect_error([&] { read_cache_header(path("none_##.obj"), CacheFormat::obj_sequence); }, PLEAT_ERROR_IO,
               "none_00.obj");
  std::ofstream(path("c_0.obj")) << "v 0 0 0\nv 1 1 1\n";
  std::ofstream(path("c_1.obj")) << "v 0 0 0\n";
  expect_error([&] { read_cache(path("c_#.obj"), CacheFormat::obj_sequence, y, 0, 64); }, PLEAT_ERROR_FORMAT,
               "c_1.obj");
  std::ofstream(path("d_0.obj")) << "v 0 0 0\nv 1 x 1\n";
  expect_error([&] { read_cache_header(path("d_#.obj"), CacheFormat::obj_sequence); }, PLEAT_ERROR_FORMAT,
               "line 2");
  std::ofstream(path("e_0.obj")) << "v 0 0 0\nv 1 nan 1\n";
  expect_error([&] { read_cache_header(path("e_#.obj"), CacheFormat::obj_sequence); }, PLEAT_ERROR_FORMAT,
               "vertex 1");
  std::ofstream(path("f_0.obj")) << "f 1 2 3\n";
  expect_error([&] { read_cache_header(path("f_#.obj"), CacheFormat::obj_sequence); }, PLEAT_ERROR_FORMAT,
               "no 'v' lines");
}

}  // namespace
}  // namespace pleat
