/*
 * pleat: learned garment deformation behind a stable C ABI.
 *
 * This is the only public header. It compiles as C99 and C++, includes only
 * <stddef.h> and <stdint.h>, and follows these rules (docs/c_api.md):
 *
 *  - Every fallible function returns pleat_status (PLEAT_OK = 0). On failure its
 *    outputs are left untouched and pleat_last_error() names the file, field or
 *    index at fault.
 *  - Objects are opaque handles with a destroy function that accepts NULL.
 *    Garments are immutable once prepared and may then be shared by threads.
 *  - Options structs begin with uint32_t struct_size; a NULL options pointer or
 *    a zero field means "use the default". Only fixed-width fields.
 *  - dlopen users call pleat_get_api(PLEAT_API_VERSION) and use the table; its
 *    layout only ever grows and is pinned by offsetof checks in the tests.
 *
 * Conventions: metres, right-handed, Y up. Positions are float32 xyz triples.
 * A "frames" buffer holds frame_count frames of vertex_count xyz triples; its
 * frame_stride is the distance in floats between the starts of two frames
 * (0 means tightly packed, vertex_count * 3).
 */
#ifndef PLEAT_H
#define PLEAT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define PLEAT_EXPORT __declspec(dllexport)
#else
#define PLEAT_EXPORT __attribute__((visibility("default")))
#endif

/* ---- Versions ------------------------------------------------------------ */

#define PLEAT_VERSION_MAJOR 0
#define PLEAT_VERSION_MINOR 1
#define PLEAT_VERSION_PATCH 0
#define PLEAT_VERSION_STRING "0.1.0"
/* (major << 16) | (minor << 8) | patch, as returned by pleat_version(). */
#define PLEAT_VERSION_NUMBER ((PLEAT_VERSION_MAJOR << 16) | (PLEAT_VERSION_MINOR << 8) | PLEAT_VERSION_PATCH)
/* Version of the function table returned by pleat_get_api(): 1 = garments,
   metrics, caches, bodies, motions; 2 = + models and instances; 3 = +
   instance_evaluate_motion; 4 = + instance_set_vertex_mask. */
#define PLEAT_API_VERSION 4u

/* ---- Status codes -------------------------------------------------------- */

typedef int32_t pleat_status;
#define PLEAT_OK 0
#define PLEAT_ERROR_INVALID_ARGUMENT 1    /* NULL pointer, bad size, bad option */
#define PLEAT_ERROR_IO 2                  /* file missing, unreadable, unwritable */
#define PLEAT_ERROR_FORMAT 3              /* file content malformed or truncated */
#define PLEAT_ERROR_INVALID_MESH 4        /* mesh cannot be used (empty, NaN, ...) */
#define PLEAT_ERROR_UNSUPPORTED_VERSION 5 /* file written by a newer pleat */
#define PLEAT_ERROR_OUT_OF_MEMORY 6
#define PLEAT_ERROR_BUFFER_TOO_SMALL 7 /* caller buffer smaller than required */
#define PLEAT_ERROR_NUMERICAL 8        /* solver failed to converge, NaN result */
#define PLEAT_ERROR_NOT_PREPARED 9     /* garment lacks the prepared data asked for */
#define PLEAT_ERROR_INTERNAL 10        /* a bug in pleat: please report it */

/* ---- Handles ------------------------------------------------------------- */

typedef struct pleat_garment pleat_garment;
typedef struct pleat_body pleat_body;
typedef struct pleat_motion pleat_motion;
typedef struct pleat_model pleat_model;
typedef struct pleat_instance pleat_instance;

/* ---- Plain data ---------------------------------------------------------- */

typedef struct pleat_const_frames {
  const float* data;
  size_t frame_stride; /* floats between frame starts; 0 = vertex_count * 3 */
} pleat_const_frames;

typedef struct pleat_frames {
  float* data;         /* NULL: this output is not wanted */
  size_t frame_stride; /* floats between frame starts; 0 = vertex_count * 3 */
} pleat_frames;

/* Unit guess of the validation report. */
#define PLEAT_UNITS_METRES 0
#define PLEAT_UNITS_LOOK_LIKE_CENTIMETRES 1
#define PLEAT_UNITS_LOOK_LIKE_MILLIMETRES 2

typedef struct pleat_garment_load_options {
  uint32_t struct_size;
  uint32_t reserved;
  /* Vertices closer than this (after unit_scale) are welded into one, so that
     UV seams do not split the graph. 0: 1e-6 of the bounding-box diagonal.
     Negative: do not weld. */
  double weld_tolerance;
  /* Multiplies every coordinate on load, e.g. 0.01 for a file in centimetres.
     0: 1 (the file is in metres). */
  double unit_scale;
} pleat_garment_load_options;

/* What loading found. Counts refer to the mesh as loaded (after welding). */
typedef struct pleat_mesh_report {
  uint32_t struct_size;
  uint32_t input_vertex_count;        /* vertices in the source, before welding */
  uint32_t vertex_count;              /* graph vertices after welding */
  uint32_t triangle_count;            /* usable triangles kept */
  uint32_t welded_vertex_count;       /* duplicates merged into another vertex */
  uint32_t component_count;           /* connected components of the edge graph */
  uint32_t boundary_loop_count;       /* closed loops of boundary edges */
  uint32_t non_manifold_edge_count;   /* edges shared by three or more triangles */
  uint32_t degenerate_triangle_count; /* zero-area or repeated-index, dropped */
  uint32_t isolated_vertex_count;     /* vertices used by no triangle */
  uint32_t units;                     /* PLEAT_UNITS_* guess from the size */
  uint32_t reserved;
  float bbox_min[3];
  float bbox_max[3];
  double total_area; /* m^2 */
} pleat_mesh_report;

