#include "preview.h"

#include <cmath>
#include <filesystem>

#include "body/body_source.h"
#include "body/motion_ops.h"
#include "capi/pleat.h"
#include "character_clip.h"
#include "core/error.h"
#include "io/contact_sheet.h"
#include "io/obj_reader.h"
#include "io/point_cache.h"

namespace pleat::datagen {
namespace {

constexpr std::array<uint8_t, 3> kBodyColor{190, 190, 190}, kGarmentColor{70, 120, 200};

void write_sheet(const std::string& png, const std::vector<int64_t>& frames, const float* garment, int64_t n,
                 const Triangles& garment_triangles, const float* body, int64_t nb,
                 const Triangles& body_triangles) {
  std::vector<std::vector<SheetMesh>> sheet;
  for (int64_t f : frames)
    sheet.push_back({{body + f * nb * 3, nb, &body_triangles, kBodyColor},
                     {garment + f * n * 3, n, &garment_triangles, kGarmentColor}});
  write_contact_sheet(png, sheet);
}

}  // namespace

std::vector<int64_t> preview_frames(int64_t frames, int count) {
  std::vector<int64_t> out;
  const int64_t k = std::min<int64_t>(std::max(count, 1), frames);
  for (int64_t i = 0; i < k; ++i)
    out.push_back(
        k == 1 ? 0 : static_cast<int64_t>(std::llround(double(i) * double(frames - 1) / double(k - 1))));
  return out;
}

void preview_sequence(const std::string& dir, const std::string& png, int count) {
  const SequenceData d = read_sequence(dir);
  std::string source = d.meta.body_source;
  if (!source.empty() && std::filesystem::path(source).is_relative()) source = dir + "/" + source;
  const Body body = load_body_source(source, d.meta.body_kind, d.meta.body_rig).body;
  const int64_t nb = d.body_vertex_count();
  if (nb != body.vertex_count())
    fail(PLEAT_ERROR_FORMAT, "sequence '" + dir + "': body.pc2 has " + std::to_string(nb) +
                                 " vertices, the body '" + source + "' " +
                                 std::to_string(body.vertex_count()));
  write_sheet(png, preview_frames(d.meta.frame_count, count), d.garment_frames.data(),
              d.garment_rest.vertex_count(), d.garment_rest.triangles, d.body_frames.data(), nb,
              body.rest.triangles);
}

void preview_bake(const BakePreview& b, const std::string& png, int count) {
  const TriMesh garment = read_obj_file_order(b.garment);
  const CacheHeader header = read_cache_header(b.cache, CacheFormat::automatic);
  if (header.vertex_count != garment.vertex_count())
    fail(PLEAT_ERROR_FORMAT, "'" + b.cache + "' has " + std::to_string(header.vertex_count) + " vertices, '" +
                                 b.garment + "' " + std::to_string(garment.vertex_count()));
  std::vector<float> frames(static_cast<size_t>(header.frame_count * header.vertex_count * 3));
  read_cache(b.cache, CacheFormat::automatic, frames.data(), 0, frames.size());
  const CharacterClip character = load_character_clip(b.body, b.rig, b.shape, b.motion, b.map, b.frame_rate);
  const Body& body = character.body;
  const Motion& clip = character.clip;
  if (b.first + header.frame_count > clip.frame_count)
    fail(PLEAT_ERROR_INVALID_ARGUMENT,
         "'" + b.cache + "' has " + std::to_string(header.frame_count) + " frames, the clip '" + b.motion +
             "' " + std::to_string(clip.frame_count) + " at " + std::to_string(b.frame_rate) +
             " fps (--first " + std::to_string(b.first) + ")");
  const std::vector<int64_t> picked = preview_frames(header.frame_count, count);
  const Points3d posed = pose_body_frames(body, clip, b.first, header.frame_count);
  const std::vector<float> body_frames(posed.data(), posed.data() + posed.size());
  write_sheet(png, picked, frames.data(), garment.vertex_count(), garment.triangles, body_frames.data(),
              body.vertex_count(), body.rest.triangles);
}

}  // namespace pleat::datagen
