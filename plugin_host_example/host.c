/*
 * A minimal host, in C, that uses pleat the way an engine or DCC plug-in
 * does: dlopen the library, resolve pleat_get_api, and call through the table.
 *
 *   plugin_host_example <path/to/libpleat.so.0> <garment.obj|.fbx|.gltf|.pleatg>
 *                       [<model.pleat> <body> <motion.bvh> <out_####.obj> [frames]]
 *
 * It loads and prepares the garment, splits its rest shape into the low, mid
 * and high frequency bands and prints each band's energy. Given a model, a
 * body (a MakeHuman assets folder, an SMPL-layout .npz or a rigged mesh) and
 * a motion, it then binds the model to the garment and the body, evaluates
 * the first frames of the motion (default 30) and writes them as an OBJ
 * sequence ('#'s in the name become the frame number).
 */
#define _GNU_SOURCE /* RTLD_NODELETE */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "capi/pleat.h"

static double rms(const float* x, size_t vertex_count) {
  double sum = 0.0;
  size_t i;
  for (i = 0; i < vertex_count * 3; ++i) sum += (double)x[i] * x[i];
  return sqrt(sum / (double)vertex_count);
}

static int fail(const pleat_api* api, pleat_status status, const char* what) {
  fprintf(stderr, "%s failed: %s: %s\n", what, api->status_name(status), api->last_error());
  return 1;
}

/* The animation part: model + body + motion -> OBJ sequence. */
static int animate(const pleat_api* api, const pleat_garment* garment, const char* model_path,
                   const char* body_path, const char* motion_path, const char* out_pattern, size_t frames) {
  pleat_model* model = NULL;
  pleat_body* body = NULL;
  pleat_motion *clip = NULL, *resampled = NULL, *motion = NULL;
  pleat_instance* instance = NULL;
  pleat_model_info model_info = {0};
  pleat_motion_info motion_info = {0};
  pleat_instance_info info = {0};
  pleat_evaluate_outputs outputs = {0};
  pleat_const_frames written;
  float* positions = NULL;
  pleat_status status;
  const char* step = "loading the model";
  int result = 1;

  status = api->model_load(model_path, &model);
  if (status == PLEAT_OK) {
    step = "loading the body";
    status = api->body_load(body_path, NULL, &body);
  }
  if (status == PLEAT_OK) {
    step = "loading the motion";
    status = api->motion_load(motion_path, NULL, &clip);
  }
  if (status == PLEAT_OK) {
    model_info.struct_size = sizeof model_info;
    api->model_get_info(model, &model_info);
    step = "resampling the motion to the model's frame rate";
    status = api->motion_resample(clip, model_info.frame_rate, &resampled);
  }
  if (status == PLEAT_OK) {
    step = "retargeting the motion onto the body";
    status = api->motion_retarget(resampled, body, NULL, &motion);
  }
  if (status == PLEAT_OK) {
    step = "binding the model to the garment and the body";
    status = api->instance_create(model, garment, body, NULL, &instance);
  }
  if (status != PLEAT_OK) {
    result = fail(api, status, step);
    goto done;
  }
  info.struct_size = sizeof info;
  motion_info.struct_size = sizeof motion_info;
  api->instance_get_info(instance, &info);
  api->motion_get_info(motion, &motion_info);
  if (frames > motion_info.frame_count) frames = (size_t)motion_info.frame_count;
  printf("instance: %u vertices, %u joints, top-%u skinning; evaluating %zu frames at %g fps\n",
         info.vertex_count, info.joint_count, info.top_k, frames, info.frame_rate);

  positions = malloc(frames * info.vertex_count * 3 * sizeof *positions);
  if (!positions) {
    fprintf(stderr, "out of memory\n");
    goto done;
  }
  outputs.struct_size = sizeof outputs;
  outputs.positions.data = positions;
  status = api->instance_evaluate_motion(instance, motion, 0, frames, NULL, &outputs);
  if (status != PLEAT_OK) {
    result = fail(api, status, "evaluating the frames");
    goto done;
  }
  written.data = positions;
  written.frame_stride = 0;
  status = api->cache_write(out_pattern, PLEAT_CACHE_OBJ_SEQUENCE, garment, written, frames,
                            info.vertex_count, info.frame_rate);
  if (status != PLEAT_OK) {
    result = fail(api, status, "writing the OBJ sequence");
    goto done;
  }
  printf("wrote %zu frames to %s\n", frames, out_pattern);
  result = 0;

done:
  free(positions);
  api->instance_destroy(instance);
  api->motion_destroy(motion);
  api->motion_destroy(resampled);
  api->motion_destroy(clip);
  api->body_destroy(body);
  api->model_destroy(model);
  return result;
}