/* Band solver selection (pleat_prepare_options.solver). */
#define PLEAT_SOLVER_AUTO 0    /* dense below 3000 vertices, slicing above */
#define PLEAT_SOLVER_DENSE 1   /* LAPACK dsyevr on the dense Laplacian */
#define PLEAT_SOLVER_SLICING 2 /* shift-invert Lanczos slices, CHOLMOD LDL^T */
#define PLEAT_SOLVER_HYBRID 3  /* window eigenpairs + Chebyshev-filtered subspace */

/* Band projection form (pleat_prepare_options.projection). */
#define PLEAT_PROJECTION_RANDOM_WALK 0 /* D^-1/2 U U^T D^1/2: translation-invariant */
#define PLEAT_PROJECTION_SYMMETRIC 1   /* U U^T exactly as in the paper */

typedef struct pleat_prepare_options {
  uint32_t struct_size;
  uint32_t solver;     /* PLEAT_SOLVER_*; 0 = auto */
  uint32_t projection; /* PLEAT_PROJECTION_*; 0 = random walk */
  uint32_t reserved;
  double low_fraction;    /* low/mid cut at ceil(N * f); 0 = 1/30 */
  double mid_fraction;    /* mid/high cut at ceil(N * f); 0 = 1/5 */
  double geodesic_radius; /* metres; rest-pose neighbourhood radius; 0 = 0.10 */
} pleat_prepare_options;

typedef struct pleat_band_info {
  uint32_t struct_size;
  uint32_t vertex_count;
  uint32_t low_count;           /* eigenvectors in the low band (after gap move) */
  uint32_t mid_count;           /* eigenvectors in low + mid (after gap move) */
  uint32_t low_count_requested; /* ceil(N * low_fraction) */
  uint32_t mid_count_requested; /* ceil(N * mid_fraction) */
  uint32_t solver;              /* PLEAT_SOLVER_* actually used */
  uint32_t projection;          /* PLEAT_PROJECTION_* */
  double low_gap;               /* lambda[low_count] - lambda[low_count - 1] */
  double mid_gap;               /* lambda[mid_count] - lambda[mid_count - 1] */
  double geodesic_radius;       /* metres */
  uint64_t geodesic_pair_count; /* vertex pairs within the radius */
} pleat_band_info;

/* Metric selection (pleat_metrics_options.flags); 0 = all that apply. */
#define PLEAT_METRIC_VERTEX 0x1u          /* E_verts */
#define PLEAT_METRIC_NORMALS 0x2u         /* E_vnorm, E_fnorm */
#define PLEAT_METRIC_EDGES 0x4u           /* E_edge */
#define PLEAT_METRIC_CURVATURE 0x8u       /* E_curv */
#define PLEAT_METRIC_BANDS 0x10u          /* per-band E_verts (needs prepare) */
#define PLEAT_METRIC_SELF_COLLISION 0x20u /* self-collision rate of predicted */

typedef struct pleat_metrics_options {
  uint32_t struct_size;
  uint32_t flags;             /* PLEAT_METRIC_*; 0 = everything that applies */
  double collision_prefilter; /* metres; pair pre-filter radius; 0 = 0.015 */
} pleat_metrics_options;

/* Means over all frames (and vertices, faces or edges). Metrics not computed
   are 0 and their bit is clear in `computed`. */
typedef struct pleat_metrics {
  uint32_t struct_size;
  uint32_t computed; /* PLEAT_METRIC_* bits actually computed */
  uint64_t frame_count;
  double e_verts_cm;     /* mean vertex distance */
  double e_vnorm_deg;    /* mean angle between vertex normals */
  double e_fnorm_deg;    /* mean angle between face normals */
  double e_edge_percent; /* mean relative edge-length error */
  double e_curv;         /* mean |K_pred - K_truth|, K in 1/m^2 */
  double e_low_cm;       /* per-band mean vertex distance */
  double e_mid_cm;
  double e_high_cm;
  double self_collision_percent; /* faces crossed by a non-adjacent edge */
} pleat_metrics;

/* Point-cache formats for pleat_cache_write / pleat_cache_read. */
#define PLEAT_CACHE_AUTO 0 /* from the extension: .pc2, .mdd, .gltf/.glb, .usda, else OBJ sequence */
#define PLEAT_CACHE_PC2 1
#define PLEAT_CACHE_MDD 2
#define PLEAT_CACHE_OBJ_SEQUENCE 3 /* path holds a run of '#' for the frame number */
#define PLEAT_CACHE_GLTF 4         /* morph-target animation; .glb binary, else JSON */
#define PLEAT_CACHE_USDA 5         /* USD ASCII, time-sampled points; written, not read */

typedef struct pleat_cache_info {
  uint32_t struct_size;
  uint32_t format; /* PLEAT_CACHE_* */
  uint64_t frame_count;
  uint64_t vertex_count;
  double frame_rate; /* frames per second */
  double start_time; /* seconds */
} pleat_cache_info;

