/* dlopen conformance: the library is usable through pleat_get_api alone, the
   table describes itself, and versions it does not serve give NULL. */
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

#include "capi/pleat.h"

static int failures = 0;
static int checks = 0;
#define CHECK(cond)                                                            \
  do {                                                                         \
    ++checks;                                                                  \
    if (!(cond)) {                                                             \
      ++failures;                                                              \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                          \
  } while (0)

int main(int argc, char** argv) {
  void* library;
  pleat_get_api_fn get_api;
  const pleat_api* api;
  pleat_garment* garment = NULL;
  pleat_status status;
  if (argc != 2) return 2;
  library = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (!library) {
    fprintf(stderr, "dlopen: %s\n", dlerror());
    return 1;
  }
  *(void**)(&get_api) = dlsym(library, "pleat_get_api");
  CHECK(get_api != NULL);
  if (!get_api) return 1;

  api = get_api(PLEAT_API_VERSION);
  CHECK(api != NULL);
  if (!api) return 1;
  CHECK(api->struct_size == sizeof(pleat_api));
  CHECK(api->version == PLEAT_API_VERSION);
  CHECK(get_api(PLEAT_API_VERSION + 1) == NULL);
  CHECK(get_api(0) == NULL);
  CHECK(api->version_number() == PLEAT_VERSION_NUMBER);
  CHECK(strcmp(api->status_name(PLEAT_ERROR_IO), "PLEAT_ERROR_IO") == 0);

  /* Every slot of the table is filled. */
  {
    const char* base = (const char*)api;
    size_t offset;
    for (offset = 8; offset < sizeof(pleat_api); offset += sizeof(void*)) {
      void* slot;
      memcpy(&slot, base + offset, sizeof slot);
      CHECK(slot != NULL);
    }
  }

  /* Errors come back as a status and a message naming the file. */
  status = api->garment_load("/nonexistent/shirt.obj", NULL, &garment);
  CHECK(status == PLEAT_ERROR_IO);
  CHECK(garment == NULL);
  CHECK(strstr(api->last_error(), "/nonexistent/shirt.obj") != NULL);
  status = api->garment_load(NULL, NULL, &garment);
  CHECK(status == PLEAT_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(api->last_error(), "path") != NULL);
  api->garment_destroy(NULL);

  dlclose(library);
  printf("abi_dlopen: %d passed, %d failed\n", checks - failures, failures);
  return failures == 0 ? 0 : 1;
}
