#pragma once
// Where and when a prediction misses (`pleat-train evaluate --errors DIR`):
// the vertex distance to the simulation per frame and per vertex, so a
// technical artist can find the frames and the region of the garment a
// model fails on, next to LBS and the noise floor.

#include <optional>
#include <string>
#include <vector>

#include "dataset.h"

namespace pleat::training {

// Vertex distance in cm between `predicted` (frame_count x N x 3 floats, the
// sequence's welded vertex order) and the sequence's simulation. Both means
// equal the sequence's E_verts.
struct VertexErrors {
  std::vector<double> per_frame;   // frame_count values: the mean over the vertices
  std::vector<double> per_vertex;  // N values: the mean over the frames
  // The prediction itself in garment.obj's vertex order (frame_count x
  // source vertices x 3), so its cache loads onto the sequence's garment.obj.
  std::vector<float> frames;
};
VertexErrors vertex_errors(const TrainingSequence& s, const float* predicted);

// One sequence's columns of the error maps: LBS, the noise floor (none
// without a twin) and each model, in the report's order. The report's scoring
// fills them from the frames it scores, so nothing runs twice.
struct SequenceErrors {
  VertexErrors lbs;
  std::optional<VertexErrors> noise_floor;
  std::vector<VertexErrors> models;
};

// For each sequence of `data` (errors[i] its columns, model_names the models'
// column names), writes <dir>/<sequence>_frames.csv (frame, lbs_cm,
// noise_floor_cm, <model>_cm...) and <dir>/<sequence>_vertices.csv (vertex,
// rest_x, rest_y, rest_z in metres, then the same columns), each atomically;
// noise_floor_cm is empty where the sequence has no twin; and each
// prediction as <dir>/<sequence>_<column>.pc2 (lbs and each model, not the
// twin: its own folder holds it), to play back against garment.pc2.
void write_error_maps(const Dataset& data, const std::vector<SequenceErrors>& errors,
                      const std::vector<std::string>& model_names, const std::string& dir);

}  // namespace pleat::training
