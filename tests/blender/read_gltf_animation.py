# Blender script (tests/test_cli.cpp): imports a glTF morph animation the way
# an artist would and writes what Blender made of it as JSON: the mesh's
# vertex count, its shape keys, the keyframes of the weights animation and the
# evaluated positions of a few vertices at every keyed frame.
# blender -b --factory-startup -P read_gltf_animation.py -- in.glb out.json
import json
import sys

import bpy
import numpy

# Debian's Blender 3.4 glTF importer still calls numpy.bool, which numpy 1.24
# removed; the alias restores it.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

source, target = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = 30  # pleat's frame rate: keys land on whole frames
bpy.ops.import_scene.gltf(filepath=source)
meshes = [o for o in scene.objects if o.type == "MESH"]
obj = meshes[0]
keys = obj.data.shape_keys
action = keys.animation_data.action if keys and keys.animation_data else None
frames = sorted({round(k.co[0]) for c in action.fcurves for k in c.keyframe_points}) if action else [scene.frame_current]
probe = [0, 1, len(obj.data.vertices) // 2, len(obj.data.vertices) - 1]
positions = []
for f in frames:
    scene.frame_set(f)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    positions.append([list(evaluated.matrix_world @ evaluated.data.vertices[v].co) for v in probe])
with open(target, "w") as out:
    json.dump({"meshes": len(meshes), "vertices": len(obj.data.vertices),
               "shape_keys": len(keys.key_blocks) if keys else 0, "frames": frames,
               "probe": probe, "positions": positions}, out)
