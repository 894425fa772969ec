#pragma once
// The acceptance check of a simulation (config.h CheckSettings): no NaN, the
// garment stays near the body and on it, and it does not sink far into it.
#include <string>
#include <vector>

#include "config.h"
#include "core/mesh.h"

namespace pleat::datagen {

struct CheckReport {
  bool passed = true;
  std::string reason;         // the first failure, naming the frame and vertex
  double max_distance = 0;    // m, over kept frames and vertices, to the nearest body vertex
  double max_body_speed = 0;  // m/s, the fastest body vertex between two kept frames
  int64_t max_distance_frame = 0;
  double max_penetrating_fraction = 0;  // of vertices deeper than max_penetration, worst frame
  double mean_penetrating_fraction = 0;
  double mean_slipped_fraction = 0;  // of vertices slipped (CheckSettings), mean over kept frames
  double max_slipped_fraction = 0;   // worst frame
};

// garment, body: frame_count frames each (vertices x 3 floats per frame) at
// frame_rate; garment_rest and body_rest: the same vertices at rest, where
// each garment vertex's anchor for the slip check is its nearest body vertex.
// Penetration depth is the distance behind the nearest body vertex's normal.
CheckReport check_simulation(const std::vector<float>& garment, const Points3d& garment_rest,
                             const std::vector<float>& body, const Points3d& body_rest,
                             const Triangles& body_triangles, int64_t frame_count, double frame_rate,
                             const CheckSettings& settings);

}  // namespace pleat::datagen
