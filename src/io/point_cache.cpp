#include "io/point_cache.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"
#include "io/gltf_cache.h"
#include "io/obj_writer.h"
#include "io/text_file.h"
#include "io/usda_cache.h"

namespace pleat {
namespace {

constexpr char kPc2Magic[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr int64_t kPc2HeaderBytes = 32;
constexpr int64_t kMddHeaderBytes = 8;
constexpr int64_t kPointBytes = 12;

std::string in_quotes(const std::string& path) {
  return "'" + path + "'";
}

[[noreturn]] void fail_format(const std::string& path, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, in_quotes(path) + ": " + what);
}

// ---- Byte order ------------------------------------------------------------
// Assembled from bytes, so the code is right on any host; compilers turn it
// into a plain (or byte-swapped) load.

uint32_t load_u32(const unsigned char* p, bool big_endian) {
  if (big_endian) return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | uint32_t{p[3]};
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

int32_t load_i32(const unsigned char* p, bool big_endian) {
  return static_cast<int32_t>(load_u32(p, big_endian));
}

float load_f32(const unsigned char* p, bool big_endian) {
  uint32_t u = load_u32(p, big_endian);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

void store_u32(uint32_t u, bool big_endian, std::vector<unsigned char>* out) {
  for (int k = 0; k < 4; ++k) {
    int shift = big_endian ? 24 - 8 * k : 8 * k;
    out->push_back(static_cast<unsigned char>(u >> shift));
  }
}

void store_i32(int64_t value, bool big_endian, std::vector<unsigned char>* out) {
  store_u32(static_cast<uint32_t>(static_cast<int32_t>(value)), big_endian, out);
}

void store_f32(float value, bool big_endian, std::vector<unsigned char>* out) {
  uint32_t u;
  std::memcpy(&u, &value, 4);
  store_u32(u, big_endian, out);
}

// ---- Files -----------------------------------------------------------------

void read_at(std::FILE* file, const std::string& path, int64_t offset, void* out, size_t bytes) {
  if (::fseeko(file, static_cast<off_t>(offset), SEEK_SET) != 0 || std::fread(out, 1, bytes, file) != bytes) {
    if (std::ferror(file)) fail(PLEAT_ERROR_IO, "cannot read " + in_quotes(path));
    fail_format(path, "truncated while reading (the file changed during the read?)");
  }
}

// The exact size a header promises; counts are int32, so the product can
// exceed int64 only through the multiplication, which is checked.
// frame_bytes: bytes per frame beyond the points (MDD's time).
void check_file_size(const std::string& path, int64_t actual, int64_t header_bytes, int64_t frame_bytes,
                     int64_t frames, int64_t points, const char* frame_word) {
  int64_t payload = 0;
  std::string counts =
      "(" + std::to_string(points) + " points, " + std::to_string(frames) + " " + frame_word + ")";
  if (__builtin_mul_overflow(points * kPointBytes + frame_bytes, frames, &payload) ||
      payload > INT64_MAX - header_bytes)
    fail_format(path, "header counts " + counts + " exceed any file size");
  int64_t expected = header_bytes + payload;
  if (actual < expected)
    fail_format(path, "truncated: " + std::to_string(actual) + " bytes, the header " + counts + " needs " +
                          std::to_string(expected));
  if (actual > expected)
    fail_format(path, std::to_string(actual - expected) + " bytes of trailing data after the " +
                          std::to_string(expected) + " the header " + counts + " describes");
}

void check_finite_frame(const std::string& path, int64_t frame, const float* xyz, int64_t vertex_count) {
  for (int64_t i = 0; i < 3 * vertex_count; ++i)
    if (!std::isfinite(xyz[i]))
      fail_format(path,
                  "frame " + std::to_string(frame) + " vertex " + std::to_string(i / 3) + " is not finite");
}

// ---- Readers ---------------------------------------------------------------
// A reader validates its header on construction and then decodes frames in any
// order; read_cache runs it twice (check everything, then copy) so the
// caller's buffer stays untouched when any frame is bad.

class FrameReader {
 public:
  virtual ~FrameReader() = default;
  const CacheHeader& header() const { return header_; }
  // Decodes frame f into dst (vertex_count * 3 floats); throws for bad data.
  virtual void read_frame(int64_t f, float* dst) = 0;

 protected:
  CacheHeader header_;
};

class BinaryReader : public FrameReader {
 public:
  BinaryReader(const std::string& path, CacheFormat format) : path_(path) {
    header_.format = format;
    int64_t size = 0;
    file_ = open_for_reading(path, &size);
    if (format == CacheFormat::pc2)
      read_pc2_header(size);
    else
      read_mdd_header(size);
    // One frame's bytes; a cache of no frames holds no data to bound the
    // point count with, so it gets no buffer.
    if (header_.frame_count > 0) bytes_.resize(static_cast<size_t>(header_.vertex_count * kPointBytes));
  }

  void read_frame(int64_t f, float* dst) override {
    read_at(file_.get(), path_, data_offset_ + f * header_.vertex_count * kPointBytes, bytes_.data(),
            bytes_.size());
    for (size_t i = 0; i < bytes_.size() / 4; ++i) dst[i] = load_f32(&bytes_[4 * i], big_endian_);
    check_finite_frame(path_, f, dst, header_.vertex_count);
  }

 private:
  void read_pc2_header(int64_t size) {
    unsigned char h[kPc2HeaderBytes];
    if (size < kPc2HeaderBytes)
      fail_format(path_, "truncated: " + std::to_string(size) + " bytes, shorter than the " +
                             std::to_string(kPc2HeaderBytes) + "-byte PC2 header");
    read_at(file_.get(), path_, 0, h, sizeof(h));
    if (std::memcmp(h, kPc2Magic, sizeof(kPc2Magic)) != 0)
      fail_format(path_, "not a PC2 file (no \"POINTCACHE2\" magic)");
    int32_t version = load_i32(h + 12, false);
    int32_t points = load_i32(h + 16, false);
    float start_frame = load_f32(h + 20, false);
    float sample_rate = load_f32(h + 24, false);
    int32_t samples = load_i32(h + 28, false);
    if (version != 1) fail_format(path_, "PC2 version " + std::to_string(version) + ", only 1 is defined");
    if (points <= 0) fail_format(path_, "PC2 points is " + std::to_string(points));
    if (samples < 0) fail_format(path_, "PC2 samples is " + std::to_string(samples));
    if (!std::isfinite(start_frame)) fail_format(path_, "PC2 start frame is not finite");
    if (!(std::isfinite(sample_rate) && sample_rate > 0.0f))
      fail_format(path_, "PC2 sample rate is " + std::to_string(sample_rate) +
                             ", must be a positive number of frames per sample");
    check_file_size(path_, size, kPc2HeaderBytes, 0, samples, points, "samples");
    header_.frame_count = samples;
    header_.vertex_count = points;
    header_.frame_rate = kDefaultFrameRate / sample_rate;
    header_.start_time = start_frame / kDefaultFrameRate;
    data_offset_ = kPc2HeaderBytes;
    big_endian_ = false;
  }

  void read_mdd_header(int64_t size) {
    unsigned char h[kMddHeaderBytes];
    if (size < kMddHeaderBytes)
      fail_format(path_, "truncated: " + std::to_string(size) + " bytes, shorter than the " +
                             std::to_string(kMddHeaderBytes) + "-byte MDD header");
    read_at(file_.get(), path_, 0, h, sizeof(h));
    int32_t frames = load_i32(h, true);
    int32_t points = load_i32(h + 4, true);
    if (frames < 0) fail_format(path_, "MDD frames is " + std::to_string(frames));
    if (points <= 0) fail_format(path_, "MDD points is " + std::to_string(points));
    check_file_size(path_, size, kMddHeaderBytes, 4, frames, points, "frames");
    // Safe to allocate now: the file really holds these times.
    std::vector<unsigned char> raw(static_cast<size_t>(frames) * 4);
    if (frames > 0) read_at(file_.get(), path_, kMddHeaderBytes, raw.data(), raw.size());
    std::vector<double> times(static_cast<size_t>(frames));
    for (int32_t i = 0; i < frames; ++i) {
      times[i] = load_f32(&raw[4 * static_cast<size_t>(i)], true);
      if (!std::isfinite(times[i])) fail_format(path_, "MDD times[" + std::to_string(i) + "] is not finite");
    }
    header_.frame_count = frames;
    header_.vertex_count = points;
    header_.start_time = frames > 0 ? times.front() : 0.0;
    if (frames >= 2 && times.back() > times.front())
      header_.frame_rate = (frames - 1) / (times.back() - times.front());
    data_offset_ = kMddHeaderBytes + 4 * int64_t{frames};
    big_endian_ = true;
  }

  std::string path_;
  FilePtr file_;
  int64_t data_offset_ = 0;
  bool big_endian_ = false;
  std::vector<unsigned char> bytes_;
};

// Appends the 'v' coordinates of an OBJ text (w and vertex colours after xyz
// are ignored; every other statement is skipped).
void parse_obj_vertices(const std::string& path, const std::string& text, std::vector<float>* xyz) {
  xyz->clear();
  size_t line_start = 0;
  for (int64_t line = 1; line_start < text.size(); ++line) {
    size_t line_end = std::min(text.find('\n', line_start), text.size());
    const char* p = text.data() + line_start;
    const char* end = text.data() + line_end;
    line_start = line_end + 1;
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (end - p < 2 || p[0] != 'v' || (p[1] != ' ' && p[1] != '\t')) continue;
    p += 2;
    for (int k = 0; k < 3; ++k) {
      while (p < end && (*p == ' ' || *p == '\t')) ++p;
      if (p < end && *p == '+') ++p;  // from_chars rejects an explicit plus sign
      float value = 0.0f;
      auto result = std::from_chars(p, end, value);
      if (result.ec != std::errc() ||
          (result.ptr < end && !std::isspace(static_cast<unsigned char>(*result.ptr))))
        fail_format(path, "line " + std::to_string(line) + ": 'v' needs three numbers");
      if (!std::isfinite(value))
        fail_format(path, "line " + std::to_string(line) + ": vertex " + std::to_string(xyz->size() / 3) +
                              " is not finite");
      xyz->push_back(value);
      p = result.ptr;
    }
  }
}

bool is_file(const std::string& path) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error);
}

class ObjSequenceReader : public FrameReader {
 public:
  explicit ObjSequenceReader(const std::string& pattern) : pattern_(pattern) {
    header_.format = CacheFormat::obj_sequence;
    std::string frame0 = obj_sequence_frame_path(pattern, 0);
    std::string frame1 = obj_sequence_frame_path(pattern, 1);
    first_ = is_file(frame0) ? 0 : is_file(frame1) ? 1 : -1;
    if (first_ < 0)
      fail(PLEAT_ERROR_IO, "OBJ sequence " + in_quotes(pattern) + ": neither " + in_quotes(frame0) + " nor " +
                               in_quotes(frame1) + " exists");
    while (is_file(obj_sequence_frame_path(pattern, first_ + header_.frame_count))) ++header_.frame_count;
    std::string first_path = obj_sequence_frame_path(pattern, first_);
    parse_obj_vertices(first_path, read_text_file(first_path), &scratch_);
    if (scratch_.empty()) fail_format(first_path, "no 'v' lines");
    header_.vertex_count = static_cast<int64_t>(scratch_.size() / 3);
    header_.start_time = first_ / kDefaultFrameRate;
  }

