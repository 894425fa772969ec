// Library-wide entry points: versions, errors, and the dlopen function table.
#include "capi/firewall.h"

namespace pleat::capi {
namespace {
thread_local std::string last_error;
thread_local const char* fixed_error = nullptr;  // set when last_error could not be
}  // namespace

void set_last_error(const char* function, const char* prefix, const char* detail) noexcept {
  try {
    last_error.assign(function).append(": ").append(prefix).append(detail);
    fixed_error = nullptr;
  } catch (...) {
    fixed_error = "out of memory while reporting an error";
  }
}
}  // namespace pleat::capi

extern "C" {

uint32_t pleat_version(void) {
  return PLEAT_VERSION_NUMBER;
}

const char* pleat_last_error(void) {
  return pleat::capi::fixed_error ? pleat::capi::fixed_error : pleat::capi::last_error.c_str();
}

const char* pleat_status_name(pleat_status status) {
  switch (status) {
    case PLEAT_OK: return "PLEAT_OK";
    case PLEAT_ERROR_INVALID_ARGUMENT: return "PLEAT_ERROR_INVALID_ARGUMENT";
    case PLEAT_ERROR_IO: return "PLEAT_ERROR_IO";
    case PLEAT_ERROR_FORMAT: return "PLEAT_ERROR_FORMAT";
    case PLEAT_ERROR_INVALID_MESH: return "PLEAT_ERROR_INVALID_MESH";
    case PLEAT_ERROR_UNSUPPORTED_VERSION: return "PLEAT_ERROR_UNSUPPORTED_VERSION";
    case PLEAT_ERROR_OUT_OF_MEMORY: return "PLEAT_ERROR_OUT_OF_MEMORY";
    case PLEAT_ERROR_BUFFER_TOO_SMALL: return "PLEAT_ERROR_BUFFER_TOO_SMALL";
    case PLEAT_ERROR_NUMERICAL: return "PLEAT_ERROR_NUMERICAL";
    case PLEAT_ERROR_NOT_PREPARED: return "PLEAT_ERROR_NOT_PREPARED";
    case PLEAT_ERROR_INTERNAL: return "PLEAT_ERROR_INTERNAL";
    default: return "PLEAT_ERROR_UNKNOWN";
  }
}

const pleat_api* pleat_get_api(uint32_t version) {
  static const pleat_api table = {
      sizeof(pleat_api),
      PLEAT_API_VERSION,
      pleat_version,
      pleat_last_error,
      pleat_status_name,
      pleat_garment_load,
      pleat_garment_create,
      pleat_garment_destroy,
      pleat_garment_get_report,
      pleat_garment_get_mesh,
      pleat_garment_prepare,
      pleat_garment_get_band_info,
      pleat_garment_save,
      pleat_garment_split_bands,
      pleat_metrics_compute,
      pleat_cache_get_info,
      pleat_cache_read,
      pleat_cache_write,
      pleat_body_load,
      pleat_body_destroy,
      pleat_body_get_info,
      pleat_body_joint_name,
      pleat_body_shape_name,
      pleat_body_get_shape,
      pleat_body_set_shape,
      pleat_body_get_rest,
      pleat_body_pose_motion,
      pleat_motion_load,
      pleat_motion_destroy,
      pleat_motion_get_info,
      pleat_motion_joint_name,
      pleat_motion_resample,
      pleat_motion_retarget,
      pleat_motion_get_frames,
      pleat_mesh_write_obj,
      pleat_body_create,
      pleat_body_pose,
      // API version 2: models and instances.
      pleat_model_load,
      pleat_model_initialize,
      pleat_model_save,
      pleat_model_destroy,
      pleat_model_get_info,
      pleat_model_joint_name,
      pleat_instance_create,
      pleat_instance_destroy,
      pleat_instance_get_info,
      pleat_instance_evaluate,
      // API version 3.
      pleat_instance_evaluate_motion,
      // API version 4.
      pleat_instance_set_vertex_mask,
  };
  // Every version up to the current one is served by the same, grown table:
  // older callers only read its prefix.
  if (version == 0 || version > PLEAT_API_VERSION) return nullptr;
  return &table;
}

}  // extern "C"
