#pragma once
// The scene of a garment mesh or a rigged character file, for the importers
// that walk it (io/mesh_import, body/rig_import). glTF (.gltf, .glb, or the
// binary magic under any name) is read by io/gltf_scene (tinygltf, every
// index checked by pleat); every other format by assimp, after pleat has
// refused the FBX structures assimp recurses over without a bound
// (io/fbx_precheck.h). A binary glTF header declaring more bytes than the
// file holds is refused before either reader runs.
#include <memory>
#include <string>

struct aiScene;
namespace Assimp {
class Importer;
}

namespace pleat {

class SceneFile {
 public:
  // Throws PLEAT_ERROR_IO (unreadable, a directory) or PLEAT_ERROR_FORMAT
  // (the reader's reason, naming the file).
  explicit SceneFile(const std::string& path);
  ~SceneFile();
  SceneFile(const SceneFile&) = delete;
  SceneFile& operator=(const SceneFile&) = delete;

  const aiScene& scene() const { return *scene_; }
  // Metres per file unit: FBX stores centimetres per unit
  // ("UnitScaleFactor"); glTF is metres by specification, and other formats
  // carry no unit and are taken as metres (1).
  double unit_scale() const;

 private:
  std::unique_ptr<Assimp::Importer> importer_;  // owns an assimp scene
  std::unique_ptr<aiScene> gltf_;               // or the glTF one
  const aiScene* scene_ = nullptr;
};

}  // namespace pleat
