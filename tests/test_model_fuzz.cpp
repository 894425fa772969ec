// Mutation fuzzing of the model-file loader: corrupted, truncated and
// bit-flipped model files are refused with a format (or version) error that
// names the source, or load into a model that is fully usable — never a crash,
// a sanitizer report or a foreign exception. CI runs this test in the
// sanitizer build too (scripts/test.sh -> scripts/sanitize.sh test_model_fuzz).
//
// The mutations are deterministic: a fixed-seed std::mt19937_64 (whose output
// the standard fixes) mapped to choices here, not through <random>'s
// distributions, so every platform runs the same sequence.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "runtime/model_file.h"
#include "runtime/model_init.h"
#include "schema/model_generated.h"

using namespace pleat;
using namespace pleat::runtime;
namespace fb = pleat::schema;

namespace {

// CI's run; PLEAT_FUZZ_MUTATIONS (more only) and PLEAT_FUZZ_SEED make longer
// or different local campaigns.
constexpr int kMutations = 50000;
constexpr uint64_t kSeed = 0x706c656174667a31ull;  // "pleatfz1"

uint64_t env_or(const char* name, uint64_t fallback) {
  const char* value = std::getenv(name);
  return value && *value ? std::strtoull(value, nullptr, 0) : fallback;
}

// A small but complete model: one parse takes microseconds. Every optional
// part the writer knows (normalisations, training metrics) is present so the
// mutations reach its reader too.
std::vector<uint8_t> small_model_bytes(int32_t body_vertex_stride = 1, float offset_filter_length = 0.0f) {
  ModelSkeleton skeleton;
  skeleton.joint_names = {"hips", "spine", "arm"};
  skeleton.parents = {-1, 0, 1};
  const std::vector<ShapeEntry> shape = {{"height", 0.5f}, {"weight", -0.25f}};
  ModelInitOptions o;
  o.seed = 11;
  o.code_width = 8;
  o.body_widths = {8, 8};
  o.garment_widths = {8, 8};
  o.heads = 2;
  o.gru_layers = 1;
  o.blend_widths = {4, 3};
  o.refinement_widths = {4, 3};
  o.created = "2024-01-01T00:00:00Z";
  o.body_vertex_stride = body_vertex_stride;
  o.offset_filter_length = offset_filter_length;
  std::shared_ptr<Model> m = initialize_model(skeleton, shape, o);

  const auto norm = [](Index width) {
    InputNormalization n;
    n.shift = nn::RowVector::Constant(width, 0.125f);
    n.scale = nn::RowVector::Constant(width, 2.0f);
    return n;
  };
  m->body_normalization = norm(2 + 3);                 // shape + rest joint distances
  m->garment_encoder.normalization = norm(3 + 3 + 3);  // position, normal, joint distances
  m->motion_normalization = norm(6 * 3 + 3);           // rotations + root velocity
  m->refinement.normalization = norm(3 + 3 + 3);       // velocity, normal, joint distances
  m->training.metrics = {{"E_verts", 0.01}, {"E_edge", 0.002}};
  m->training.optimizer = "adamax";
  m->training.schedule = "cosine";
  validate_model(*m);
  return serialize_model(*m);
}

// --------------------------------------------------------------- mutator

class Mutator {
 public:
  explicit Mutator(uint64_t seed) : rng_(seed) {}

  // 0..n-1 (n > 0). Modulo bias is irrelevant here; the mapping is ours, so
  // the sequence is the same everywhere.
  size_t below(size_t n) { return static_cast<size_t>(rng_() % n); }
  size_t range(size_t lo, size_t hi) { return lo + below(hi - lo + 1); }  // [lo, hi]
  uint8_t byte() { return static_cast<uint8_t>(rng_() & 0xff); }
  uint32_t word() { return static_cast<uint32_t>(rng_() >> 32); }

  uint32_t interesting(size_t size) {
    const uint32_t s = static_cast<uint32_t>(size);
    const std::array<uint32_t, 12> values = {0u,    1u, 0x7fffffffu, 0xffffffffu, 0x80000000u, s, s - 1,
                                             s + 1, 2u, 4u,          0xfffffffcu, 0x7ffffffcu};
    return values[below(values.size())];
  }

