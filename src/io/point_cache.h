#pragma once
// Point caches: per-frame vertex positions in the formats DCC tools read.
//
// PC2 (Blender, 3ds Max, Maya): little endian. "POINTCACHE2\0", int32 version
//   1, int32 points, float start frame, float sample rate, int32 samples, then
//   float32 xyz per point per sample. Start frame and sample rate are in
//   *frames* (the rate is frames per sample; 1 = one sample every frame); the
//   file stores no frame rate. Reading, pleat puts the frame timeline at the
//   project's 30 fps: frame_rate = 30 / sample_rate samples per second and
//   start_time = start_frame / 30 s. Writing, it stores start frame 0 and
//   sample rate 1, as Blender's and 3ds Max's exporters do, so that hosts play
//   one sample per scene frame; `frame_rate` has no field to go to there.
// MDD (LightWave, Blender, Houdini): big endian. int32 frames, int32 points,
//   float32 time in seconds per frame, then float32 xyz per point per frame.
//   Reading, frame_rate = (frames - 1) / (last time - first time), or 30 fps
//   for a single frame or non-increasing times; start_time = the first time.
//   Writing, frame i gets time i / frame_rate.
// OBJ sequence: one OBJ file per frame; the last run of '#' in the path is
//   replaced by the zero-padded frame number ("out/shirt_####.obj" ->
//   "out/shirt_0000.obj", ...; wider numbers use more digits). Writing numbers
//   frames from 0 and deletes the consecutive frames after the last one that an
//   earlier, longer write left (they would lengthen the sequence on reading). Reading starts at frame 0, or
//   at 1 when there is no frame 0 (Blender's exporter starts at the scene's first frame, 1 by default), and
//   counts consecutive files; only 'v' lines are read. No frame rate is stored:
//   reading reports 30 fps and start_time = first frame number / 30.
// glTF (.gltf, .glb): morph-target animation, read and written
//   (io/gltf_cache.h).
// USD ASCII (.usda): time-sampled mesh points, written only (io/usda_cache.h).
//
// Reading checks the whole file before writing to the caller's buffer, so on
// any failure that buffer is untouched. Writing is atomic per file (AtomicFile);
// an OBJ sequence writes and syncs all its frames before renaming any, so a
// failed write leaves the previous sequence whole.
#include <cstddef>
#include <cstdint>
#include <string>

#include "capi/pleat.h"
#include "core/mesh.h"

namespace pleat {

enum class CacheFormat : uint32_t {
  automatic = PLEAT_CACHE_AUTO,
  pc2 = PLEAT_CACHE_PC2,
  mdd = PLEAT_CACHE_MDD,
  obj_sequence = PLEAT_CACHE_OBJ_SEQUENCE,
  gltf = PLEAT_CACHE_GLTF,
  usda = PLEAT_CACHE_USDA,
};

// Formats that store the mesh's faces with the points (the writer needs them).
inline bool cache_holds_faces(CacheFormat format) {
  return format == CacheFormat::obj_sequence || format == CacheFormat::gltf || format == CacheFormat::usda;
}

// Frame rate assumed where a format stores none (DESIGN section 8).
constexpr double kDefaultFrameRate = 30.0;

// `requested` unless automatic; then .pc2 / .mdd / .gltf / .glb / .usda by
// extension (any case), and an OBJ sequence otherwise. Throws PLEAT_ERROR_INVALID_ARGUMENT for a value
// outside the enum.
CacheFormat resolve_cache_format(const std::string& path, CacheFormat requested);

struct CacheHeader {
  CacheFormat format = CacheFormat::automatic;
  int64_t frame_count = 0;
  int64_t vertex_count = 0;
  double frame_rate = kDefaultFrameRate;  // samples per second
  double start_time = 0.0;                // seconds
};

// Reads and validates the header (PC2, MDD: including that the file size
// matches it exactly), or counts and checks an OBJ sequence. Throws
// PLEAT_ERROR_IO for a missing or unreadable file and PLEAT_ERROR_FORMAT,
// naming the file and field, for malformed content.
CacheHeader read_cache_header(const std::string& path, CacheFormat format);

// Reads every frame: frame f goes to out + f * out_stride (vertex_count * 3
// floats; out_stride 0 = packed). capacity_floats is the size of `out`; too
// small gives PLEAT_ERROR_BUFFER_TOO_SMALL. A non-finite value gives
// PLEAT_ERROR_FORMAT naming the frame and vertex.
CacheHeader read_cache(const std::string& path, CacheFormat format, float* out, size_t out_stride,
                       size_t capacity_floats);

// Writes frame_count frames of vertex_count points (frame f at frames + f *
// in_stride; 0 = packed). `triangles` is required for the formats that hold
// faces (cache_holds_faces) and ignored otherwise. Every input is checked before the first byte is written:
// NaN/Inf (named by frame and vertex), zero counts, a bad frame rate or triangle
// give PLEAT_ERROR_INVALID_ARGUMENT; counts beyond a format's int32 fields too.
void write_cache(const std::string& path, CacheFormat format, const float* frames, size_t frame_count,
                 size_t vertex_count, size_t in_stride, double frame_rate, const Triangles* triangles);

// Path of one frame of an OBJ sequence pattern. Throws
// PLEAT_ERROR_INVALID_ARGUMENT when the pattern holds no '#'.
std::string obj_sequence_frame_path(const std::string& pattern, int64_t frame);

}  // namespace pleat