  void read_frame(int64_t f, float* dst) override {
    std::string path = obj_sequence_frame_path(pattern_, first_ + f);
    parse_obj_vertices(path, read_text_file(path), &scratch_);
    if (static_cast<int64_t>(scratch_.size() / 3) != header_.vertex_count)
      fail_format(path, "frame " + std::to_string(f) + " has " + std::to_string(scratch_.size() / 3) +
                            " vertices, the first frame " + std::to_string(header_.vertex_count));
    std::copy(scratch_.begin(), scratch_.end(), dst);
  }

 private:
  std::string pattern_;
  int64_t first_ = 0;
  std::vector<float> scratch_;
};

class GltfReader : public FrameReader {
 public:
  explicit GltfReader(const std::string& path) : animation_(path) {
    header_.format = CacheFormat::gltf;
    header_.frame_count = animation_.frame_count();
    header_.vertex_count = animation_.vertex_count();
    header_.frame_rate = animation_.frame_rate();
    header_.start_time = animation_.start_time();
  }
  void read_frame(int64_t f, float* dst) override { animation_.frame(f, dst); }

 private:
  GltfMorphAnimation animation_;
};

std::unique_ptr<FrameReader> open_reader(const std::string& path, CacheFormat format) {
  format = resolve_cache_format(path, format);
  if (format == CacheFormat::obj_sequence) return std::make_unique<ObjSequenceReader>(path);
  if (format == CacheFormat::gltf) return std::make_unique<GltfReader>(path);
  if (format == CacheFormat::usda)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         in_quotes(path) +
             ": pleat writes USD point caches but does not read them; convert to PC2, MDD or glTF");
  return std::make_unique<BinaryReader>(path, format);
}

// ---- Writers ---------------------------------------------------------------

void write_binary(const std::string& path, CacheFormat format, const float* frames, size_t frame_count,
                  size_t vertex_count, size_t stride, double frame_rate) {
  bool big = format == CacheFormat::mdd;
  std::vector<unsigned char> bytes;
  if (format == CacheFormat::pc2) {
    bytes.assign(kPc2Magic, kPc2Magic + sizeof(kPc2Magic));
    store_i32(1, big, &bytes);  // version
    store_i32(static_cast<int64_t>(vertex_count), big, &bytes);
    store_f32(0.0f, big, &bytes);  // start frame
    store_f32(1.0f, big, &bytes);  // sample rate: one sample per frame
    store_i32(static_cast<int64_t>(frame_count), big, &bytes);
  } else {
    store_i32(static_cast<int64_t>(frame_count), big, &bytes);
    store_i32(static_cast<int64_t>(vertex_count), big, &bytes);
    for (size_t f = 0; f < frame_count; ++f)
      store_f32(static_cast<float>(static_cast<double>(f) / frame_rate), big, &bytes);
  }
  AtomicFile file(path);
  file.write(bytes.data(), bytes.size());
  for (size_t f = 0; f < frame_count; ++f) {
    bytes.clear();
    const float* xyz = frames + f * stride;
    for (size_t i = 0; i < 3 * vertex_count; ++i) store_f32(xyz[i], big, &bytes);
    file.write(bytes.data(), bytes.size());
  }
  file.commit();
}

}  // namespace

