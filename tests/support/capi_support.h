#pragma once
// For tests of the C API: owning garment handles and garments from test meshes.
#include <gtest/gtest.h>

#include <memory>

#include "capi/pleat.h"
#include "support/test_support.h"

namespace pleat_test {

struct GarmentDeleter {
  void operator()(pleat_garment* g) const { pleat_garment_destroy(g); }
};
using GarmentPtr = std::unique_ptr<pleat_garment, GarmentDeleter>;

inline GarmentPtr create_garment(const SimpleMesh& m) {
  pleat_garment* g = nullptr;
  EXPECT_EQ(pleat_garment_create(m.positions.data(), m.vertex_count(), m.triangles.data(), m.triangle_count(),
                                 nullptr, &g),
            PLEAT_OK)
      << pleat_last_error();
  return GarmentPtr(g);
}

}  // namespace pleat_test