int main(int argc, char** argv) {
  void* library;
  pleat_get_api_fn get_api;
  const pleat_api* api;
  pleat_garment* garment = NULL;
  pleat_mesh_report report = {0};
  pleat_band_info bands = {0};
  pleat_status status;
  float *rest = NULL, *low = NULL, *mid = NULL, *high = NULL;
  size_t n;
  int result = 1;

  if (argc != 3 && argc != 7 && argc != 8) {
    fprintf(
        stderr,
        "usage: %s <libpleat.so> <garment file> [<model.pleat> <body> <motion> <out_####.obj> [frames]]\n",
        argv[0]);
    return 2;
  }
  /* RTLD_NODELETE: the library keeps OpenBLAS worker threads and one-time
     allocations; a host keeps it mapped for its whole life rather than
     unmapping code under them at dlclose. */
  library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (!library) {
    fprintf(stderr, "dlopen failed: %s\n", dlerror());
    return 1;
  }
  /* POSIX allows this conversion; ISO C does not name it, hence the copy. */
  *(void**)(&get_api) = dlsym(library, "pleat_get_api");
  if (!get_api) {
    fprintf(stderr, "pleat_get_api not found: %s\n", dlerror());
    dlclose(library);
    return 1;
  }
  api = get_api(PLEAT_API_VERSION);
  if (!api) {
    fprintf(stderr, "the library does not serve API version %u\n", PLEAT_API_VERSION);
    dlclose(library);
    return 1;
  }
  printf("pleat library %u.%u.%u, API table version %u\n", api->version_number() >> 16,
         (api->version_number() >> 8) & 0xffu, api->version_number() & 0xffu, api->version);

  status = api->garment_load(argv[2], NULL, &garment);
  if (status != PLEAT_OK) {
    result = fail(api, status, "loading the garment");
    goto done;
  }
  report.struct_size = sizeof report;
  api->garment_get_report(garment, &report);
  printf("garment: %u vertices, %u triangles, %u components\n", report.vertex_count, report.triangle_count,
         report.component_count);

  status = api->garment_prepare(garment, NULL);
  if (status != PLEAT_OK) {
    result = fail(api, status, "preparing the garment");
    goto done;
  }
  bands.struct_size = sizeof bands;
  api->garment_get_band_info(garment, &bands);
  printf("bands: %u low and %u low+mid eigenvectors\n", bands.low_count, bands.mid_count);

  n = report.vertex_count;
  rest = malloc(n * 3 * sizeof *rest);
  low = malloc(n * 3 * sizeof *low);
  mid = malloc(n * 3 * sizeof *mid);
  high = malloc(n * 3 * sizeof *high);
  if (!rest || !low || !mid || !high) {
    fprintf(stderr, "out of memory\n");
    goto done;
  }
  status = api->garment_get_mesh(garment, rest, n * 3, NULL, 0);
  if (status == PLEAT_OK) {
    pleat_const_frames in;
    pleat_frames out_low, out_mid, out_high;
    in.data = rest;
    in.frame_stride = 0;
    out_low.data = low;
    out_low.frame_stride = 0;
    out_mid.data = mid;
    out_mid.frame_stride = 0;
    out_high.data = high;
    out_high.frame_stride = 0;
    status = api->garment_split_bands(garment, in, 1, out_low, out_mid, out_high);
  }
  if (status != PLEAT_OK) {
    result = fail(api, status, "splitting the rest shape");
    goto done;
  }
  printf("band energy (RMS per vertex, m): low %.6f  mid %.6f  high %.6f\n", rms(low, n), rms(mid, n),
         rms(high, n));
  result = 0;
  if (argc >= 7)
    result =
        animate(api, garment, argv[3], argv[4], argv[5], argv[6], argc == 8 ? (size_t)atol(argv[7]) : 30);

done:
  free(rest);
  free(low);
  free(mid);
  free(high);
  api->garment_destroy(garment);
  dlclose(library);
  return result;
}