 private:
  std::mt19937_64 rng_;
};

enum Kind : int {
  kBitFlip,
  kMultiBitFlip,
  kOverwrite,
  kTruncate,
  kTruncateTiny,
  kInsert,
  kDelete,
  kInterestingWord,
  kDuplicateChunk,
  kRootOffset,
  kRootVtable,
  kRootField,
  kStacked,
  kKindCount
};
const char* const kKindNames[kKindCount] = {
    "bit flip",    "multi bit flip",   "overwrite",        "truncate",        "truncate 0..16",
    "insert",      "delete",           "interesting word", "duplicate chunk", "root offset",
    "root vtable", "root table field", "stacked"};

// Little-endian words; bytes past the end (of a buffer an earlier stacked
// mutation shortened) read as 0 and are not written.
uint32_t read_u32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v = 0;
  for (size_t i = 4; i-- > 0;) v = (v << 8) | (at + i < b.size() ? b[at + i] : 0u);
  return v;
}
void write_u32(std::vector<uint8_t>* b, size_t at, uint32_t v) {
  for (size_t i = 0; i < 4 && at + i < b->size(); ++i) (*b)[at + i] = static_cast<uint8_t>(v >> (8 * i));
}

// Where the root table and its vtable lie in the (unmutated) buffer.
struct RootLayout {
  size_t table = 0;
  size_t vtable = 0;
  size_t vtable_size = 0;
  std::vector<size_t> fields;  // absolute positions of the root's present fields
};

RootLayout root_layout(const std::vector<uint8_t>& b) {
  RootLayout l;
  l.table = read_u32(b, 0);
  const auto soffset = static_cast<int32_t>(read_u32(b, l.table));
  l.vtable = static_cast<size_t>(static_cast<int64_t>(l.table) - soffset);
  l.vtable_size = static_cast<size_t>(b[l.vtable] | (b[l.vtable + 1] << 8));
  for (size_t e = 4; e + 1 < l.vtable_size; e += 2) {
    const size_t field = static_cast<size_t>(b[l.vtable + e] | (b[l.vtable + e + 1] << 8));
    if (field != 0) l.fields.push_back(l.table + field);
  }
  return l;
}

