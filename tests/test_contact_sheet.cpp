// Contact sheets (io/contact_sheet.h) read back with libpng: the layout
// (frames side by side, front over side view), depth order, shading and
// background; and `pleat preview` on a training sequence folder.
#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <filesystem>

#include "io/contact_sheet.h"
#include "support/expect_error.h"
#include "support/synthetic_sequence.h"
#include "support/test_support.h"

namespace {

struct Png {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  const uint8_t* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * width + x) * 3]; }
};

Png read_png(const std::string& path) {
  Png image;
  png_image p{};
  p.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&p, path.c_str())) return image;
  p.format = PNG_FORMAT_RGB;
  image.width = static_cast<int>(p.width);
  image.height = static_cast<int>(p.height);
  image.rgb.resize(PNG_IMAGE_SIZE(p));
  if (!png_image_finish_read(&p, nullptr, image.rgb.data(), 0, nullptr)) image.width = 0;
  return image;
}

// A square of side 1 m at depth z facing +z (two triangles), centred at (0, 1).
pleat::Points3f square(float z, float half) {
  pleat::Points3f p(4, 3);
  p << -half, 1 - half, z, half, 1 - half, z, half, 1 + half, z, -half, 1 + half, z;
  return p;
}

}  // namespace

TEST(ContactSheet, DrawsFramesSideBySideWithDepthAndShading) {
  const std::string dir = pleat_test::temp_dir("contact_sheet");
  pleat::Triangles quad(2, 3);
  quad << 0, 1, 2, 0, 2, 3;
  const pleat::Points3f back = square(0.0f, 0.5f), front = square(0.1f, 0.25f);
  // Frame 0: the small square in front of the big one; frame 1: the big one alone.
  const std::vector<std::vector<pleat::SheetMesh>> frames = {
      {{front.data(), 4, &quad, {0, 0, 250}}, {back.data(), 4, &quad, {250, 0, 0}}},
      {{back.data(), 4, &quad, {250, 0, 0}}}};
  pleat::write_contact_sheet(dir + "/sheet.png", frames, 90);
  const Png png = read_png(dir + "/sheet.png");
  ASSERT_EQ(png.width, 2 * 60);
  ASSERT_EQ(png.height, 2 * 90);
  // Front view of frame 0, cell centre: the nearer blue square wins, lit
  // head-on (shade 1: full colour).
  EXPECT_EQ(png.at(30, 45)[2], 250);
  EXPECT_EQ(png.at(30, 45)[0], 0);
  // Beside the small square, the red one; the cell corner is background.
  EXPECT_EQ(png.at(30 - 18, 45)[0], 250);
  EXPECT_EQ(png.at(1, 1)[0], 255);
  EXPECT_EQ(png.at(1, 1)[2], 255);
  // Frame 1 is centred on itself in the second cell.
  EXPECT_EQ(png.at(60 + 30, 45)[0], 250);
  // Side view: the squares are edge-on, so nearly nothing is drawn.
  int coloured = 0;
  for (int y = 90; y < 180; ++y)
    for (int x = 0; x < 120; ++x) coloured += png.at(x, y)[1] != 255;
  EXPECT_LT(coloured, 200);

  pleat::Points3f nan = back;
  nan(2, 1) = NAN;
  pleat_test::expect_error(
      [&] {
        pleat::write_contact_sheet(dir + "/bad.png", {{{nan.data(), 4, &quad, {0, 0, 0}}}});
      },
      PLEAT_ERROR_INVALID_ARGUMENT, "frame 0: vertex 2 is not finite");
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.png"));
}

TEST(ContactSheet, PleatPreviewDrawsASequenceFolder) {
  const std::string dir = pleat_test::temp_dir("preview_cli");
  const std::string sequence = pleat_test::write_skirt_walk(dir);
  std::string text;
  const std::string cli = std::getenv("PLEAT_CLI");
  ASSERT_EQ(
      pleat_test::run_command(cli + " preview " + sequence + " -o " + dir + "/p.png --frames 3 2>&1", &text),
      0)
      << text;
  const Png png = read_png(dir + "/p.png");
  EXPECT_EQ(png.width, 3 * 240);
  EXPECT_EQ(png.height, 2 * 360);
  int garment = 0, body = 0;
  for (size_t i = 0; i < png.rgb.size(); i += 3) {
    garment += png.rgb[i + 2] > png.rgb[i] + 40;                                  // blue
    body += png.rgb[i] == png.rgb[i + 1] && png.rgb[i] < 250 && png.rgb[i] > 40;  // grey
  }
  EXPECT_GT(garment, 2000) << "the skirt";
  EXPECT_GT(body, 20000) << "the body";
  EXPECT_EQ(pleat_test::run_command(cli + " preview " + dir + "/nowhere -o " + dir + "/q.png 2>&1", &text),
            2);
  EXPECT_NE(text.find("nowhere"), std::string::npos) << text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/q.png"));
}
