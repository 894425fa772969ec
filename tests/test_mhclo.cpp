// MakeHuman clothes bindings (.mhclo): the formula on a hand-made binding,
// every garment of the asset pack on the default and on reshaped bodies, and
// bad files refused.
#include <gtest/gtest.h>

#include <fstream>

#include "body/makehuman.h"
#include "body/mhclo.h"
#include "core/error.h"
#include "core/nearest_points.h"
#include "io/obj_reader.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;

namespace {

std::string garments() {
  return pleat_test::asset_dir() + "/garments";
}

}  // namespace

// The formula on a hand-made binding: vertex 0 copies base vertex 2; vertex
// 1 = 0.5 B0 + 0.25 B1 + 0.25 B2 + S d with S from the scale pairs.
TEST(Mhclo, HandComputedBinding) {
  const std::string dir = pleat_test::temp_dir("mhclo_hand");
  std::ofstream(dir + "/hand.mhclo") << "name hand\nobj_file hand.obj\nx_scale 0 1 2.0\ny_scale 0 2 1.0\n"
                                        "z_scale 1 2 4.0\nverts 0\n2\n0 1 2 0.5 0.25 0.25 1.0 -2.0 0.5\n"
                                        "delete_verts\n3 5 - 7\n";
  const ClothesBinding b = read_mhclo(dir + "/hand.mhclo");
  EXPECT_EQ(b.obj_file, "hand.obj");
  EXPECT_EQ(b.deleted_base_vertices, (std::vector<int32_t>{3, 5, 6, 7}));
  Points3d base(3, 3);
  base << 0, 0, 0, 4, 0, 1, 0, 3, 5;
  const Points3d x = fit_clothes(b, base);
  // S = diag(|0 - 4| / 2, |0 - 3| / 1, |1 - 5| / 4) = diag(2, 3, 1).
  EXPECT_EQ(x.row(0), base.row(2));
  EXPECT_NEAR(x(1, 0), 0.25 * 4 + 2 * 1.0, 1e-12);
  EXPECT_NEAR(x(1, 1), 0.25 * 3 + 3 * -2.0, 1e-12);
  EXPECT_NEAR(x(1, 2), 0.25 * 1 + 0.25 * 5 + 1 * 0.5, 1e-12);
}

// Every CC0 garment of the pack, fitted to the default MakeHuman body, sits
// on it (the authored OBJs were draped on other shapes: the male outfits on
// a taller body).
TEST(Mhclo, EveryGarmentFitsTheDefaultBody) {
  const auto model = MakeHumanModel::load(pleat_test::asset_dir() + "/body");
  const Eigen::VectorXd beta = makehuman_default_beta();
  const Points3d base = model->shaped_vertices(beta);  // metres
  const Body body = model->body(beta);
  for (const char* name : {"female_casualsuit01", "female_casualsuit02", "female_elegantsuit01",
                           "male_casualsuit02", "male_casualsuit04", "male_elegantsuit01"}) {
    const std::string dir = garments() + "/" + name;
    const ClothesBinding b = read_mhclo(dir + "/" + name + ".mhclo");
    EXPECT_EQ(b.name, name);
    ASSERT_EQ(static_cast<Eigen::Index>(b.vertices.size()),
              read_obj_file_order(dir + "/" + b.obj_file).vertices.rows());
    const Points3d fitted = fit_clothes(b, base);
    const std::vector<int32_t> nearest = nearest_points(body.rest.vertices, fitted);
    double mean = 0;
    for (Eigen::Index v = 0; v < fitted.rows(); ++v)
      mean += (fitted.row(v) - body.rest.vertices.row(nearest[v])).norm();
    mean /= double(fitted.rows());
    EXPECT_LT(mean, 0.025) << name << ": mean distance to the body, metres";
    EXPECT_GT(mean, 0.002) << name << ": the garment is not glued into the skin";
    EXPECT_FALSE(b.deleted_base_vertices.empty()) << name;
  }
}

// Reshaped bodies: the fitted garment follows them.
TEST(Mhclo, GarmentFollowsAReshapedBody) {
  const auto model = MakeHumanModel::load(pleat_test::asset_dir() + "/body");
  const ClothesBinding b = read_mhclo(garments() + "/female_casualsuit01/female_casualsuit01.mhclo");
  Eigen::VectorXd beta = makehuman_default_beta();
  const Body body = model->body(beta);
  int height = -1;
  for (size_t i = 0; i < body.shape.size(); ++i)
    if (body.shape[i].name == "height") height = static_cast<int>(i);
  ASSERT_GE(height, 0);
  const auto distance_to_body = [&](const Eigen::VectorXd& shape) {
    const Points3d base = model->shaped_vertices(shape);  // metres
    const Points3d fitted = fit_clothes(b, base);
    const Body shaped = model->body(shape);
    const std::vector<int32_t> nearest = nearest_points(shaped.rest.vertices, fitted);
    double mean = 0;
    for (Eigen::Index v = 0; v < fitted.rows(); ++v)
      mean += (fitted.row(v) - shaped.rest.vertices.row(nearest[v])).norm();
    return std::make_pair(mean / double(fitted.rows()), fitted);
  };
  const auto [default_gap, standard] = distance_to_body(beta);
  beta[height] = 1.0;
  const auto [tall_gap, tall] = distance_to_body(beta);
  EXPECT_LT(default_gap, 0.025) << "within 2.5 cm of the default body on average";
  EXPECT_LT(tall_gap, 0.025) << "and of the tallest body";
  // The tall body is taller: so is the garment (trousers to the ankles).
  const double standard_height = standard.col(1).maxCoeff() - standard.col(1).minCoeff();
  const double tall_height = tall.col(1).maxCoeff() - tall.col(1).minCoeff();
  EXPECT_GT(tall_height, standard_height * 1.05);
}

TEST(Mhclo, BadFilesAreRefusedAndNamed) {
  const std::string dir = pleat_test::temp_dir("mhclo");
  std::ofstream(dir + "/short.mhclo")
      << "name x\nx_scale 1 2 1.0\ny_scale 1 2 1.0\nz_scale 1 2 1.0\nverts 0\n1 2 3 0.5\n";
  pleat_test::expect_error([&] { read_mhclo(dir + "/short.mhclo"); }, PLEAT_ERROR_FORMAT, "short.mhclo:6");
  std::ofstream(dir + "/noscale.mhclo") << "name x\nx_scale 1 2 1.0\nverts 0\n7\n";
  pleat_test::expect_error([&] { read_mhclo(dir + "/noscale.mhclo"); }, PLEAT_ERROR_FORMAT, "no y_scale");
  std::ofstream(dir + "/far.mhclo")
      << "name far\nx_scale 0 1 1.0\ny_scale 0 1 1.0\nz_scale 0 1 1.0\nverts 0\n99\n";
  const ClothesBinding far = read_mhclo(dir + "/far.mhclo");
  pleat_test::expect_error([&] { fit_clothes(far, Points3d::Zero(4, 3)); }, PLEAT_ERROR_INVALID_ARGUMENT,
                           "garment vertex 0 refers to base vertex 99");
  pleat_test::expect_error([&] { read_mhclo(dir + "/missing.mhclo"); }, PLEAT_ERROR_IO, "missing.mhclo");
}