// Applies one mutation of `kind` to *b; returns a description for messages.
std::string mutate(Mutator& r, Kind kind, const RootLayout& root, std::vector<uint8_t>* b) {
  const size_t n = b->size();
  if (n == 0) {
    b->push_back(r.byte());
    return "grow empty";
  }
  switch (kind) {
    case kBitFlip: {
      const size_t at = r.below(n);
      const int bit = static_cast<int>(r.below(8));
      (*b)[at] = static_cast<uint8_t>((*b)[at] ^ (1u << bit));
      return "flip byte " + std::to_string(at) + " bit " + std::to_string(bit);
    }
    case kMultiBitFlip: {
      const size_t count = r.range(2, 16);
      std::string d = "flip bits at";
      for (size_t i = 0; i < count; ++i) {
        const size_t at = r.below(n);
        (*b)[at] = static_cast<uint8_t>((*b)[at] ^ (1u << r.below(8)));
        d += " " + std::to_string(at);
      }
      return d;
    }
    case kOverwrite: {
      const size_t at = r.below(n), len = r.range(1, 32);
      for (size_t i = at; i < at + len && i < n; ++i) (*b)[i] = r.byte();
      return "overwrite " + std::to_string(len) + " bytes at " + std::to_string(at);
    }
    case kTruncate: {
      const size_t len = r.below(n);
      b->resize(len);
      return "truncate to " + std::to_string(len);
    }
    case kTruncateTiny: {
      const size_t len = r.below(17 < n ? 17 : n);
      b->resize(len);
      return "truncate to " + std::to_string(len);
    }
    case kInsert: {
      const size_t at = r.below(n + 1), len = r.range(1, 16);
      std::vector<uint8_t> bytes(len);
      for (auto& x : bytes) x = r.byte();
      b->insert(b->begin() + static_cast<std::ptrdiff_t>(at), bytes.begin(), bytes.end());
      return "insert " + std::to_string(len) + " bytes at " + std::to_string(at);
    }
    case kDelete: {
      const size_t at = r.below(n), len = r.range(1, 16);
      const size_t end = at + len < n ? at + len : n;
      b->erase(b->begin() + static_cast<std::ptrdiff_t>(at), b->begin() + static_cast<std::ptrdiff_t>(end));
      return "delete " + std::to_string(end - at) + " bytes at " + std::to_string(at);
    }
    case kInterestingWord: {
      // Mostly 4-aligned (where FlatBuffers keeps offsets and lengths).
      size_t at = r.below(n);
      if (r.below(4) != 0) at &= ~size_t{3};
      const uint32_t v = r.interesting(n);
      write_u32(b, at, v);
      return "word at " + std::to_string(at) + " = " + std::to_string(v);
    }
    case kDuplicateChunk: {
      const size_t from = r.below(n), len = r.range(1, 64);
      const size_t end = from + len < n ? from + len : n;
      const std::vector<uint8_t> chunk(b->begin() + static_cast<std::ptrdiff_t>(from),
                                       b->begin() + static_cast<std::ptrdiff_t>(end));
      const size_t to = r.below(n);
      if (r.below(2) == 0) {
        b->insert(b->begin() + static_cast<std::ptrdiff_t>(to), chunk.begin(), chunk.end());
        return "insert copy of [" + std::to_string(from) + ", " + std::to_string(end) + ") at " +
               std::to_string(to);
      }
      for (size_t i = 0; i < chunk.size() && to + i < n; ++i) (*b)[to + i] = chunk[i];
      return "overwrite with copy of [" + std::to_string(from) + ", " + std::to_string(end) + ") at " +
             std::to_string(to);
    }
    case kRootOffset: {
      uint32_t v = 0;
      switch (r.below(4)) {
        case 0: v = r.interesting(n); break;
        case 1: v = read_u32(*b, 0) ^ (1u << r.below(32)); break;
        case 2: v = static_cast<uint32_t>(r.below(n + 8)); break;
        default: v = static_cast<uint32_t>(read_u32(*b, 0) + r.range(0, 16) - 8); break;
      }
      write_u32(b, 0, v);
      return "root offset = " + std::to_string(v);
    }
    case kRootVtable: {
      // The root table's soffset to its vtable, or a byte / entry of the vtable.
      if (r.below(4) == 0) {
        const uint32_t v =
            r.below(2) == 0 ? r.interesting(n) : read_u32(*b, root.table) ^ (1u << r.below(32));
        write_u32(b, root.table, v);
        return "root soffset = " + std::to_string(v);
      }
      const size_t at = root.vtable + (r.below(root.vtable_size) & ~size_t{1});
      uint16_t v = 0;
      switch (r.below(3)) {
        case 0: v = static_cast<uint16_t>(r.word()); break;
        case 1: v = static_cast<uint16_t>(((*b)[at] | ((*b)[at + 1] << 8)) ^ (1u << r.below(16))); break;
        default: v = std::array<uint16_t, 6>{0, 1, 2, 4, 0x7fff, 0xffff}[r.below(6)]; break;
      }
      (*b)[at] = static_cast<uint8_t>(v);
      (*b)[at + 1] = static_cast<uint8_t>(v >> 8);
      return "root vtable entry at " + std::to_string(at) + " = " + std::to_string(v);
    }
    case kRootField: {
      // A field of the root table: its offset to a sub-table, or a scalar.
      const size_t at = root.fields[r.below(root.fields.size())];
      const uint32_t v = r.below(2) == 0 ? r.interesting(n) : read_u32(*b, at) + r.word() % 64 - 32;
      write_u32(b, at, v);
      return "root field at " + std::to_string(at) + " = " + std::to_string(v);
    }
    case kStacked:
    case kKindCount: break;
  }
  // Two to four mutations of the other kinds in a row.
  const size_t count = r.range(2, 4);
  std::string d = "stacked:";
  for (size_t i = 0; i < count; ++i) {
    const auto k = static_cast<Kind>(r.below(kStacked));
    // Positions found in the original buffer may be gone after a resize.
    const bool structural = k == kRootVtable || k == kRootField;
    d += " [" + mutate(r, structural && b->size() != n ? kBitFlip : k, root, b) + "]";
  }
  return d;
}

