// OBJ files read in their own vertex order (io/obj_reader.h): corner syntaxes,
// fan triangulation, negative indices, and errors that name the line.
#include <gtest/gtest.h>

#include <fstream>

#include "io/obj_reader.h"
#include "support/expect_error.h"
#include "support/test_support.h"

using namespace pleat;
using pleat_test::expect_error;

namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = pleat_test::temp_dir("obj_reader") + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(ObjReader, KeepsTheFileOrderAndTriangulatesPolygons) {
  const std::string path =
      write("quad.obj",
            "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nvt 0 0\nv 1 1 0\nv 0 1 0\n"
            "vn 0 0 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nv 2 0 0.5\nf -4//1 5//1 3//1\ng x\ns off\n");
  const TriMesh m = read_obj_file_order(path);
  ASSERT_EQ(m.vertex_count(), 5);
  EXPECT_EQ(m.vertices(4, 0), 2.0);
  EXPECT_EQ(m.vertices(4, 2), 0.5);
  ASSERT_EQ(m.triangles.rows(), 3);
  EXPECT_EQ(m.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(m.triangles.row(1), Eigen::RowVector3i(0, 2, 3)) << "fan from the first corner";
  EXPECT_EQ(m.triangles.row(2), Eigen::RowVector3i(1, 4, 2)) << "-4 counts back from the 5th vertex";
}

TEST(ObjReader, ErrorsNameTheLine) {
  const auto F = PLEAT_ERROR_FORMAT;
  expect_error([] { read_obj_file_order(write("a.obj", "v 0 0 0\nv 1 0\n")); }, F,
               "line 2: is not 'v x y z'");
  expect_error([] { read_obj_file_order(write("b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")); }, F,
               "line 4: corner '4' is outside the 3 vertices read so far");
  expect_error([] { read_obj_file_order(write("c.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n")); }, F,
               "line 3: a face needs at least three corners");
  expect_error([] { read_obj_file_order(write("d.obj", "v 0 0 nan\n")); }, F,
               "line 1: a coordinate is not finite");
  expect_error([] { read_obj_file_order(write("e.obj", "v 0 0 0\nf 1 x 1\n")); }, F,
               "corner 'x' is not an index");
  expect_error([] { read_obj_file_order("/nonexistent/g.obj"); }, PLEAT_ERROR_IO, "/nonexistent/g.obj");
}

TEST(ObjReader, ReportsTheGroupOfEveryTriangle) {
  const std::string path = write("groups.obj",
                                 "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\ng body\nf 1 2 3 4\n"
                                 "g helper skirt \r\nf 2 3 4\ng body\nf 4 3 1\n");
  ObjGroups groups;
  groups.names = {"stale"};
  const TriMesh m = read_obj_file_order(path, &groups);
  ASSERT_EQ(m.triangles.rows(), 5);
  EXPECT_EQ(groups.names, (std::vector<std::string>{"body", "helper skirt"})) << "first appearance, trimmed";
  EXPECT_EQ(groups.of_triangle, (std::vector<int32_t>{-1, 0, 0, 1, 0})) << "a quad gives two triangles";
}
