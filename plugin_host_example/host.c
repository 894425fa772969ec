/*
 * A minimal host, in C, that uses pleat the way an engine or DCC plug-in
 * does: dlopen the library, resolve pleat_get_api, and call through the table.
 *
 *   plugin_host_example <path/to/libpleat.so.0> <garment.obj|.fbx|.gltf|.pleatg>
 *
 * It loads and prepares the garment, splits its rest shape into the low, mid
 * and high frequency bands and prints each band's energy.
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

  if (argc != 3) {
    fprintf(stderr, "usage: %s <libpleat.so> <garment file>\n", argv[0]);
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

done:
  free(rest);
  free(low);
  free(mid);
  free(high);
  api->garment_destroy(garment);
  dlclose(library);
  return result;
}