// --------------------------------------------------------------- checks

enum class Outcome { accepted, refused_format, refused_version, failed };

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// A loaded model must be usable: finite tensors, and it writes a file that
// loads again and is a fixed point of write(load(...)). Reports and returns
// false otherwise.
bool check_accepted(const Model& m, const std::string& what) {
  for (const TensorView& t : model_tensors(m))
    for (size_t i = 0; i < t.size(); ++i)
      if (!std::isfinite(t.data[i])) {
        ADD_FAILURE() << what << ": accepted with " << t.name << "[" << i << "] = " << t.data[i];
        return false;
      }
  const std::vector<uint8_t> again = serialize_model(m);
  std::shared_ptr<Model> reloaded;
  try {
    reloaded = deserialize_model(again.data(), again.size(), "fuzz reloaded");
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": the accepted model's own file is refused: " << e.what();
    return false;
  }
  if (!reloaded || serialize_model(*reloaded) != again) {
    ADD_FAILURE() << what << ": writing the reloaded model changes the bytes";
    return false;
  }
  return true;
}

// One parse of `bytes` (at an odd address if `unaligned`, with the buffer
// ending exactly at its end so ASan sees any over-read).
Outcome parse(const std::vector<uint8_t>& bytes, bool unaligned, const std::string& what) {
  std::vector<uint8_t> storage(bytes.size() + (unaligned ? 1 : 0));
  uint8_t* data = storage.data() + (unaligned ? 1 : 0);
  if (!bytes.empty()) std::memcpy(data, bytes.data(), bytes.size());
  std::shared_ptr<Model> m;
  try {
    m = deserialize_model(bytes.empty() ? nullptr : data, bytes.size(), "fuzz");
  } catch (const Error& e) {
    const std::string message = e.what();
    if (!starts_with(message, "model 'fuzz'")) {
      ADD_FAILURE() << what << ": message does not name the source: " << message;
      return Outcome::failed;
    }
    if (e.status() == PLEAT_ERROR_FORMAT) return Outcome::refused_format;
    if (e.status() == PLEAT_ERROR_UNSUPPORTED_VERSION) return Outcome::refused_version;
    ADD_FAILURE() << what << ": status " << e.status() << ": " << message;
    return Outcome::failed;
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": foreign exception: " << e.what();
    return Outcome::failed;
  } catch (...) {
    ADD_FAILURE() << what << ": unknown exception";
    return Outcome::failed;
  }
  if (!m) {
    ADD_FAILURE() << what << ": null model without an error";
    return Outcome::failed;
  }
  return check_accepted(*m, what) ? Outcome::accepted : Outcome::failed;
}

void expect_refused(const std::vector<uint8_t>& bytes, pleat_status status, const std::string& part) {
  for (bool unaligned : {false, true}) {
    std::vector<uint8_t> storage(bytes.size() + 1);
    uint8_t* data = storage.data() + (unaligned ? 1 : 0);
    if (!bytes.empty()) std::memcpy(data, bytes.data(), bytes.size());
    try {
      deserialize_model(data, bytes.size(), "fuzz");
      ADD_FAILURE() << "accepted (" << bytes.size() << " bytes)";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), status) << e.what();
      EXPECT_TRUE(starts_with(e.what(), "model 'fuzz'")) << e.what();
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  }
}

// The valid file with its format_version replaced (found through the
// FlatBuffers table API; ForceDefaults means the field is always stored).
std::vector<uint8_t> with_format_version(std::vector<uint8_t> bytes, uint32_t version) {
  auto* table = flatbuffers::GetMutableRoot<flatbuffers::Table>(bytes.data());
  EXPECT_TRUE(table->SetField<uint32_t>(fb::Model::VT_FORMAT_VERSION, version, 0));
  EXPECT_EQ(fb::GetModel(bytes.data())->format_version(), version);
  return bytes;
}

}  // namespace

TEST(ModelFuzz, TheUnmutatedFileLoads) {
  const std::vector<uint8_t> good = small_model_bytes();
  for (bool unaligned : {false, true})
    EXPECT_EQ(parse(good, unaligned, "unmutated"), Outcome::accepted) << "unaligned " << unaligned;
}

