/* The public header compiles as strict C11, and the ABI's layout is pinned
   here: moving a field of the function table or of a public struct breaks the
   build. Offsets are for LP64 (Linux, macOS on 64-bit). */
#include <stddef.h>

#include "capi/pleat.h"

#define PIN(type, field, offset) _Static_assert(offsetof(type, field) == (offset), #type "." #field " moved")
#define SIZE(type, size) _Static_assert(sizeof(type) == (size), #type " changed size")

PIN(pleat_api, struct_size, 0);
PIN(pleat_api, version, 4);
PIN(pleat_api, version_number, 8);
PIN(pleat_api, last_error, 16);
PIN(pleat_api, status_name, 24);
PIN(pleat_api, garment_load, 32);
PIN(pleat_api, garment_create, 40);
PIN(pleat_api, garment_destroy, 48);
PIN(pleat_api, garment_get_report, 56);
PIN(pleat_api, garment_get_mesh, 64);
PIN(pleat_api, garment_prepare, 72);
PIN(pleat_api, garment_get_band_info, 80);
PIN(pleat_api, garment_save, 88);
PIN(pleat_api, garment_split_bands, 96);
PIN(pleat_api, metrics_compute, 104);
PIN(pleat_api, cache_get_info, 112);
PIN(pleat_api, cache_read, 120);
PIN(pleat_api, cache_write, 128);
PIN(pleat_api, body_load, 136);
PIN(pleat_api, body_destroy, 144);
PIN(pleat_api, body_get_info, 152);
PIN(pleat_api, body_joint_name, 160);
PIN(pleat_api, body_shape_name, 168);
PIN(pleat_api, body_get_shape, 176);
PIN(pleat_api, body_set_shape, 184);
PIN(pleat_api, body_get_rest, 192);
PIN(pleat_api, body_pose_motion, 200);
PIN(pleat_api, motion_load, 208);
PIN(pleat_api, motion_destroy, 216);
PIN(pleat_api, motion_get_info, 224);
PIN(pleat_api, motion_joint_name, 232);
PIN(pleat_api, motion_resample, 240);
PIN(pleat_api, motion_retarget, 248);
PIN(pleat_api, motion_get_frames, 256);
PIN(pleat_api, mesh_write_obj, 264);
PIN(pleat_api, body_create, 272);
PIN(pleat_api, body_pose, 280);
PIN(pleat_api, model_load, 288);
PIN(pleat_api, model_initialize, 296);
PIN(pleat_api, model_save, 304);
PIN(pleat_api, model_destroy, 312);
PIN(pleat_api, model_get_info, 320);
PIN(pleat_api, model_joint_name, 328);
PIN(pleat_api, instance_create, 336);
PIN(pleat_api, instance_destroy, 344);
PIN(pleat_api, instance_get_info, 352);
PIN(pleat_api, instance_evaluate, 360);
PIN(pleat_api, instance_evaluate_motion, 368);
PIN(pleat_api, instance_set_vertex_mask, 376);
SIZE(pleat_api, 384);

PIN(pleat_const_frames, data, 0);
PIN(pleat_const_frames, frame_stride, 8);
SIZE(pleat_const_frames, 16);
PIN(pleat_frames, data, 0);
PIN(pleat_frames, frame_stride, 8);
SIZE(pleat_frames, 16);

PIN(pleat_garment_load_options, struct_size, 0);
PIN(pleat_garment_load_options, weld_tolerance, 8);
PIN(pleat_garment_load_options, unit_scale, 16);
SIZE(pleat_garment_load_options, 24);