CacheFormat resolve_cache_format(const std::string& path, CacheFormat requested) {
  switch (requested) {
    case CacheFormat::pc2:
    case CacheFormat::mdd:
    case CacheFormat::obj_sequence:
    case CacheFormat::gltf:
    case CacheFormat::usda: return requested;
    case CacheFormat::automatic: break;
    default:
      fail(PLEAT_ERROR_INVALID_ARGUMENT,
           "cache format " + std::to_string(static_cast<uint32_t>(requested)) + " is unknown");
  }
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".pc2") return CacheFormat::pc2;
  if (extension == ".mdd") return CacheFormat::mdd;
  if (extension == ".gltf" || extension == ".glb") return CacheFormat::gltf;
  if (extension == ".usda") return CacheFormat::usda;
  return CacheFormat::obj_sequence;
}

std::string obj_sequence_frame_path(const std::string& pattern, int64_t frame) {
  size_t last = pattern.rfind('#');
  if (last == std::string::npos)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         in_quotes(pattern) +
             ": an OBJ sequence path needs a run of '#' for the frame number "
             "(e.g. shirt_####.obj); PC2 and MDD need a .pc2 or .mdd extension");
  size_t first = pattern.find_last_not_of('#', last);
  first = first == std::string::npos ? 0 : first + 1;
  std::string number = std::to_string(frame);
  size_t width = last + 1 - first;
  if (number.size() < width) number.insert(0, width - number.size(), '0');
  return pattern.substr(0, first) + number + pattern.substr(last + 1);
}