/* Body sources (pleat_body_load_options.kind). */
#define PLEAT_BODY_AUTO 0        /* a folder: MakeHuman assets; .npz: SMPL layout; else a rigged mesh */
#define PLEAT_BODY_MAKEHUMAN 1   /* the open body model from MakeHuman's CC0 assets folder */
#define PLEAT_BODY_SMPL_NPZ 2    /* an SMPL-layout .npz (bring your own licensed file) */
#define PLEAT_BODY_RIGGED_MESH 3 /* any skinned character: FBX (through assimp), glTF */

/* MakeHuman rigs (pleat_body_load_options.rig). */
#define PLEAT_RIG_CMU_MB 0            /* 31 joints named like the CMU BVH clips */
#define PLEAT_RIG_MAKEHUMAN_DEFAULT 1 /* MakeHuman's default 163-bone skeleton */

typedef struct pleat_body_load_options {
  uint32_t struct_size;
  uint32_t kind; /* PLEAT_BODY_*; 0 = from the path */
  uint32_t rig;  /* PLEAT_RIG_*, MakeHuman only; 0 = cmu_mb */
  uint32_t reserved;
} pleat_body_load_options;

typedef struct pleat_body_info {
  uint32_t struct_size;
  uint32_t vertex_count;
  uint32_t triangle_count;
  uint32_t joint_count;
  uint32_t shape_count;    /* entries of the shape vector (0: fixed shape) */
  uint32_t max_influences; /* most joints weighting one vertex */
} pleat_body_info;

/* A body from caller arrays (pleat_body_create). Joints are given parents
   first with their rest positions (global, metres); the rest pose has no
   joint rotation. Each vertex lists `influences` (joint, weight) pairs; zero
   weights are ignored and each vertex's weights must sum to 1. */
typedef struct pleat_body_desc {
  uint32_t struct_size;
  uint32_t joint_count;
  const char* const* joint_names; /* joint_count names, unique */
  const int32_t* parents;         /* joint_count; -1 for the first (root) only */
  const float* joint_positions;   /* joint_count xyz */
  size_t vertex_count;
  const float* positions; /* vertex_count xyz */
  size_t triangle_count;
  const uint32_t* triangles; /* triangle_count index triples */
  uint32_t influences;       /* (joint, weight) pairs per vertex */
  uint32_t reserved;
  const uint32_t* weight_joints; /* vertex_count * influences */
  const float* weights;          /* vertex_count * influences */
} pleat_body_desc;

typedef struct pleat_motion_load_options {
  uint32_t struct_size;
  uint32_t clip;     /* animation index in an FBX/glTF file; 0 = the first */
  double unit_scale; /* metres per file unit; 0 = guess (BVH: from the skeleton height) */
} pleat_motion_load_options;

typedef struct pleat_motion_info {
  uint32_t struct_size;
  uint32_t joint_count;
  uint64_t frame_count;
  double frame_rate; /* frames per second */
  double unit_scale; /* metres per file unit that was applied */
} pleat_motion_info;

/* Graph-attention variants (paper Table I); pleat_model_info.variant and
   pleat_model_init_options.variant. */
#define PLEAT_VARIANT_FLEXIGAT 1 /* learned self/neighbour mix P, Q per head */
#define PLEAT_VARIANT_GAT 2      /* plain GAT (P = Q = 1 frozen) */
#define PLEAT_VARIANT_LGAT 3     /* GAT with LipschitzNorm of the attention logits */

typedef struct pleat_model_info {
  uint32_t struct_size;
  uint32_t format_version; /* of the file it was loaded from (or would be saved as) */
  uint32_t joint_count;    /* skeleton the model was trained on */
  uint32_t shape_count;    /* entries of the shape vector it reads */
  uint32_t window_frames;  /* motion window m + 1 */
  uint32_t variant;        /* PLEAT_VARIANT_* of its graph layers */
  uint32_t default_top_k;  /* joints per vertex in skinning unless overridden */
  uint32_t code_width;     /* width of the fused code F */
  double frame_rate;       /* poses must come at this rate */
  uint64_t parameter_count;
  double offset_filter_length; /* metres: h of the offset filter (docs/runtime.md); 0 = none */
  /* The skinning prior's reach (docs/models.md): body weights averaged within
     this radius, metres (0 = the nearest body vertex's), and the floor f of
     its log(w + f). */
  double skinning_prior_radius;
  double skinning_prior_floor;
} pleat_model_info;

/* The paper's initialisation for a skeleton (pleat_model_initialize). */
typedef struct pleat_model_init_options {
  uint32_t struct_size;
  uint32_t variant;       /* PLEAT_VARIANT_*; 0 = FlexiGAT */
  uint32_t window_frames; /* 0 = 8 */
  uint32_t reserved;
  uint64_t seed;     /* 0 = 1 */
  double frame_rate; /* 0 = 30 */
} pleat_model_init_options;

typedef struct pleat_instance_options {
  uint32_t struct_size;
  uint32_t threads;   /* worker threads this instance owns; 0 = 1 (the calling thread only) */
  uint32_t top_k;     /* joints per vertex in skinning; 0 = the model's default; >= joint_count = exact */
  uint32_t max_batch; /* frames evaluated together (memory grows with it); 0 = 8 */
} pleat_instance_options;

typedef struct pleat_instance_info {
  uint32_t struct_size;
  uint32_t vertex_count; /* garment vertices per output frame */
  uint32_t joint_count;  /* joints per pose (the body's) */
  uint32_t top_k;
  uint32_t window_frames;
  uint32_t max_batch;
  double frame_rate;
} pleat_instance_info;

