#pragma once
// Where and when a prediction misses (`pleat-train evaluate --errors DIR`):
// the vertex distance to the simulation per frame and per vertex, so a
// technical artist can find the frames and the region of the garment a
// model fails on, next to LBS and the noise floor.

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dataset.h"
#include "runtime/instance.h"

namespace pleat::training {

// Vertex distance in cm between `predicted` (frame_count x N x 3 floats, the
// sequence's welded vertex order) and the sequence's simulation. Both means
// equal the sequence's E_verts.
struct VertexErrors {
  std::vector<double> per_frame;   // frame_count values: the mean over the vertices
  std::vector<double> per_vertex;  // N values: the mean over the frames
};
VertexErrors vertex_errors(const TrainingSequence& s, const float* predicted);

// For each sequence of `data`, writes <dir>/<sequence>_frames.csv (frame,
// lbs_cm, noise_floor_cm, <model>_cm...) and <dir>/<sequence>_vertices.csv
// (vertex, rest_x, rest_y, rest_z in metres, then the same columns), each
// atomically; noise_floor_cm is empty where `twins` has no twin of the
// sequence's folder. The models run as the report runs them (full stage).
void write_error_maps(
    const Dataset& data, const std::map<std::string, std::string>& twins,
    const std::vector<std::pair<std::string, std::shared_ptr<const runtime::Model>>>& models,
    const runtime::InstanceOptions& options, const std::string& dir);

}  // namespace pleat::training