CacheHeader read_cache_header(const std::string& path, CacheFormat format) {
  return open_reader(path, format)->header();
}

CacheHeader read_cache(const std::string& path, CacheFormat format, float* out, size_t out_stride,
                       size_t capacity_floats) {
  std::unique_ptr<FrameReader> reader = open_reader(path, format);
  const CacheHeader& header = reader->header();
  size_t frame_floats = static_cast<size_t>(header.vertex_count) * 3;
  size_t frames = static_cast<size_t>(header.frame_count);
  if (out_stride == 0) out_stride = frame_floats;
  if (out_stride < frame_floats)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "frame stride " + std::to_string(out_stride) +
                                           " is below vertex_count * 3 = " + std::to_string(frame_floats));
  size_t needed = frames == 0 ? 0 : (frames - 1) * out_stride + frame_floats;
  if (capacity_floats < needed)
    fail(PLEAT_ERROR_BUFFER_TOO_SMALL, in_quotes(path) + " needs " + std::to_string(needed) +
                                           " floats, the buffer holds " + std::to_string(capacity_floats));
  if (frames > 0 && !out) fail(PLEAT_ERROR_INVALID_ARGUMENT, "output buffer is NULL");
  if (frames == 0) return header;  // no data bounds the point count of an empty cache: allocate nothing
  std::vector<float> scratch(frame_floats);
  for (size_t f = 0; f < frames; ++f) reader->read_frame(static_cast<int64_t>(f), scratch.data());
  for (size_t f = 0; f < frames; ++f) reader->read_frame(static_cast<int64_t>(f), out + f * out_stride);
  return header;
}