/* Poses in the bound body's joint order: frame_count * joint_count unit
   quaternions (x, y, z, w) relative to each joint's rest orientation, and
   frame_count root positions (xyz, metres). Frames before the evaluated
   range are the history the model looks at (motion window, velocities);
   before frame 0 the sequence holds still at frame 0. */
typedef struct pleat_poses {
  uint32_t struct_size;
  uint32_t joint_count;
  size_t frame_count;
  const float* rotations;
  const float* root_positions;
  double frame_rate; /* must equal the model's (resample with pleat_motion_resample) */
} pleat_poses;

/* How far evaluation goes (pleat_evaluate_options.stage). */
#define PLEAT_STAGE_FULL 0         /* everything the model has: the default */
#define PLEAT_STAGE_SKINNING 1     /* learned skinning weights + LBS of the rest garment */
#define PLEAT_STAGE_BLEND_SHAPES 2 /* + pose-dependent blend shapes */
#define PLEAT_STAGE_REFINEMENT 3   /* + the refinement network (= full) */

typedef struct pleat_evaluate_options {
  uint32_t struct_size;
  uint32_t stage; /* PLEAT_STAGE_*; 0 = full */
  /* Full stage: the refinement network runs on frames t with t % k == 0 only;
     the k - 1 frames after each hold its offsets (in the character's heading
     frame) over their own skinned positions. 0 or 1 = every frame. A level of
     detail: the refinement is most of a frame's cost (docs/runtime.md). A
     frame's result still depends only on the poses and k. */
  uint32_t refinement_interval;
  /* Full stage: how much of each frequency band (low, mid, high) of the
     refinement's offsets to remove, 0 (keep: the default) to 1 (drop); a
     spectral level of detail, e.g. {0, 0, 1} removes the finest wrinkles of
     a garment seen from afar. Needs a prepared garment
     (PLEAT_ERROR_NOT_PREPARED otherwise) when any entry is above 0. */
  float band_attenuation[3];
  /* Any stage: > 0 runs the body-collision post-pass, which moves garment
     vertices that end inside the body, or closer to it than this many
     metres, out along the body's normal (e.g. 0.002); 0 = off. Vertices
     further than 10 cm from the body are never moved (docs/runtime.md). */
  float body_collision_distance;
} pleat_evaluate_options;

/* Where evaluation writes; any output whose data is NULL is not computed.
   Positions and normals: vertex_count xyz per frame (stride 0 =
   vertex_count * 3). Skinning weights: vertex_count * joint_count per frame
   in the model's joint order (pleat_model_joint_name), zero outside each
   vertex's top k (stride 0 = vertex_count * joint_count). Bands: the
   positions split into low + mid + high (needs a prepared garment). */
typedef struct pleat_evaluate_outputs {
  uint32_t struct_size;
  uint32_t reserved;
  pleat_frames positions;
  pleat_frames normals;
  pleat_frames skinning_weights;
  pleat_frames low;
  pleat_frames mid;
  pleat_frames high;
} pleat_evaluate_outputs;

/* ---- Library ------------------------------------------------------------- */

/* PLEAT_VERSION_NUMBER of the loaded library. Thread-safe. */
PLEAT_EXPORT uint32_t pleat_version(void);

/* Message of the last failed call on the calling thread ("" if none). Valid
   until the next pleat call on this thread. Thread-safe (thread-local). */
PLEAT_EXPORT const char* pleat_last_error(void);

/* Constant name of a status code, e.g. "PLEAT_ERROR_IO". Thread-safe. */
PLEAT_EXPORT const char* pleat_status_name(pleat_status status);

/* ---- Garments ------------------------------------------------------------ */

/* Loads a garment from an OBJ, FBX (through assimp) or glTF file, or a
   prepared-garment file written by pleat_garment_save (recognised by its
   FlatBuffers identifier; options are then ignored). Welds coincident
   vertices, builds the edge graph, rest normals and vertex areas, and fills
   the validation report. Fails with PLEAT_ERROR_INVALID_MESH only where the
   mesh cannot be used (no triangles, non-finite coordinates).
   Thread-safe (no shared state). */
PLEAT_EXPORT pleat_status pleat_garment_load(const char* path, const pleat_garment_load_options* options,
                                             pleat_garment** out_garment);

/* Same from caller arrays: vertex_count xyz floats, triangle_count index
   triples. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_garment_create(const float* positions, size_t vertex_count,
                                               const uint32_t* triangles, size_t triangle_count,
                                               const pleat_garment_load_options* options,
                                               pleat_garment** out_garment);

/* NULL is accepted. Not thread-safe with other calls on the same garment. */
PLEAT_EXPORT void pleat_garment_destroy(pleat_garment* garment);

/* Copies the validation report. Thread-safe on a shared garment. */
PLEAT_EXPORT pleat_status pleat_garment_get_report(const pleat_garment* garment,
                                                   pleat_mesh_report* out_report);

/* Copies the welded rest positions (vertex_count * 3 floats) and triangles
   (triangle_count * 3 indices); either output may be NULL. Capacities are in
   elements (floats, indices). Thread-safe on a shared garment. */
PLEAT_EXPORT pleat_status pleat_garment_get_mesh(const pleat_garment* garment, float* positions,
                                                 size_t positions_capacity, uint32_t* triangles,
                                                 size_t triangles_capacity);

/* Computes the spectral bands and the rest-pose geodesic neighbourhoods.
   Call once, before sharing the garment between threads; afterwards the
   garment is immutable. Not thread-safe with other calls on this garment. */
