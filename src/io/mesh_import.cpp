#include "io/mesh_import.h"

#include <assimp/scene.h>

#include <vector>

#include "core/error.h"
#include "io/scene_file.h"

namespace pleat {
namespace {

struct Collector {
  std::vector<double> positions;
  std::vector<int32_t> indices;
};

void collect(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, Collector* out) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[i]];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const auto base = static_cast<int32_t>(out->positions.size() / 3);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      aiVector3D p = transform * mesh->mVertices[v];
      out->positions.insert(out->positions.end(), {p.x, p.y, p.z});
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by SortByPType
      for (int c = 0; c < 3; ++c) out->indices.push_back(base + static_cast<int32_t>(face.mIndices[c]));
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(scene, node->mChildren[c], transform, out);
}

}  // namespace

ImportedMesh import_mesh(const std::string& path) {
  const SceneFile file(path);
  const aiScene* scene = &file.scene();

  Collector c;
  collect(scene, scene->mRootNode, aiMatrix4x4(), &c);
  if (c.indices.empty()) fail(PLEAT_ERROR_INVALID_MESH, path + ": the file holds no triangles");

  ImportedMesh mesh;
  mesh.unit_scale = file.unit_scale();
  mesh.vertices =
      Eigen::Map<Points3d>(c.positions.data(), static_cast<Eigen::Index>(c.positions.size() / 3), 3) *
      mesh.unit_scale;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    if (!mesh.vertices.row(v).allFinite())
      fail(PLEAT_ERROR_FORMAT, path + ": vertex " + std::to_string(v) + " is not finite (in metres)");
  mesh.triangles =
      Eigen::Map<Triangles>(c.indices.data(), static_cast<Eigen::Index>(c.indices.size() / 3), 3);
  return mesh;
}

}  // namespace pleat