TEST(ModelFuzz, EmptyShortAndForeignBuffersAreRefused) {
  const std::vector<uint8_t> good = small_model_bytes();
  EXPECT_EQ(parse({}, false, "empty"), Outcome::refused_format);
  try {
    deserialize_model(good.data(), 0, "fuzz");
    ADD_FAILURE() << "size 0 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), PLEAT_ERROR_FORMAT) << e.what();
  }
  expect_refused({}, PLEAT_ERROR_FORMAT, "identifier PLMD missing");
  expect_refused({good.begin(), good.begin() + 7}, PLEAT_ERROR_FORMAT, "identifier PLMD missing");
  expect_refused({good.begin(), good.begin() + 8}, PLEAT_ERROR_FORMAT, "corrupt or truncated");
  std::vector<uint8_t> foreign = good;
  foreign[4] = 'X';  // identifier PLMD -> XLMD
  expect_refused(foreign, PLEAT_ERROR_FORMAT, "identifier PLMD missing");
  expect_refused(std::vector<uint8_t>(good.size(), 0), PLEAT_ERROR_FORMAT, "identifier PLMD missing");
}

TEST(ModelFuzz, NewerFormatVersionIsRefusedAsUnsupported) {
  const std::vector<uint8_t> good = small_model_bytes();
  for (uint32_t version : {kModelFormatVersion + 1, 0xffffffffu})
    expect_refused(with_format_version(good, version), PLEAT_ERROR_UNSUPPORTED_VERSION, "update pleat");
  expect_refused(with_format_version(good, 0), PLEAT_ERROR_FORMAT, "format_version is 0");
  EXPECT_EQ(parse(with_format_version(good, kModelFormatVersion), false, "same version"), Outcome::accepted);
}

// Only the writer's trailing alignment padding may go; any other cut is
// refused.
// A file is written with the lowest version that reads it correctly: a
// version-1 reader would pool the body code over every vertex.
TEST(ModelFuzz, BodyVertexStrideIsWrittenAsFormatVersionTwo) {
  const std::vector<uint8_t> plain = small_model_bytes(1), strided = small_model_bytes(8);
  EXPECT_EQ(fb::GetModel(plain.data())->format_version(), 1u);
  EXPECT_EQ(fb::GetModel(strided.data())->format_version(), 2u);
  EXPECT_EQ(deserialize_model(strided.data(), strided.size(), "strided")->body_vertex_stride, 8);
  EXPECT_EQ(deserialize_model(plain.data(), plain.size(), "plain")->body_vertex_stride, 1);
  expect_refused(with_format_version(strided, 1), PLEAT_ERROR_FORMAT,
                 "body_vertex_stride 8 needs format_version 2 (the file says 1)");
  for (int32_t bad : {0, -3, kMaxBodyVertexStride + 1}) {
    std::vector<uint8_t> bytes = strided;
    auto* table = flatbuffers::GetMutableRoot<flatbuffers::Table>(bytes.data());
    ASSERT_TRUE(table->SetField<int32_t>(fb::Model::VT_BODY_VERTEX_STRIDE, bad, 1));
    expect_refused(bytes, PLEAT_ERROR_FORMAT, "body_vertex_stride is " + std::to_string(bad));
  }
}

// A reader of version 2 or older would skip the filter.
TEST(ModelFuzz, OffsetFilterLengthIsWrittenAsFormatVersionThree) {
  const std::vector<uint8_t> filtered = small_model_bytes(8, 0.01f);
  EXPECT_EQ(fb::GetModel(filtered.data())->format_version(), 3u);
  EXPECT_EQ(deserialize_model(filtered.data(), filtered.size(), "filtered")->offset_filter_length, 0.01f);
  expect_refused(with_format_version(filtered, 2), PLEAT_ERROR_FORMAT,
                 "offset_filter_length 0.010000 needs format_version 3 (the file says 2)");
  for (float bad : {-0.01f, kMaxOffsetFilterLength * 2, std::numeric_limits<float>::quiet_NaN()}) {
    std::vector<uint8_t> bytes = filtered;
    auto* table = flatbuffers::GetMutableRoot<flatbuffers::Table>(bytes.data());
    ASSERT_TRUE(table->SetField<float>(fb::Model::VT_OFFSET_FILTER_LENGTH, bad, 0.0f));
    expect_refused(bytes, PLEAT_ERROR_FORMAT, "offset_filter_length is");
  }
}