void write_cache(const std::string& path, CacheFormat format, const float* frames, size_t frame_count,
                 size_t vertex_count, size_t in_stride, double frame_rate, const Triangles* triangles) {
  format = resolve_cache_format(path, format);
  if (frame_count == 0 || vertex_count == 0)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "cannot write " + in_quotes(path) + " with " +
                                           std::to_string(frame_count) + " frames of " +
                                           std::to_string(vertex_count) + " vertices");
  if (!frames) fail(PLEAT_ERROR_INVALID_ARGUMENT, "positions are NULL");
  if (!(std::isfinite(frame_rate) && frame_rate > 0.0))
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "frame_rate " + std::to_string(frame_rate) + " is not a positive number");
  size_t frame_floats = vertex_count * 3;
  if (in_stride == 0) in_stride = frame_floats;
  if (in_stride < frame_floats)
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "frame stride " + std::to_string(in_stride) +
                                           " is below vertex_count * 3 = " + std::to_string(frame_floats));
  if (frame_count > INT32_MAX || vertex_count > static_cast<size_t>(INT32_MAX))
    fail(PLEAT_ERROR_INVALID_ARGUMENT, "a point cache holds at most 2^31 - 1 frames and points");
  if (cache_holds_faces(format)) {
    if (!triangles) fail(PLEAT_ERROR_INVALID_ARGUMENT, in_quotes(path) + " needs the garment's triangles");
    check_triangles(*triangles, vertex_count);
  }
  if (format == CacheFormat::obj_sequence)
    obj_sequence_frame_path(path, 0);  // a pattern without '#' fails up front
  for (size_t f = 0; f < frame_count; ++f)
    for (size_t i = 0; i < frame_floats; ++i)
      if (!std::isfinite(frames[f * in_stride + i]))
        fail(PLEAT_ERROR_INVALID_ARGUMENT,
             "frame " + std::to_string(f) + " vertex " + std::to_string(i / 3) + " is not finite");

  if (format == CacheFormat::pc2 || format == CacheFormat::mdd) {
    write_binary(path, format, frames, frame_count, vertex_count, in_stride, frame_rate);
    return;
  }
  if (format == CacheFormat::gltf) {
    write_gltf_cache(path, frames, frame_count, vertex_count, in_stride, frame_rate, *triangles);
    return;
  }
  if (format == CacheFormat::usda) {
    write_usda_cache(path, frames, frame_count, vertex_count, in_stride, frame_rate, *triangles);
    return;
  }
  // Every frame is on disk, and every name known, before the first frame
  // replaces its old version: a failure (disk full, memory) leaves the
  // previous sequence whole.
  std::vector<std::unique_ptr<AtomicFile>> files;
  files.reserve(frame_count);
  for (size_t f = 0; f < frame_count; ++f) {
    files.push_back(std::make_unique<AtomicFile>(obj_sequence_frame_path(path, static_cast<int64_t>(f))));
    write_obj(*files.back(), frames + f * in_stride, vertex_count, *triangles);
    files.back()->finish();
  }
  // A longer earlier bake to the same pattern would otherwise extend this one
  // when read back (frames are counted while files exist).
  std::vector<std::string> stale;
  for (auto f = static_cast<int64_t>(frame_count); is_file(obj_sequence_frame_path(path, f)); ++f)
    stale.push_back(obj_sequence_frame_path(path, f));
  for (auto& file : files) file->commit();
  for (const std::string& name : stale)
    if (std::remove(name.c_str()) != 0)
      fail(PLEAT_ERROR_IO, "the new frames are written, but the stale frame after them, " + in_quotes(name) +
                               ", cannot be removed: " + std::strerror(errno));
}

}  // namespace pleat
