#include "garment/garment_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "capi/pleat.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "schema/garment_generated.h"

namespace pleat {
namespace fb = pleat::schema;

namespace {

template <typename T>
flatbuffers::Offset<flatbuffers::Vector<T>> vec(flatbuffers::FlatBufferBuilder& b, const T* data, size_t n) {
  return b.CreateVector(data, n);
}

[[noreturn]] void bad(const std::string& source, const std::string& what) {
  fail(PLEAT_ERROR_FORMAT, source + ": " + what);
}

template <typename T>
const flatbuffers::Vector<T>& required(const flatbuffers::Vector<T>* v, const std::string& source,
                                       const char* field) {
  if (!v) bad(source, std::string("field '") + field + "' is missing");
  return *v;
}

void expect_size(size_t actual, size_t expected, const std::string& source, const char* field) {
  if (actual != expected)
    bad(source, std::string("field '") + field + "' has " + std::to_string(actual) + " values, expected " +
                    std::to_string(expected));
}

}  // namespace

std::vector<uint8_t> serialize_garment(const Garment& g) {
  flatbuffers::FlatBufferBuilder b(1024 + static_cast<size_t>(g.rest.vertex_count()) * 64);
  const auto n = static_cast<size_t>(g.rest.vertex_count());
  auto vertices = vec(b, g.rest.vertices.data(), n * 3);
  auto triangles = vec(b, g.rest.triangles.data(), static_cast<size_t>(g.rest.triangles.size()));
  auto source_vertex = vec(b, g.source_vertex.data(), g.source_vertex.size());
  const MeshReport& r = g.report;
  auto report = fb::CreateMeshReport(b, r.input_vertex_count, r.welded_vertex_count, r.component_count,
                                     r.boundary_loop_count, r.non_manifold_edge_count,
                                     r.degenerate_triangle_count, r.isolated_vertex_count, r.units);
  flatbuffers::Offset<fb::Bands> bands;
  flatbuffers::Offset<fb::Neighbourhoods> geodesic;
  if (g.prepared) {
    const BandBasis<float>& bb = g.prepared->bands;
    auto eigenvalues = vec(b, bb.eigenvalues.data(), static_cast<size_t>(bb.eigenvalues.size()));
    auto vectors = vec(b, bb.vectors.data(), static_cast<size_t>(bb.vectors.size()));
    auto sqrt_degree = vec(b, bb.sqrt_degree.data(), static_cast<size_t>(bb.sqrt_degree.size()));
    bands = fb::CreateBands(b, bb.low_count, bb.mid_count, bb.low_requested, bb.mid_requested,
                            static_cast<uint32_t>(bb.solver), static_cast<uint32_t>(bb.projection),
                            bb.low_gap, bb.mid_gap, eigenvalues, vectors, sqrt_degree);
    const Csr& geo = g.prepared->geodesic;
    geodesic = fb::CreateNeighbourhoods(b, g.prepared->geodesic_radius,
                                        vec(b, geo.offsets.data(), geo.offsets.size()),
                                        vec(b, geo.indices.data(), geo.indices.size()));
  }
  auto root = fb::CreateGarment(b, kGarmentFormatVersion, b.CreateString("pleat " PLEAT_VERSION_STRING),
                                b.CreateString(g.source), vertices, triangles, source_vertex, report, bands,
                                geodesic);
  fb::FinishGarmentBuffer(b, root);
  return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

void save_garment(const Garment& garment, const std::string& path) {
  std::vector<uint8_t> bytes = serialize_garment(garment);
  AtomicFile file(path);
  file.write(bytes.data(), bytes.size());
  file.commit();
}

bool is_garment_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[8] = {};
  if (!in.read(header, sizeof header)) return false;
  return flatbuffers::BufferHasIdentifier(header, fb::GarmentIdentifier());
}

namespace {

// The rest mesh and the map back to the source file's vertices.
// The verifier checks a vector's 4-byte length prefix, not that 8-byte
// elements are 8-aligned, so a crafted file can misalign doubles: read them
// byte-wise (found by fuzz_garment_file under UBSan).
void copy_doubles(const flatbuffers::Vector<double>& from, double* to) {
  std::memcpy(to, from.Data(), from.size() * sizeof(double));
}

void read_mesh(const fb::Garment* root, const std::string& source, Garment* g) {
  g->source = root->source() ? root->source()->str() : source;
  const auto& vertices = required(root->vertices(), source, "vertices");
  const auto& triangles = required(root->triangles(), source, "triangles");
  if (vertices.size() == 0 || vertices.size() % 3 != 0)
    bad(source,
        "field 'vertices' has " + std::to_string(vertices.size()) + " values, not a positive multiple of 3");
  if (triangles.size() == 0 || triangles.size() % 3 != 0)
    bad(source, "field 'triangles' has " + std::to_string(triangles.size()) +
                    " values, not a positive multiple of 3");
  const auto n = static_cast<Eigen::Index>(vertices.size() / 3);
  g->rest.vertices.resize(n, 3);
  copy_doubles(vertices, g->rest.vertices.data());
  if (!g->rest.vertices.allFinite() || g->rest.vertices.cwiseAbs().maxCoeff() > kMaxCoordinate)
    bad(source, "field 'vertices' holds a non-finite or huge value");
  g->rest.triangles =
      Eigen::Map<const Triangles>(triangles.data(), static_cast<Eigen::Index>(triangles.size() / 3), 3);
  for (Eigen::Index i = 0; i < g->rest.triangles.size(); ++i)
    if (g->rest.triangles.data()[i] < 0 || g->rest.triangles.data()[i] >= n)
      bad(source, "field 'triangles' index " + std::to_string(i) + " is out of range");
  const auto& source_vertex = required(root->source_vertex(), source, "source_vertex");
  g->source_vertex.assign(source_vertex.begin(), source_vertex.end());
  for (size_t i = 0; i < g->source_vertex.size(); ++i)
    if (g->source_vertex[i] < 0 || g->source_vertex[i] >= n)
      bad(source, "field 'source_vertex' index " + std::to_string(i) + " is out of range");
}

// The import report: counts as stored, sizes and bounds recomputed from the
// mesh (after derive_rest_data, for the area).
void read_report(const fb::Garment* root, const std::string& source, Garment* g) {
  const fb::MeshReport* report = root->report();
  if (!report) bad(source, "field 'report' is missing");
  MeshReport& r = g->report;
  r.input_vertex_count = report->input_vertex_count();
  r.vertex_count = static_cast<uint32_t>(g->rest.vertex_count());
  r.triangle_count = static_cast<uint32_t>(g->rest.triangle_count());
  r.welded_vertex_count = report->welded_vertex_count();
  r.component_count = report->component_count();
  r.boundary_loop_count = report->boundary_loop_count();
  r.non_manifold_edge_count = report->non_manifold_edge_count();
  r.degenerate_triangle_count = report->degenerate_triangle_count();
  r.isolated_vertex_count = report->isolated_vertex_count();
  r.units = report->units();
  const Eigen::RowVector3d lo = g->rest.vertices.colwise().minCoeff(),
                           hi = g->rest.vertices.colwise().maxCoeff();
  for (int c = 0; c < 3; ++c) {
    r.bbox_min[c] = static_cast<float>(lo[c]);
    r.bbox_max[c] = static_cast<float>(hi[c]);
  }
  r.total_area = g->vertex_areas.sum();
}

// The spectral basis, with bounds the verifier cannot check.
BandBasis<float> read_bands(const fb::Bands* bands, Eigen::Index n, const std::string& source) {
  BandBasis<float> bb;
  bb.vertex_count = static_cast<int32_t>(n);
  bb.low_count = bands->low_count();
  bb.mid_count = bands->mid_count();
  bb.low_requested = bands->low_requested();
  bb.mid_requested = bands->mid_requested();
  if (bb.mid_count < 1 || bb.mid_count > n || bb.low_count < 1 || bb.low_count > bb.mid_count)
    bad(source, "fields 'bands.low_count' " + std::to_string(bb.low_count) + " / 'bands.mid_count' " +
                    std::to_string(bb.mid_count) + " are inconsistent with " + std::to_string(n) +
                    " vertices");
  if (bands->solver() < PLEAT_SOLVER_DENSE || bands->solver() > PLEAT_SOLVER_HYBRID)
    bad(source, "field 'bands.solver' has unknown value " + std::to_string(bands->solver()));
  if (bands->projection() > PLEAT_PROJECTION_SYMMETRIC)
    bad(source, "field 'bands.projection' has unknown value " + std::to_string(bands->projection()));
  bb.solver = static_cast<SolverKind>(bands->solver());
  bb.projection = static_cast<ProjectionForm>(bands->projection());
  bb.low_gap = bands->low_gap();
  bb.mid_gap = bands->mid_gap();
  const auto& eigenvalues = required(bands->eigenvalues(), source, "bands.eigenvalues");
  const auto& vectors = required(bands->vectors(), source, "bands.vectors");
  const auto& sqrt_degree = required(bands->sqrt_degree(), source, "bands.sqrt_degree");
  if (eigenvalues.size() < static_cast<uint32_t>(bb.mid_count))
    bad(source, "field 'bands.eigenvalues' has fewer than mid_count values");
  expect_size(vectors.size(), static_cast<size_t>(n) * static_cast<size_t>(bb.mid_count), source,
              "bands.vectors");
  expect_size(sqrt_degree.size(), static_cast<size_t>(n), source, "bands.sqrt_degree");
  bb.eigenvalues.resize(eigenvalues.size());
  copy_doubles(eigenvalues, bb.eigenvalues.data());
  bb.vectors = Eigen::Map<const Eigen::MatrixXf>(vectors.data(), n, bb.mid_count);
  bb.sqrt_degree = Eigen::Map<const Eigen::VectorXf>(sqrt_degree.data(), n);
  if (!bb.vectors.allFinite() || !bb.sqrt_degree.allFinite() || !bb.eigenvalues.allFinite())
    bad(source, "field 'bands' holds a non-finite value");
  // Entries of unit eigenvectors are at most 1, eigenvalues of L_norm lie in
  // [0, 2], and sqrt_degree is the root of a vertex degree (1 when isolated).
  if (bb.vectors.cwiseAbs().maxCoeff() > 1.001f) bad(source, "field 'bands.vectors' holds an entry above 1");
  if (bb.eigenvalues.minCoeff() < -1e-6 || bb.eigenvalues.maxCoeff() > 2.0 + 1e-6)
    bad(source, "field 'bands.eigenvalues' leaves [0, 2]");
  if ((bb.sqrt_degree.array() < 1.0f).any() || (bb.sqrt_degree.array() > std::sqrt(float(n))).any())
    bad(source, "field 'bands.sqrt_degree' leaves [1, sqrt(N)]");
  return bb;
}

// The geodesic neighbourhoods (CSR), every index checked.
void read_geodesic(const fb::Neighbourhoods* geodesic, Eigen::Index n, const std::string& source,
                   PreparedData* p) {
  p->geodesic_radius = geodesic->radius();
  const auto& offsets = required(geodesic->offsets(), source, "geodesic.offsets");
  const auto& indices = required(geodesic->indices(), source, "geodesic.indices");
  expect_size(offsets.size(), static_cast<size_t>(n) + 1, source, "geodesic.offsets");
  p->geodesic.offsets.assign(offsets.begin(), offsets.end());
  p->geodesic.indices.assign(indices.begin(), indices.end());
  if (p->geodesic.offsets.front() != 0 || p->geodesic.offsets.back() != static_cast<int32_t>(indices.size()))
    bad(source, "field 'geodesic.offsets' does not span 'geodesic.indices'");
  for (size_t v = 0; v + 1 < p->geodesic.offsets.size(); ++v)
    if (p->geodesic.offsets[v] > p->geodesic.offsets[v + 1])
      bad(source, "field 'geodesic.offsets' decreases at vertex " + std::to_string(v));
  for (size_t i = 0; i < p->geodesic.indices.size(); ++i)
    if (p->geodesic.indices[i] < 0 || p->geodesic.indices[i] >= n)
      bad(source, "field 'geodesic.indices' index " + std::to_string(i) + " is out of range");
}

}  // namespace

Garment deserialize_garment(const uint8_t* data, size_t size, const std::string& source) {
  if (size < 8 || !flatbuffers::BufferHasIdentifier(data, fb::GarmentIdentifier()))
    bad(source, "not a prepared-garment file (identifier PLGM missing)");
  // Newer files still verify (FlatBuffers tables only grow), so the version
  // check after the verifier can tell "upgrade pleat" apart from "corrupt".
  flatbuffers::Verifier verifier(data, size, 64, 100000000);
  if (!fb::VerifyGarmentBuffer(verifier)) bad(source, "file is corrupt or truncated (FlatBuffers verifier)");
  const fb::Garment* root = fb::GetGarment(data);
  if (root->format_version() > kGarmentFormatVersion)
    fail(PLEAT_ERROR_UNSUPPORTED_VERSION, source + ": format_version " +
                                              std::to_string(root->format_version()) +
                                              " is newer than this pleat reads (" +
                                              std::to_string(kGarmentFormatVersion) + "); upgrade pleat");
  if (root->format_version() == 0) bad(source, "field 'format_version' is 0");

  Garment g;
  read_mesh(root, source, &g);
  derive_rest_data(&g);
  read_report(root, source, &g);
  const fb::Bands* bands = root->bands();
  const fb::Neighbourhoods* geodesic = root->geodesic();
  if (!bands != !geodesic) bad(source, "fields 'bands' and 'geodesic' must both be present or both absent");
  if (!bands) return g;
  PreparedData p;
  p.bands = read_bands(bands, g.rest.vertex_count(), source);
  read_geodesic(geodesic, g.rest.vertex_count(), source, &p);
  g.prepared = std::move(p);
  return g;
}

Garment load_garment_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(PLEAT_ERROR_IO, path + ": cannot open the file");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return deserialize_garment(bytes.data(), bytes.size(), path);
}

}  // namespace pleat