PIN(pleat_mesh_report, struct_size, 0);
PIN(pleat_mesh_report, input_vertex_count, 4);
PIN(pleat_mesh_report, vertex_count, 8);
PIN(pleat_mesh_report, triangle_count, 12);
PIN(pleat_mesh_report, welded_vertex_count, 16);
PIN(pleat_mesh_report, component_count, 20);
PIN(pleat_mesh_report, boundary_loop_count, 24);
PIN(pleat_mesh_report, non_manifold_edge_count, 28);
PIN(pleat_mesh_report, degenerate_triangle_count, 32);
PIN(pleat_mesh_report, isolated_vertex_count, 36);
PIN(pleat_mesh_report, units, 40);
PIN(pleat_mesh_report, bbox_min, 48);
PIN(pleat_mesh_report, bbox_max, 60);
PIN(pleat_mesh_report, total_area, 72);
SIZE(pleat_mesh_report, 80);

PIN(pleat_prepare_options, struct_size, 0);
PIN(pleat_prepare_options, solver, 4);
PIN(pleat_prepare_options, projection, 8);
PIN(pleat_prepare_options, low_fraction, 16);
PIN(pleat_prepare_options, mid_fraction, 24);
PIN(pleat_prepare_options, geodesic_radius, 32);
SIZE(pleat_prepare_options, 40);

PIN(pleat_band_info, struct_size, 0);
PIN(pleat_band_info, vertex_count, 4);
PIN(pleat_band_info, low_count, 8);
PIN(pleat_band_info, mid_count, 12);
PIN(pleat_band_info, low_count_requested, 16);
PIN(pleat_band_info, mid_count_requested, 20);
PIN(pleat_band_info, solver, 24);
PIN(pleat_band_info, projection, 28);
PIN(pleat_band_info, low_gap, 32);
PIN(pleat_band_info, mid_gap, 40);
PIN(pleat_band_info, geodesic_radius, 48);
PIN(pleat_band_info, geodesic_pair_count, 56);
SIZE(pleat_band_info, 64);

PIN(pleat_metrics_options, struct_size, 0);
PIN(pleat_metrics_options, flags, 4);
PIN(pleat_metrics_options, collision_prefilter, 8);
SIZE(pleat_metrics_options, 16);

PIN(pleat_metrics, struct_size, 0);
PIN(pleat_metrics, computed, 4);
PIN(pleat_metrics, frame_count, 8);
PIN(pleat_metrics, e_verts_cm, 16);
PIN(pleat_metrics, e_vnorm_deg, 24);
PIN(pleat_metrics, e_fnorm_deg, 32);
PIN(pleat_metrics, e_edge_percent, 40);
PIN(pleat_metrics, e_curv, 48);
PIN(pleat_metrics, e_low_cm, 56);
PIN(pleat_metrics, e_mid_cm, 64);
PIN(pleat_metrics, e_high_cm, 72);
PIN(pleat_metrics, self_collision_percent, 80);
SIZE(pleat_metrics, 88);

PIN(pleat_cache_info, struct_size, 0);
PIN(pleat_cache_info, format, 4);
PIN(pleat_cache_info, frame_count, 8);
PIN(pleat_cache_info, vertex_count, 16);
PIN(pleat_cache_info, frame_rate, 24);
PIN(pleat_cache_info, start_time, 32);
SIZE(pleat_cache_info, 40);

PIN(pleat_body_load_options, struct_size, 0);
PIN(pleat_body_load_options, kind, 4);
PIN(pleat_body_load_options, rig, 8);
SIZE(pleat_body_load_options, 16);

PIN(pleat_body_info, struct_size, 0);
PIN(pleat_body_info, vertex_count, 4);
PIN(pleat_body_info, triangle_count, 8);
PIN(pleat_body_info, joint_count, 12);
PIN(pleat_body_info, shape_count, 16);
PIN(pleat_body_info, max_influences, 20);
SIZE(pleat_body_info, 24);

PIN(pleat_motion_load_options, struct_size, 0);
PIN(pleat_motion_load_options, clip, 4);
PIN(pleat_motion_load_options, unit_scale, 8);
SIZE(pleat_motion_load_options, 16);