// A reader of version 3 or older would bind the nearest-vertex prior.
TEST(ModelFuzz, SoftSkinningPriorIsWrittenAsFormatVersionFour) {
  std::shared_ptr<Model> m =
      deserialize_model(small_model_bytes().data(), small_model_bytes().size(), "small");
  m->skinning_prior_radius = 0.1f;
  m->skinning_prior_floor = 0.01f;
  const std::vector<uint8_t> soft = serialize_model(*m);
  EXPECT_EQ(fb::GetModel(soft.data())->format_version(), 4u);
  const std::shared_ptr<Model> back = deserialize_model(soft.data(), soft.size(), "soft");
  EXPECT_EQ(back->skinning_prior_radius, 0.1f);
  EXPECT_EQ(back->skinning_prior_floor, 0.01f);
  EXPECT_EQ(deserialize_model(small_model_bytes().data(), small_model_bytes().size(), "plain")
                ->skinning_prior_floor,
            kDefaultSkinningPriorFloor)
      << "files without the field keep the old floor";
  expect_refused(
      with_format_version(soft, 3), PLEAT_ERROR_FORMAT,
      "skinning_prior_radius 0.100000 and skinning_prior_floor 0.010000 need format_version 4 (the "
      "file says 3)");
  for (float bad : {-0.01f, kMaxSkinningPriorRadius * 2, std::numeric_limits<float>::quiet_NaN()}) {
    std::vector<uint8_t> bytes = soft;
    auto* table = flatbuffers::GetMutableRoot<flatbuffers::Table>(bytes.data());
    ASSERT_TRUE(table->SetField<float>(fb::Model::VT_SKINNING_PRIOR_RADIUS, bad, 0.0f));
    expect_refused(bytes, PLEAT_ERROR_FORMAT, "skinning_prior_radius is");
  }
  for (float bad : {0.0f, 2.0f, std::numeric_limits<float>::infinity()}) {
    std::vector<uint8_t> bytes = soft;
    auto* table = flatbuffers::GetMutableRoot<flatbuffers::Table>(bytes.data());
    ASSERT_TRUE(table->SetField<float>(fb::Model::VT_SKINNING_PRIOR_FLOOR, bad, kDefaultSkinningPriorFloor));
    expect_refused(bytes, PLEAT_ERROR_FORMAT, "skinning_prior_floor is");
  }
}

// A reader of version 4 or older would not know the feature.
TEST(ModelFuzz, FusedCodeRefinementIsWrittenAsFormatVersionFive) {
  const std::vector<uint8_t> plain = small_model_bytes();
  std::shared_ptr<Model> m = deserialize_model(plain.data(), plain.size(), "small");
  GraphStack& r = m->refinement;
  const Index code = m->code_width(), in = r.in_width();
  r.features.push_back(Feature::fused_code);
  nn::GraphAttentionLayer& first = r.layers.front();
  first.weight.conservativeResize(in + code, Eigen::NoChange);
  first.weight.bottomRows(code).setConstant(0.01f);
  ASSERT_FALSE(r.normalization.empty());
  r.normalization.shift.conservativeResize(in + code);
  r.normalization.scale.conservativeResize(in + code);
  r.normalization.shift.tail(code).setZero();
  r.normalization.scale.tail(code).setOnes();
  validate_model(*m);
  const std::vector<uint8_t> fused = serialize_model(*m);
  EXPECT_EQ(fb::GetModel(fused.data())->format_version(), 5u);
  EXPECT_EQ(deserialize_model(fused.data(), fused.size(), "fused")->refinement.features, r.features);
  expect_refused(with_format_version(fused, 4), PLEAT_ERROR_FORMAT,
                 "refinement feature 'fused_code' needs format_version 5 (the file says 4)");
  // The code is the refinement's input alone, and its width is the code's.
  std::shared_ptr<Model> narrow = std::make_shared<Model>(*m);
  narrow->refinement.layers.front().weight.conservativeResize(in + code - 1, Eigen::NoChange);
  expect_refused(serialize_model(*narrow), PLEAT_ERROR_FORMAT, "refinement");
  std::shared_ptr<Model> elsewhere = std::make_shared<Model>(*m);
  elsewhere->motion_features.push_back(Feature::fused_code);
  expect_refused(serialize_model(*elsewhere), PLEAT_ERROR_FORMAT,
                 "motion_features entry 2 'fused_code' is not an input of this stack");
}

