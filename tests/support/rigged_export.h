#pragma once
// Writes a pleat::Body as a skinned character through assimp's exporter
// (FBX, glTF): the mesh, one node per joint with its rest transform, one bone
// per joint with its weights and inverse bind matrix. Tests use it to make a
// "rigged FBX character" with the MakeHuman skeleton, so the same model binds
// to it and to the MakeHuman body.
#include <assimp/scene.h>

#include <assimp/Exporter.hpp>
#include <string>
#include <vector>

#include "body/body.h"
#include "body/skeleton.h"

namespace pleat_test {

inline aiMatrix4x4 to_ai(const Eigen::Affine3d& a) {
  aiMatrix4x4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i][j] = static_cast<float>(a.matrix()(i, j));
  return r;
}

// Returns assimp's error text, empty on success.
inline std::string export_rigged_body(const pleat::Body& body, const std::string& path,
                                      const char* format_id) {
  const pleat::Skeleton& s = body.skeleton;
  const int32_t joints = s.joint_count(), n = body.vertex_count();
  std::vector<Eigen::Affine3d> local(static_cast<size_t>(joints)), global(static_cast<size_t>(joints));
  for (int32_t j = 0; j < joints; ++j) {
    local[j] =
        Eigen::Translation3d(s.rest_translation.row(j).transpose()) * s.rest_rotation[static_cast<size_t>(j)];
    global[j] = s.parents[j] < 0 ? local[j] : global[static_cast<size_t>(s.parents[j])] * local[j];
  }

  aiScene scene;
  scene.mRootNode = new aiNode("root");
  scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
  scene.mNumMaterials = 1;
  std::vector<aiNode*> nodes(static_cast<size_t>(joints));
  for (int32_t j = 0; j < joints; ++j) {
    nodes[j] = new aiNode(s.names[static_cast<size_t>(j)]);
    nodes[j]->mTransformation = to_ai(local[j]);
  }
  std::vector<std::vector<aiNode*>> children(static_cast<size_t>(joints) + 1);  // last: the root node's
  for (int32_t j = 0; j < joints; ++j)
    children[s.parents[j] < 0 ? static_cast<size_t>(joints) : static_cast<size_t>(s.parents[j])].push_back(
        nodes[j]);
  auto* mesh_node = new aiNode("body_mesh");
  mesh_node->mMeshes = new unsigned[1]{0};
  mesh_node->mNumMeshes = 1;
  children.back().insert(children.back().begin(), mesh_node);
  scene.mRootNode->addChildren(static_cast<unsigned>(children.back().size()), children.back().data());
  for (int32_t j = 0; j < joints; ++j)
    if (!children[j].empty())
      nodes[j]->addChildren(static_cast<unsigned>(children[j].size()), children[j].data());

  scene.mMeshes = new aiMesh* [1] { new aiMesh() };
  scene.mNumMeshes = 1;
  aiMesh* mesh = scene.mMeshes[0];
  mesh->mName = "body";
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = static_cast<unsigned>(n);
  mesh->mVertices = new aiVector3D[n];
  for (int32_t v = 0; v < n; ++v)
    mesh->mVertices[v] =
        aiVector3D(static_cast<float>(body.rest.vertices(v, 0)), static_cast<float>(body.rest.vertices(v, 1)),
                   static_cast<float>(body.rest.vertices(v, 2)));
  const auto faces = static_cast<unsigned>(body.rest.triangles.rows());
  mesh->mNumFaces = faces;
  mesh->mFaces = new aiFace[faces];
  for (unsigned f = 0; f < faces; ++f) {
    mesh->mFaces[f].mNumIndices = 3;
    mesh->mFaces[f].mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k)
      mesh->mFaces[f].mIndices[k] = static_cast<unsigned>(body.rest.triangles(f, k));
  }
  std::vector<std::vector<aiVertexWeight>> weights(static_cast<size_t>(joints));
  for (int32_t v = 0; v < n; ++v)
    for (int32_t k = body.weights.offsets[v]; k < body.weights.offsets[v + 1]; ++k)
      weights[static_cast<size_t>(body.weights.joints[k])].emplace_back(
          static_cast<unsigned>(v), static_cast<float>(body.weights.weights[k]));
  mesh->mNumBones = static_cast<unsigned>(joints);
  mesh->mBones = new aiBone*[joints];
  for (int32_t j = 0; j < joints; ++j) {
    aiBone* bone = mesh->mBones[j] = new aiBone();
    bone->mName = s.names[static_cast<size_t>(j)];
    bone->mOffsetMatrix = to_ai(global[j].inverse());
    bone->mNumWeights = static_cast<unsigned>(weights[j].size());
    bone->mWeights = new aiVertexWeight[weights[j].size()];
    std::copy(weights[j].begin(), weights[j].end(), bone->mWeights);
  }
  Assimp::Exporter exporter;
  if (exporter.Export(&scene, format_id, path) != aiReturn_SUCCESS) return exporter.GetErrorString();
  return "";
}

}  // namespace pleat_test
