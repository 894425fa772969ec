#pragma once
// Skinned characters and their animation clips from glTF, FBX and the other
// formats assimp reads (io/scene_file: bones with offset matrices and vertex
// weights, a node hierarchy, aiAnimation channels).
//
// Rest pose = the node hierarchy's own transforms (for files written at bind,
// the bind pose). The rest mesh is the skinned mesh at that pose:
//   v_rest = sum_b w_b * G_node(b) * offset(b) * v_mesh
// so it is exactly what an engine shows for the file's default pose. Joints
// are the bone nodes plus every node on the way from them up to their lowest
// common ancestor (the skeleton's root); rest rotations come from the nodes
// and may be non-identity. Node scales are baked into positions (the
// skeleton itself is rigid); scale keys of clips are ignored, and so are
// translation keys of joints other than the root.
//
// Units: FBX declares its unit (UnitScaleFactor, centimetres per unit) and is
// converted to metres as in io/mesh_import.h; other formats are taken as
// metres (glTF is metres by specification). Axes are taken as given (Y up
// for glTF and for assimp's FBX import).
#include <string>
#include <vector>

#include "body/body.h"
#include "body/skeleton.h"

namespace pleat {

struct RigImportOptions {
  // Sampling rate of the clips in frames per second; 0 = the key rate (the
  // finest spacing between keys of a clip, at most 240 fps; 30 fps for clips
  // with a single key time).
  double frame_rate = 0.0;
  // Extra factor applied on top of the file's declared unit.
  double scale = 1.0;
};

struct ImportedClip {
  std::string name;
  Motion motion;  // motion.skeleton == the rig's skeleton
  double duration_seconds = 0.0;
  std::vector<std::string> ignored_channels;  // channels on nodes outside the skeleton
};

struct ImportedRig {
  Body body;                        // skeleton + rest mesh + weights (no shape parameters)
  std::vector<ImportedClip> clips;  // one per aiAnimation, in file order
  double unit_scale = 1.0;          // factor applied from the file's unit (times options.scale)
  // Vertices no bone weighs: bound rigidly to the nearest joint above their
  // mesh node, or to the root when the mesh hangs outside the skeleton.
  std::vector<int32_t> unweighted_vertices;
};

// Throws PLEAT_ERROR_IO (unreadable), PLEAT_ERROR_FORMAT (the reader's reason,
// no triangles, no bones, a bone without a node, two bone nodes with one
// name) or PLEAT_ERROR_INVALID_ARGUMENT (bad options, non-finite data).
ImportedRig import_rig(const std::string& path, const RigImportOptions& options = {});

}  // namespace pleat
