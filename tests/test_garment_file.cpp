// The prepared-garment file: versions, required fields and consistency checks
// name what is wrong.
#include <gtest/gtest.h>

#include "core/error.h"
#include "garment/garment_file.h"
#include "schema/garment_generated.h"
#include "support/test_support.h"

using namespace pleat;
namespace fb = pleat::schema;

namespace {

std::vector<uint8_t> finish(flatbuffers::FlatBufferBuilder& b, flatbuffers::Offset<fb::Garment> root) {
  fb::FinishGarmentBuffer(b, root);
  return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

void expect_refused(const std::vector<uint8_t>& bytes, pleat_status status, const std::string& text) {
  try {
    deserialize_garment(bytes.data(), bytes.size(), "crafted.pleatg");
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), status) << e.what();
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("crafted.pleatg"), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(GarmentFile, NewerFormatIsRefusedWithUpgradeHint) {
  flatbuffers::FlatBufferBuilder b;
  std::vector<double> v = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::vector<int32_t> t = {0, 1, 2};
  auto root = fb::CreateGarment(b, kGarmentFormatVersion + 1, 0, 0, b.CreateVector(v), b.CreateVector(t));
  expect_refused(finish(b, root), PLEAT_ERROR_UNSUPPORTED_VERSION, "upgrade pleat");
}

TEST(GarmentFile, MissingAndInconsistentFieldsAreNamed) {
  std::vector<double> v = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::vector<int32_t> t = {0, 1, 2}, remap = {0, 1, 2};
  {
    flatbuffers::FlatBufferBuilder b;
    auto root = fb::CreateGarment(b, kGarmentFormatVersion, 0, 0, b.CreateVector(v));
    expect_refused(finish(b, root), PLEAT_ERROR_FORMAT, "'triangles' is missing");
  }
  {
    flatbuffers::FlatBufferBuilder b;
    std::vector<int32_t> bad = {0, 1, 7};
    auto root = fb::CreateGarment(b, kGarmentFormatVersion, 0, 0, b.CreateVector(v), b.CreateVector(bad),
                                  b.CreateVector(remap), fb::CreateMeshReport(b));
    expect_refused(finish(b, root), PLEAT_ERROR_FORMAT, "'triangles' index 2 is out of range");
  }
  {
    flatbuffers::FlatBufferBuilder b;
    std::vector<double> nan = v;
    nan[4] = std::numeric_limits<double>::quiet_NaN();
    auto root = fb::CreateGarment(b, kGarmentFormatVersion, 0, 0, b.CreateVector(nan), b.CreateVector(t),
                                  b.CreateVector(remap), fb::CreateMeshReport(b));
    expect_refused(finish(b, root), PLEAT_ERROR_FORMAT, "'vertices' holds a non-finite");
  }
  {
    flatbuffers::FlatBufferBuilder b;
    std::vector<double> eig = {0.0, 0.5};
    std::vector<float> vec = {1, 0, 0}, deg = {1, 1, 1};
    auto bands = fb::CreateBands(b, 1, 2, 1, 2, PLEAT_SOLVER_DENSE, 0, 0.5, 0.5, b.CreateVector(eig),
                                 b.CreateVector(vec), b.CreateVector(deg));
    std::vector<int32_t> offsets = {0, 0, 0, 0};
    auto geo =
        fb::CreateNeighbourhoods(b, 0.1, b.CreateVector(offsets), b.CreateVector(std::vector<int32_t>{}));
    auto root = fb::CreateGarment(b, kGarmentFormatVersion, 0, 0, b.CreateVector(v), b.CreateVector(t),
                                  b.CreateVector(remap), fb::CreateMeshReport(b), bands, geo);
    expect_refused(finish(b, root), PLEAT_ERROR_FORMAT, "'bands.vectors' has 3 values, expected 6");
  }
}

TEST(GarmentFile, NotAGarmentFile) {
  std::vector<uint8_t> junk(64, 0x41);
  expect_refused(junk, PLEAT_ERROR_FORMAT, "identifier PLGM");
  expect_refused({}, PLEAT_ERROR_FORMAT, "identifier PLGM");
}