PLEAT_EXPORT pleat_status pleat_garment_prepare(pleat_garment* garment, const pleat_prepare_options* options);

/* Band settings of a prepared garment. PLEAT_ERROR_NOT_PREPARED otherwise.
   Thread-safe on a shared garment. */
PLEAT_EXPORT pleat_status pleat_garment_get_band_info(const pleat_garment* garment,
                                                      pleat_band_info* out_info);

/* Writes the prepared garment (mesh, report, bands, neighbourhoods) to a
   FlatBuffers file, atomically (temporary file, then rename).
   Thread-safe on a shared garment. */
PLEAT_EXPORT pleat_status pleat_garment_save(const pleat_garment* garment, const char* path);

/* Splits frame_count frames of positions into low, mid and high bands, with
   low + mid + high = input. Any output whose data is NULL is skipped.
   Allocates a scratch buffer per call (batch frames to amortise it).
   Thread-safe on a shared garment. */
PLEAT_EXPORT pleat_status pleat_garment_split_bands(const pleat_garment* garment,
                                                    pleat_const_frames positions, size_t frame_count,
                                                    pleat_frames low, pleat_frames mid, pleat_frames high);

/* ---- Metrics ------------------------------------------------------------- */

/* Compares predicted with ground-truth frames of the garment's vertices
   (paper section IV). Band errors need a prepared garment and are skipped
   (bit clear) otherwise unless explicitly requested, which then fails with
   PLEAT_ERROR_NOT_PREPARED. Thread-safe on a shared garment. */
PLEAT_EXPORT pleat_status pleat_metrics_compute(const pleat_garment* garment, pleat_const_frames predicted,
                                                pleat_const_frames truth, size_t frame_count,
                                                const pleat_metrics_options* options,
                                                pleat_metrics* out_metrics);

/* ---- Point caches -------------------------------------------------------- */

/* Reads the header of a PC2, MDD or glTF file, or counts an OBJ sequence.
   format: PLEAT_CACHE_*. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_cache_get_info(const char* path, uint32_t format, pleat_cache_info* out_info);

/* Reads every frame into out (frame_count * vertex_count * 3 floats at the
   given stride; capacity in floats). Thread-safe. */
PLEAT_EXPORT pleat_status pleat_cache_read(const char* path, uint32_t format, pleat_frames out,
                                           size_t capacity);

/* Writes frames atomically. OBJ sequences, glTF and USD take the faces from
   `garment` (required for those formats, ignored otherwise). Thread-safe. */
PLEAT_EXPORT pleat_status pleat_cache_write(const char* path, uint32_t format, const pleat_garment* garment,
                                            pleat_const_frames positions, size_t frame_count,
                                            size_t vertex_count, double frame_rate);

/* ---- Bodies -------------------------------------------------------------- */

/* Loads a body: the MakeHuman open model from its assets folder (shape =
   macro sliders, default 0.5), an SMPL-layout .npz (shape = betas, default 0)
   or a skinned FBX/glTF character (fixed shape). Thread-safe. */
PLEAT_EXPORT pleat_status pleat_body_load(const char* path, const pleat_body_load_options* options,
                                          pleat_body** out_body);

/* A fixed-shape body from caller arrays (see pleat_body_desc). Thread-safe. */
PLEAT_EXPORT pleat_status pleat_body_create(const pleat_body_desc* desc, pleat_body** out_body);

/* NULL is accepted. Not thread-safe with other calls on the same body. */
PLEAT_EXPORT void pleat_body_destroy(pleat_body* body);

/* Counts. Thread-safe on a shared body. */
PLEAT_EXPORT pleat_status pleat_body_get_info(const pleat_body* body, pleat_body_info* out_info);

/* Name of joint `index` or shape entry `index`; NULL when out of range. The
   string lives as long as the body. Thread-safe on a shared body. */
PLEAT_EXPORT const char* pleat_body_joint_name(const pleat_body* body, uint32_t index);
PLEAT_EXPORT const char* pleat_body_shape_name(const pleat_body* body, uint32_t index);

/* Current shape vector (shape_count doubles). Thread-safe on a shared body. */
PLEAT_EXPORT pleat_status pleat_body_get_shape(const pleat_body* body, double* values, size_t capacity);

/* Reshapes the body (mesh, joints) from shape_count values. Not thread-safe
   with other calls on this body. */
PLEAT_EXPORT pleat_status pleat_body_set_shape(pleat_body* body, const double* values, size_t count);

/* Rest mesh (vertex_count xyz), triangles (triangle_count triples) and rest
   joint positions (joint_count xyz, global); any output may be NULL.
   Capacities in elements. Thread-safe on a shared body. */
PLEAT_EXPORT pleat_status pleat_body_get_rest(const pleat_body* body, float* positions,
                                              size_t positions_capacity, uint32_t* triangles,
                                              size_t triangles_capacity, float* joints,
                                              size_t joints_capacity);

/* Skinned body vertices for frames [first_frame, first_frame + frame_count)
   of a motion on this body's skeleton (load it, then pleat_motion_retarget).
   Thread-safe on a shared body and motion. */
PLEAT_EXPORT pleat_status pleat_body_pose_motion(const pleat_body* body, const pleat_motion* motion,
                                                 size_t first_frame, size_t frame_count, pleat_frames out);

/* Skinned body vertices for poses given as arrays: frame_count * joint_count
   unit quaternions (x, y, z, w), each relative to the joint's rest
   orientation, and frame_count root positions (xyz, metres). Thread-safe on
   a shared body. */