PIN(pleat_motion_info, struct_size, 0);
PIN(pleat_motion_info, joint_count, 4);
PIN(pleat_motion_info, frame_count, 8);
PIN(pleat_motion_info, frame_rate, 16);
PIN(pleat_motion_info, unit_scale, 24);
SIZE(pleat_motion_info, 32);

PIN(pleat_body_desc, struct_size, 0);
PIN(pleat_body_desc, joint_count, 4);
PIN(pleat_body_desc, joint_names, 8);
PIN(pleat_body_desc, parents, 16);
PIN(pleat_body_desc, joint_positions, 24);
PIN(pleat_body_desc, vertex_count, 32);
PIN(pleat_body_desc, positions, 40);
PIN(pleat_body_desc, triangle_count, 48);
PIN(pleat_body_desc, triangles, 56);
PIN(pleat_body_desc, influences, 64);
PIN(pleat_body_desc, weight_joints, 72);
PIN(pleat_body_desc, weights, 80);
SIZE(pleat_body_desc, 88);

PIN(pleat_model_info, struct_size, 0);
PIN(pleat_model_info, format_version, 4);
PIN(pleat_model_info, joint_count, 8);
PIN(pleat_model_info, shape_count, 12);
PIN(pleat_model_info, window_frames, 16);
PIN(pleat_model_info, variant, 20);
PIN(pleat_model_info, default_top_k, 24);
PIN(pleat_model_info, code_width, 28);
PIN(pleat_model_info, frame_rate, 32);
PIN(pleat_model_info, parameter_count, 40);
PIN(pleat_model_info, offset_filter_length, 48);
PIN(pleat_model_info, skinning_prior_radius, 56);
PIN(pleat_model_info, skinning_prior_floor, 64);
SIZE(pleat_model_info, 72);

PIN(pleat_model_init_options, struct_size, 0);
PIN(pleat_model_init_options, variant, 4);
PIN(pleat_model_init_options, window_frames, 8);
PIN(pleat_model_init_options, seed, 16);
PIN(pleat_model_init_options, frame_rate, 24);
SIZE(pleat_model_init_options, 32);

PIN(pleat_instance_options, struct_size, 0);
PIN(pleat_instance_options, threads, 4);
PIN(pleat_instance_options, top_k, 8);
PIN(pleat_instance_options, max_batch, 12);
SIZE(pleat_instance_options, 16);

PIN(pleat_instance_info, struct_size, 0);
PIN(pleat_instance_info, vertex_count, 4);
PIN(pleat_instance_info, joint_count, 8);
PIN(pleat_instance_info, top_k, 12);
PIN(pleat_instance_info, window_frames, 16);
PIN(pleat_instance_info, max_batch, 20);
PIN(pleat_instance_info, frame_rate, 24);
SIZE(pleat_instance_info, 32);

PIN(pleat_poses, struct_size, 0);
PIN(pleat_poses, joint_count, 4);
PIN(pleat_poses, frame_count, 8);
PIN(pleat_poses, rotations, 16);
PIN(pleat_poses, root_positions, 24);
PIN(pleat_poses, frame_rate, 32);
SIZE(pleat_poses, 40);

PIN(pleat_evaluate_options, struct_size, 0);
PIN(pleat_evaluate_options, stage, 4);
PIN(pleat_evaluate_options, refinement_interval, 8);
PIN(pleat_evaluate_options, band_attenuation, 12);
PIN(pleat_evaluate_options, body_collision_distance, 24);
SIZE(pleat_evaluate_options, 28);

PIN(pleat_evaluate_outputs, struct_size, 0);
PIN(pleat_evaluate_outputs, positions, 8);
PIN(pleat_evaluate_outputs, normals, 24);
PIN(pleat_evaluate_outputs, skinning_weights, 40);
PIN(pleat_evaluate_outputs, low, 56);
PIN(pleat_evaluate_outputs, mid, 72);
PIN(pleat_evaluate_outputs, high, 88);
SIZE(pleat_evaluate_outputs, 104);
