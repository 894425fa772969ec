# Blender side of `pleat datagen`: simulates one garment on one animated body
# and writes the garment's positions per frame. Run by pleat-datagen as
#   blender -b --factory-startup -noaudio --python-exit-code 3 -P simulate_cloth.py -- job.json
# job.json (written by datagen/blender_job.cpp) names the inputs and every
# simulator setting. Coordinates stay pleat's (metres, Y up): the scene's
# gravity points down -Y instead of converting axes, so no vertex is ever
# transformed on the way in or out.
#
# Inputs: the rest collider (the body, or a low-poly proxy of it) and garment as
# OBJ ("v" and "f" lines, read here so the vertex order is exactly the file's),
# the posed collider per frame as PC2 (a MESH_CACHE modifier, then COLLISION),
# and the garment skinned to the body as PC2 (a MESH_CACHE modifier before
# CLOTH, so pinned vertices follow the body).
# Outputs: the simulated garment as PC2 and result.json (Blender version,
# timing, how far the evaluated collider strayed from collider.pc2).
# Progress goes to stdout as "PLEAT_FRAME <done> <total>" lines.
import array
import json
import os
import struct
import sys
import time

import bpy


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append((float(parts[1]), float(parts[2]), float(parts[3])))
            elif parts[0] == "f":
                faces.append([int(p.split("/")[0]) - 1 for p in parts[1:]])
    return vertices, faces


def read_pc2(path):
    with open(path, "rb") as f:
        header = f.read(32)
        if header[:12] != b"POINTCACHE2\0":
            raise RuntimeError(path + ": not a PC2 file")
        _, points, _, _, samples = struct.unpack("<iiffi", header[12:32])
        data = array.array("f")
        data.frombytes(f.read())
    if sys.byteorder != "little":
        data.byteswap()
    if len(data) != points * samples * 3:
        raise RuntimeError(path + ": %d floats, expected %d" % (len(data), points * samples * 3))
    return points, samples, data


def write_pc2(path, points, frames, fps):
    data = array.array("f")
    for frame in frames:
        data.extend(frame)
    if sys.byteorder != "little":
        data.byteswap()
    temporary = path + ".partial"
    with open(temporary, "wb") as f:
        f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, points, 0.0, 1.0, len(frames)))
        f.write(data.tobytes())
    os.replace(temporary, path)


def make_object(name, vertices, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_mesh_cache(obj, path):
    cache = obj.modifiers.new("pleat_cache", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = path
    cache.time_mode = "FRAME"
    cache.play_mode = "SCENE"
    cache.frame_start = 1.0  # scene frame 1 shows sample 0
    cache.forward_axis = "POS_Y"  # identity: the cache is in scene coordinates
    cache.up_axis = "POS_Z"
    return cache


def evaluated_positions(obj, depsgraph, count):
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    if len(mesh.vertices) != count:
        raise RuntimeError("%s: %d vertices after evaluation, expected %d" % (obj.name, len(mesh.vertices), count))
    out = array.array("f", bytes(4 * 3 * count))
    mesh.vertices.foreach_get("co", out)
    evaluated.to_mesh_clear()
    return out


def main():
    job_path = sys.argv[sys.argv.index("--") + 1]
    with open(job_path) as f:
        job = json.load(f)
    here = os.path.dirname(os.path.abspath(job_path))
    path = lambda name: os.path.join(here, job["files"][name])
    cloth_settings, collision = job["cloth"], job["collision"]

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    scene.gravity = (0.0, -9.81, 0.0)
    scene.render.fps = int(round(job["frame_rate"]))
    scene.render.fps_base = scene.render.fps / job["frame_rate"]
    frames = job["frame_count"]
    scene.frame_start, scene.frame_end = 1, frames

    collider_vertices, collider_faces = read_obj(path("collider_obj"))
    collider = make_object("collider", collider_vertices, collider_faces)
    add_mesh_cache(collider, path("collider_pc2"))
    collider.modifiers.new("pleat_collision", "COLLISION")
    collider.collision.thickness_outer = collision["body_thickness"]
    collider.collision.thickness_inner = collision["body_thickness_inner"]
    collider.collision.cloth_friction = collision["friction"]
    collider.collision.damping = collision["damping"]

    garment_vertices, garment_faces = read_obj(path("garment_obj"))
    garment = make_object("garment", garment_vertices, garment_faces)
    add_mesh_cache(garment, path("garment_skinned_pc2"))
    if job["pinned"]:
        group = garment.vertex_groups.new(name="pleat_pin")
        group.add(job["pinned"], 1.0, "REPLACE")
    cloth = garment.modifiers.new("pleat_cloth", "CLOTH")
    s = cloth.settings
    s.quality = cloth_settings["quality"]
    s.mass = cloth_settings["mass"]
    s.air_damping = cloth_settings["air_damping"]
    s.tension_stiffness = cloth_settings["tension_stiffness"]
    s.compression_stiffness = cloth_settings["compression_stiffness"]
    s.shear_stiffness = cloth_settings["shear_stiffness"]
    s.bending_stiffness = cloth_settings["bending_stiffness"]
    s.tension_damping = cloth_settings["tension_damping"]
    s.compression_damping = cloth_settings["compression_damping"]
    s.shear_damping = cloth_settings["shear_damping"]
    s.bending_damping = cloth_settings["bending_damping"]
    if job["pinned"]:
        s.vertex_group_mass = "pleat_pin"
        s.pin_stiffness = cloth_settings["pin_stiffness"]
    c = cloth.collision_settings
    c.use_collision = True
    c.collision_quality = collision["quality"]
    c.distance_min = collision["distance"]
    c.use_self_collision = collision["self_collision"]
    c.self_distance_min = collision["self_distance"]
    c.self_friction = collision["self_friction"]
    cloth.point_cache.frame_start = 1
    cloth.point_cache.frame_end = frames

    collider_points, collider_samples, collider_cache = read_pc2(path("collider_pc2"))
    if collider_points != len(collider_vertices) or collider_samples != frames:
        raise RuntimeError("collider.pc2 has %d points x %d samples, expected %d x %d"
                           % (collider_points, collider_samples, len(collider_vertices), frames))
    n = len(garment_vertices)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    start = time.time()
    simulated = []
    collider_error = 0.0
    for f in range(frames):
        scene.frame_set(f + 1)
        simulated.append(evaluated_positions(garment, depsgraph, n))
        if f % 10 == 0 or f == frames - 1:  # the collider the cloth saw is collider.pc2's sample f
            posed = evaluated_positions(collider, depsgraph, collider_points)
            offset = f * collider_points * 3
            collider_error = max(collider_error, max(abs(posed[i] - collider_cache[offset + i])
                                                     for i in range(0, len(posed), 7)))
        print("PLEAT_FRAME %d %d" % (f + 1, frames), flush=True)
    seconds = time.time() - start

    write_pc2(path("garment_sim_pc2"), n, simulated, job["frame_rate"])
    result = {"blender_version": bpy.app.version_string, "simulation_seconds": seconds,
              "collider_cache_max_error": collider_error}
    with open(path("result") + ".partial", "w") as f:
        json.dump(result, f)
    os.replace(path("result") + ".partial", path("result"))


main()