PLEAT_EXPORT pleat_status pleat_body_pose(const pleat_body* body, const float* rotations,
                                          const float* root_positions, size_t frame_count, pleat_frames out);

/* ---- Motions ------------------------------------------------------------- */

/* Loads a motion: BVH, or an animation clip of an FBX/glTF file. Units are
   converted to metres, Z-up BVH files to Y up. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_motion_load(const char* path, const pleat_motion_load_options* options,
                                            pleat_motion** out_motion);

/* NULL is accepted. */
PLEAT_EXPORT void pleat_motion_destroy(pleat_motion* motion);

/* Thread-safe on a shared motion. */
PLEAT_EXPORT pleat_status pleat_motion_get_info(const pleat_motion* motion, pleat_motion_info* out_info);

/* Name of joint `index`; NULL when out of range. Thread-safe. */
PLEAT_EXPORT const char* pleat_motion_joint_name(const pleat_motion* motion, uint32_t index);

/* A new motion resampled to frame_rate (quaternion slerp). Thread-safe. */
PLEAT_EXPORT pleat_status pleat_motion_resample(const pleat_motion* motion, double frame_rate,
                                                pleat_motion** out_motion);

/* A new motion on the body's skeleton: joints paired by equal names, plus
   those a joint-map file pairs (one "source[|alternative...] target" per
   line; pleat ships maps for the CMU families, Mixamo and the Unreal
   mannequin onto the cmu_mb names in data/retarget/). Rest poses are
   aligned, so a T-posed clip drives an A-posed body; the root path is scaled
   by the ratio of leg lengths. joint_map_path may be NULL. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_motion_retarget(const pleat_motion* motion, const pleat_body* body,
                                                const char* joint_map_path, pleat_motion** out_motion);

/* Joint rotations relative to the rest pose as unit quaternions (x, y, z, w)
   for frame_count * joint_count joints, and root positions (frame_count xyz)
   of frames [first_frame, first_frame + frame_count). Either output may be
   NULL; capacities in floats. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_motion_get_frames(const pleat_motion* motion, size_t first_frame,
                                                  size_t frame_count, float* rotations,
                                                  size_t rotations_capacity, float* root_positions,
                                                  size_t root_capacity);

/* ---- Models -------------------------------------------------------------- */

/* Loads a model file (.pleat, FlatBuffers): runs the FlatBuffers verifier and
   checks every tensor's shape against the architecture. A file from a newer
   format gives PLEAT_ERROR_UNSUPPORTED_VERSION, a damaged one
   PLEAT_ERROR_FORMAT. A model is immutable and shareable by threads.
   Thread-safe. */
PLEAT_EXPORT pleat_status pleat_model_load(const char* path, pleat_model** out_model);

/* A model with the paper's initialisation (geometric for linear layers,
   Kaiming for graph layers) for the skeleton and shape vector of `body`:
   valid and loadable before any training exists. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_model_initialize(const pleat_body* body,
                                                 const pleat_model_init_options* options,
                                                 pleat_model** out_model);

/* Writes the model atomically (temporary file, then rename). Thread-safe. */
PLEAT_EXPORT pleat_status pleat_model_save(const pleat_model* model, const char* path);

/* NULL is accepted. Instances keep the model alive: it may be destroyed
   while instances bound to it are in use. */
PLEAT_EXPORT void pleat_model_destroy(pleat_model* model);

/* Thread-safe on a shared model. */
PLEAT_EXPORT pleat_status pleat_model_get_info(const pleat_model* model, pleat_model_info* out_info);

/* Name of the model's joint `index`; NULL when out of range. The string lives
   as long as the model. Thread-safe. */
PLEAT_EXPORT const char* pleat_model_joint_name(const pleat_model* model, uint32_t index);

/* ---- Instances ----------------------------------------------------------- */

/* Binds a model to a garment and a body: checks that the body's skeleton can
   drive the model (same joint names, same parents; message names the joint),
   and computes every pose-independent result (body code, garment encoder).
   The instance keeps its own references: model, garment and body may be
   destroyed afterwards. Thread-safe on shared model, garment and body. */
PLEAT_EXPORT pleat_status pleat_instance_create(const pleat_model* model, const pleat_garment* garment,
                                                const pleat_body* body, const pleat_instance_options* options,
                                                pleat_instance** out_instance);

/* NULL is accepted. */
PLEAT_EXPORT void pleat_instance_destroy(pleat_instance* instance);

/* Counts and settings. Thread-safe (they never change after binding). */
PLEAT_EXPORT pleat_status pleat_instance_get_info(const pleat_instance* instance,
                                                  pleat_instance_info* out_info);

/* Evaluates frames [first_frame, first_frame + frame_count) of `poses` into
   the outputs. Results depend only on the poses (not on batching, earlier
   calls or the thread count). Allocates nothing. Every input is checked
   before anything is written; a non-finite result (PLEAT_ERROR_NUMERICAL)
   stops at the batch of max_batch frames where it arose, leaving that batch
   unwritten. One thread at a time per instance; different instances may run
   on different threads at once. */
PLEAT_EXPORT pleat_status pleat_instance_evaluate(pleat_instance* instance, const pleat_poses* poses,
                                                  size_t first_frame, size_t frame_count,
                                                  const pleat_evaluate_options* options,
                                                  const pleat_evaluate_outputs* outputs);

