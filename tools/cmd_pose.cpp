// `pleat pose`: a body driven by a motion, written as a PC2 cache (+ rest OBJ).
#include <algorithm>
#include <cstdio>
#include <vector>

#include "cli.h"

namespace pleat_cli {

int run_pose(const Args& args) {
  if (!args.has("body") || !args.has("motion") || !args.has("output"))
    throw CliError{"needs --body, --motion and -o out.pc2", 2};
  BodyPtr body = load_body(args);
  const double fps = args.number("fps", 30.0);
  MotionPtr motion = load_motion_for(args, body.get(), fps);

  pleat_body_info info{};
  info.struct_size = sizeof info;
  check(pleat_body_get_info(body.get(), &info), "reading the body");
  const FrameRange range = frame_range(args, motion.get(), fps);
  const size_t first = range.first, count = range.count;

  const size_t n = info.vertex_count;
  std::vector<float> frames(count * n * 3);
  const size_t chunk = 32;
  for (size_t f = 0; f < count; f += chunk) {
    const size_t c = std::min(chunk, count - f);
    check(pleat_body_pose_motion(body.get(), motion.get(), first + f, c, {frames.data() + f * n * 3, 0}),
          "posing frames");
    std::fprintf(stderr, "\rposed %zu / %zu frames", f + c, count);
  }
  std::fprintf(stderr, "\n");
  check(pleat_cache_write(args.get("output").c_str(), PLEAT_CACHE_AUTO, nullptr, {frames.data(), 0}, count, n,
                          fps),
        "writing '" + args.get("output") + "'");
  std::printf("wrote %s: %zu frames of %zu vertices at %g fps\n", args.get("output").c_str(), count, n, fps);

  if (args.has("rest-obj")) {
    std::vector<float> rest(n * 3);
    std::vector<uint32_t> triangles(info.triangle_count * size_t{3});
    check(pleat_body_get_rest(body.get(), rest.data(), rest.size(), triangles.data(), triangles.size(),
                              nullptr, 0),
          "reading the rest body");
    check(pleat_mesh_write_obj(args.get("rest-obj").c_str(), rest.data(), n, triangles.data(),
                               info.triangle_count),
          "writing '" + args.get("rest-obj") + "'");
    std::printf("wrote %s\n", args.get("rest-obj").c_str());
  }
  return 0;
}

}  // namespace pleat_cli
