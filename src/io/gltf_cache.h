#pragma once
// Point caches as glTF 2.0 morph-target animation (through tinygltf): the
// form Blender, three.js, Unreal and Godot import as shape-key animation.
//
// Writing: one mesh, one triangle primitive; its POSITION is frame 0 and
// morph target t holds frame t + 1 minus frame 0. One animation, "pleat",
// drives the node's weights with LINEAR keys at f / frame_rate seconds: at
// frame f target f - 1 has weight 1 and every other 0, so the positions
// between two keys blend linearly. ".glb" writes the binary container, any
// other name (".gltf") JSON with the buffer embedded as a data URI: one file
// either way, so the write is atomic.
//
// Reading (any glTF, not only pleat's): the first node with a mesh whose
// first primitive is triangles, evaluated at every key time of the animation
// channel that drives that node's weights (LINEAR or STEP; CUBICSPLINE uses
// its values). No animation: one frame of the base positions.
// frame_rate = (keys - 1) / (last time - first time), start_time = first time.
// Skinned or node-transformed meshes are read in their mesh space.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace pleat {

void write_gltf_cache(const std::string& path, const float* frames, size_t frame_count, size_t vertex_count,
                      size_t stride, double frame_rate, const Triangles& triangles);

// A glTF morph animation read and checked whole on construction (throws
// PLEAT_ERROR_IO for a missing file, PLEAT_ERROR_FORMAT naming the file and
// the glTF field at fault); frames are then evaluated in any order.
class GltfMorphAnimation {
 public:
  explicit GltfMorphAnimation(const std::string& path);

  int64_t frame_count() const { return static_cast<int64_t>(times_.size()); }
  int64_t vertex_count() const { return static_cast<int64_t>(base_.size() / 3); }
  double frame_rate() const;
  double start_time() const { return times_.front(); }
  // Frame f's positions into dst (vertex_count * 3 floats).
  void frame(int64_t f, float* dst) const;

 private:
  std::string path_;
  std::vector<float> base_;                  // vertex_count * 3
  std::vector<std::vector<float>> targets_;  // each vertex_count * 3
  std::vector<double> times_;                // one per frame
  std::vector<float> weights_;               // frame_count * targets
};

}  // namespace pleat