/* pleat_instance_evaluate with a motion's frames as the poses, without
   copying them: the motion must be on the bound body's skeleton (same joints
   in the same order: pleat_motion_retarget onto the body) at the model's
   frame rate (pleat_motion_resample). Frames before first_frame are the
   history. Allocates nothing; same threading rules as
   pleat_instance_evaluate (the motion may be shared by threads). */
PLEAT_EXPORT pleat_status pleat_instance_evaluate_motion(pleat_instance* instance, const pleat_motion* motion,
                                                         size_t first_frame, size_t frame_count,
                                                         const pleat_evaluate_options* options,
                                                         const pleat_evaluate_outputs* outputs);

/* Restricts the blend shapes and the refinement to the vertices whose byte
   in `mask` (vertex_count entries, the instance's) is nonzero: the others
   keep their skinned positions (what PLEAT_STAGE_SKINNING gives them), and
   the networks run only on the part of the garment the active vertices
   depend on (their neighbourhood to the depth of the network's graph
   layers), so a frozen or hidden region costs little. Active vertices get
   what they would get without a mask (up to float rounding) unless the
   model has an offset filter or bands are attenuated: those act on the
   whole garment, and near the mask's edge the active vertices then differ
   slightly (docs/runtime.md). Applies to every later evaluate call; NULL, or
   a mask with every vertex active, clears it. Allocates (call it when the
   view changes, not per frame). Not thread-safe with other calls on this
   instance. */
PLEAT_EXPORT pleat_status pleat_instance_set_vertex_mask(pleat_instance* instance, const uint8_t* mask,
                                                         size_t vertex_count);

/* ---- Meshes -------------------------------------------------------------- */

/* Writes a triangle mesh as OBJ, atomically. Thread-safe. */
PLEAT_EXPORT pleat_status pleat_mesh_write_obj(const char* path, const float* positions, size_t vertex_count,
                                               const uint32_t* triangles, size_t triangle_count);

/* ---- Function table for dlopen users ------------------------------------- */