TEST(ModelFuzz, EveryTruncationIsRefused) {
  const std::vector<uint8_t> good = small_model_bytes();
  size_t padding = 0;
  while (padding < 8 && good[good.size() - 1 - padding] == 0) ++padding;
  for (size_t len = 0; len < good.size(); ++len) {
    const std::vector<uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(len));
    const Outcome o = parse(cut, len % 2 == 1, "truncated to " + std::to_string(len));
    if (len + padding >= good.size()) {
      EXPECT_NE(o, Outcome::failed) << "truncated to " << len << " of " << good.size();
      if (o == Outcome::accepted) {
        EXPECT_EQ(serialize_model(*deserialize_model(cut.data(), cut.size(), "fuzz")), good);
      }
    } else {
      ASSERT_EQ(o, Outcome::refused_format) << "truncated to " << len << " of " << good.size();
    }
  }
}

TEST(ModelFuzz, MutatedFilesAreRefusedOrLoadUsable) {
  const std::vector<uint8_t> good = small_model_bytes();
  ASSERT_GT(good.size(), 256u);
  const RootLayout root = root_layout(good);
  ASSERT_GT(root.vtable_size, 4u);
  ASSERT_FALSE(root.fields.empty());

  const uint64_t seed = env_or("PLEAT_FUZZ_SEED", kSeed);
  const int mutations = static_cast<int>(std::max<uint64_t>(kMutations, env_or("PLEAT_FUZZ_MUTATIONS", 0)));
  Mutator r(seed);
  int accepted = 0, refused_format = 0, refused_version = 0, failed = 0, unchanged = 0;
  std::array<int, kKindCount> per_kind{}, refused_per_kind{};
  const auto start = std::chrono::steady_clock::now();
  int i = 0;
  for (; i < mutations; ++i) {
    const auto kind = static_cast<Kind>(i % kKindCount);
    std::vector<uint8_t> bytes = good;
    const std::string what = "mutation " + std::to_string(i) + " (" + kKindNames[kind] + ": " +
                             mutate(r, kind, root, &bytes) + ")";
    if (bytes == good) ++unchanged;
    ++per_kind[kind];
    switch (parse(bytes, i % 3 == 2, what)) {
      case Outcome::accepted: ++accepted; break;
      case Outcome::refused_format:
        ++refused_format;
        ++refused_per_kind[kind];
        break;
      case Outcome::refused_version:
        ++refused_version;
        ++refused_per_kind[kind];
        break;
      case Outcome::failed: ++failed; break;
    }
    if (failed >= 20) break;  // enough to debug; do not flood the log
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::cout << "model fuzz (seed " << seed << "): " << i << " mutations of a " << good.size()
            << "-byte file in " << seconds << " s: " << accepted << " accepted, " << refused_format
            << " refused (format), " << refused_version << " refused (version), " << failed << " failed, "
            << unchanged << " left the bytes unchanged\n";
  for (int k = 0; k < kKindCount; ++k)
    std::cout << "  " << kKindNames[k] << ": " << refused_per_kind[k] << " of " << per_kind[k]
              << " refused\n";

  EXPECT_EQ(failed, 0);
  EXPECT_GE(i, kMutations);
  EXPECT_EQ(accepted + refused_format + refused_version, i);
  // The mutator really mutates: most files are refused, and both kinds of
  // refusal occur.
  EXPECT_GT(refused_format + refused_version, i / 2);
  EXPECT_GT(refused_version, 0);
  EXPECT_GT(accepted, 0);
  EXPECT_LT(unchanged, i / 100);
}
