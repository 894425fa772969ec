#pragma once
// A vertex mask (pleat_instance_set_vertex_mask): the graph stacks run on the
// part of the garment the active vertices' results depend on, not on the
// whole garment. A graph layer mixes each vertex with its 1-ring, so an
// L-layer stack's output at a vertex depends on its L-ring only: run on the
// subgraph induced by the active vertices dilated by L rings, it gives the
// active vertices what the whole garment would (up to the GEMM's rounding).
// The refinement reads the posed garment M̃ and its normals (1 ring more), and
// M̃ reads the blend stack, hence the chain of regions below.
#include <cstdint>
#include <vector>

#include "nn/graph_attention.h"

namespace pleat::runtime {

// The subgraph of `graph` induced by `vertices` (ascending garment indices),
// in local indices: node i is garment vertex vertices[i].
struct SubGraph {
  std::vector<int32_t> vertices;
  nn::AttentionGraph graph;
};

struct VertexMask {
  std::vector<int32_t> active;  // evaluated by every stage
  std::vector<int32_t> masked;  // keep their skinned positions
  SubGraph refinement;          // active + the refinement stack's reach
  SubGraph blend;               // posed + the blend stack's reach
  // Where M̃ must be the whole garment's: the refinement's region and its
  // 1-ring (normals), as local indices of `blend`.
  std::vector<int32_t> posed_in_blend;
  std::vector<int32_t> active_in_refinement;  // local indices of `active` in `refinement`
};

// The regions for a mask of `vertex_count` bytes (nonzero = active) on a
// garment with attention graph `graph`. Returns nothing (an empty `active`
// and `masked`) when every vertex is active: no mask is cheaper then.
VertexMask make_vertex_mask(const nn::AttentionGraph& graph, const uint8_t* mask, int32_t blend_layers,
                            int32_t refinement_layers);

}  // namespace pleat::runtime