typedef struct pleat_api {
  uint32_t struct_size; /* sizeof(pleat_api) of the library */
  uint32_t version;     /* PLEAT_API_VERSION it serves */
  /* Each entry is the exported pleat_<entry> function (version_number is
     pleat_version); its declaration above is the full contract. */
  /* (major << 16) | (minor << 8) | patch of the library */
  uint32_t (*version_number)(void);
  /* message of this thread's last failed call ("" if none) */
  const char* (*last_error)(void);
  /* the constant's name of a status code, e.g. "PLEAT_ERROR_IO" */
  const char* (*status_name)(pleat_status status);
  /* reads a mesh file (OBJ, glTF, FBX, ...) or a prepared .pleatg */
  pleat_status (*garment_load)(const char* path, const pleat_garment_load_options* options,
                               pleat_garment** out_garment);
  /* a garment from caller arrays (copied) */
  pleat_status (*garment_create)(const float* positions, size_t vertex_count, const uint32_t* triangles,
                                 size_t triangle_count, const pleat_garment_load_options* options,
                                 pleat_garment** out_garment);
  /* frees a garment; NULL is a no-op */
  void (*garment_destroy)(pleat_garment* garment);
  /* copies the validation report of the load */
  pleat_status (*garment_get_report)(const pleat_garment* garment, pleat_mesh_report* out_report);
  /* copies the welded rest positions and triangles (either may be NULL) */
  pleat_status (*garment_get_mesh)(const pleat_garment* garment, float* positions, size_t positions_capacity,
                                   uint32_t* triangles, size_t triangles_capacity);
  /* computes the spectral bands and geodesic neighbourhoods; once, before sharing */
  pleat_status (*garment_prepare)(pleat_garment* garment, const pleat_prepare_options* options);
  /* the band split of a prepared garment */
  pleat_status (*garment_get_band_info)(const pleat_garment* garment, pleat_band_info* out_info);
  /* writes the prepared garment (.pleatg), atomically */
  pleat_status (*garment_save)(const pleat_garment* garment, const char* path);
  /* splits frames into low, mid and high bands (any may be NULL) */
  pleat_status (*garment_split_bands)(const pleat_garment* garment, pleat_const_frames positions,
                                      size_t frame_count, pleat_frames low, pleat_frames mid,
                                      pleat_frames high);
  /* the paper's Table I metrics of predicted against true frames */
  pleat_status (*metrics_compute)(const pleat_garment* garment, pleat_const_frames predicted,
                                  pleat_const_frames truth, size_t frame_count,
                                  const pleat_metrics_options* options, pleat_metrics* out_metrics);
  /* reads the header of a PC2 or MDD file, or counts an OBJ sequence */
  pleat_status (*cache_get_info)(const char* path, uint32_t format, pleat_cache_info* out_info);
  /* reads every frame of a cache into the caller buffer */
  pleat_status (*cache_read)(const char* path, uint32_t format, pleat_frames out, size_t capacity);
  /* writes frames as a cache, atomically */
  pleat_status (*cache_write)(const char* path, uint32_t format, const pleat_garment* garment,
                              pleat_const_frames positions, size_t frame_count, size_t vertex_count,
                              double frame_rate);
  /* reads a body: MakeHuman assets folder, SMPL-layout .npz or skinned FBX/glTF */
  pleat_status (*body_load)(const char* path, const pleat_body_load_options* options, pleat_body** out_body);
  /* frees a body; NULL is a no-op */
  void (*body_destroy)(pleat_body* body);
  /* counts of a body */
  pleat_status (*body_get_info)(const pleat_body* body, pleat_body_info* out_info);
  /* the joint's name, NULL past the end; valid while the body lives */
  const char* (*body_joint_name)(const pleat_body* body, uint32_t index);
  /* the shape parameter's name, NULL past the end */
  const char* (*body_shape_name)(const pleat_body* body, uint32_t index);
  /* copies the current shape parameters */
  pleat_status (*body_get_shape)(const pleat_body* body, double* values, size_t capacity);
  /* reshapes the body (mesh, joints) from shape values */
  pleat_status (*body_set_shape)(pleat_body* body, const double* values, size_t count);
  /* copies the rest mesh and joint positions (any buffer may be NULL) */
  pleat_status (*body_get_rest)(const pleat_body* body, float* positions, size_t positions_capacity,
                                uint32_t* triangles, size_t triangles_capacity, float* joints,
                                size_t joints_capacity);
  /* poses the body's vertices along frames of a motion */
  pleat_status (*body_pose_motion)(const pleat_body* body, const pleat_motion* motion, size_t first_frame,
                                   size_t frame_count, pleat_frames out);
  /* reads a motion: BVH, or an animation clip of an FBX/glTF file */
  pleat_status (*motion_load)(const char* path, const pleat_motion_load_options* options,
                              pleat_motion** out_motion);
  /* frees a motion; NULL is a no-op */
  void (*motion_destroy)(pleat_motion* motion);
  /* frame count, rate and joint count of a motion */
  pleat_status (*motion_get_info)(const pleat_motion* motion, pleat_motion_info* out_info);
  /* the joint's name, NULL past the end */
  const char* (*motion_joint_name)(const pleat_motion* motion, uint32_t index);
  /* a new motion resampled to frame_rate (quaternion slerp) */
  pleat_status (*motion_resample)(const pleat_motion* motion, double frame_rate, pleat_motion** out_motion);
  /* a new motion on the body's skeleton: joints by name, plus an optional map file */
  pleat_status (*motion_retarget)(const pleat_motion* motion, const pleat_body* body,
                                  const char* joint_map_path, pleat_motion** out_motion);
  /* copies joint rotations and root positions of frames */
  pleat_status (*motion_get_frames)(const pleat_motion* motion, size_t first_frame, size_t frame_count,
                                    float* rotations, size_t rotations_capacity, float* root_positions,
                                    size_t root_capacity);
  /* writes a triangle mesh as OBJ, atomically */
  pleat_status (*mesh_write_obj)(const char* path, const float* positions, size_t vertex_count,
                                 const uint32_t* triangles, size_t triangle_count);
  /* a body from caller arrays (copied) */
  pleat_status (*body_create)(const pleat_body_desc* desc, pleat_body** out_body);
  /* poses the body from caller rotations and root positions */
  pleat_status (*body_pose)(const pleat_body* body, const float* rotations, const float* root_positions,
                            size_t frame_count, pleat_frames out);
  /* reads a model file (.pleat, FlatBuffers; verified) */
  pleat_status (*model_load)(const char* path, pleat_model** out_model);
  /* the paper's untrained initialisation for the body's skeleton */
  pleat_status (*model_initialize)(const pleat_body* body, const pleat_model_init_options* options,
                                   pleat_model** out_model);
  /* writes a model file, atomically */
  pleat_status (*model_save)(const pleat_model* model, const char* path);
  /* frees a model; NULL is a no-op */
  void (*model_destroy)(pleat_model* model);
  /* architecture summary of a model */
  pleat_status (*model_get_info)(const pleat_model* model, pleat_model_info* out_info);
  /* the joint's name in the model's skeleton, NULL past the end */
  const char* (*model_joint_name)(const pleat_model* model, uint32_t index);
  /* binds a model to a prepared garment and a body */
  pleat_status (*instance_create)(const pleat_model* model, const pleat_garment* garment,
                                  const pleat_body* body, const pleat_instance_options* options,
                                  pleat_instance** out_instance);
  /* frees an instance; NULL is a no-op */
  void (*instance_destroy)(pleat_instance* instance);
  /* counts and settings, fixed at binding */
  pleat_status (*instance_get_info)(const pleat_instance* instance, pleat_instance_info* out_info);
  /* frames of poses into the requested outputs; allocates nothing */
  pleat_status (*instance_evaluate)(pleat_instance* instance, const pleat_poses* poses, size_t first_frame,
                                    size_t frame_count, const pleat_evaluate_options* options,
                                    const pleat_evaluate_outputs* outputs);
  /* frames of a motion on the bound body into the outputs; no copy, no allocation (API version 3) */
  pleat_status (*instance_evaluate_motion)(pleat_instance* instance, const pleat_motion* motion,
                                           size_t first_frame, size_t frame_count,
                                           const pleat_evaluate_options* options,
                                           const pleat_evaluate_outputs* outputs);
  /* restricts the networks to the vertices a mask leaves active (API version 4) */
  pleat_status (*instance_set_vertex_mask)(pleat_instance* instance, const uint8_t* mask,
                                           size_t vertex_count);
} pleat_api;

/* The table for `version`, or NULL if this library does not serve it (a newer
   version than it knows, or 0). The table is static: never freed.
   Thread-safe. */
PLEAT_EXPORT const pleat_api* pleat_get_api(uint32_t version);
typedef const pleat_api* (*pleat_get_api_fn)(uint32_t version);

#ifdef __cplusplus
}
#endif

#endif /* PLEAT_H */
