#include "cluttertamp/robot/mesh.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>
#include <unordered_map>

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace cluttertamp::robot {

namespace fs = std::filesystem;

void TriangleMesh::bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const {
  min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  max = -min;
  for (const Eigen::Vector3d& v : vertices) {
    min = min.cwiseMin(v);
    max = max.cwiseMax(v);
  }
}

const char* mesh_collision_name(MeshCollision m) {
  switch (m) {
    case MeshCollision::convex_hull: return "convex_hull";
    case MeshCollision::triangles: return "triangles";
    case MeshCollision::convex_pieces: return "convex_pieces";
  }
  return "?";
}

PackagePaths PackagePaths::with_environment(std::vector<fs::path> directories) {
  PackagePaths out{std::move(directories)};
  if (const char* env = std::getenv("ROS_PACKAGE_PATH")) {
    std::stringstream list(env);
    for (std::string entry; std::getline(list, entry, ':');) {
      if (!entry.empty()) out.directories.emplace_back(entry);
    }
  }
  return out;
}

namespace {

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// The folders of `root` that may be package NAME: root itself, root/NAME, root/*/NAME.
std::vector<fs::path> package_candidates(const fs::path& root, const std::string& name) {
  std::vector<fs::path> out;
  if (root.filename() == name) out.push_back(root);
  out.push_back(root / name);
  std::error_code ec;
  std::vector<fs::path> children;
  for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_directory(type_ec)) children.push_back(it->path() / name);
  }
  std::sort(children.begin(), children.end());  // the same answer on every file system
  out.insert(out.end(), children.begin(), children.end());
  return out;
}

std::string list(const std::vector<fs::path>& directories) {
  std::string out;
  for (const fs::path& d : directories) out += "\n  " + d.string();
  return out;
}

}  // namespace

fs::path resolve_mesh_uri(const std::string& uri, const fs::path& relative_to, const PackagePaths& packages,
                          const SourceLocation& where) {
  const std::string package_scheme = "package://", file_scheme = "file://";
  if (uri.rfind(package_scheme, 0) == 0) {
    const std::string rest = uri.substr(package_scheme.size());
    const auto slash = rest.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == rest.size()) {
      throw InputError(where, "mesh URI '" + uri + "' is not package://NAME/PATH");
    }
    const std::string name = rest.substr(0, slash), path = rest.substr(slash + 1);
    if (packages.directories.empty()) {
      throw InputError(where, "mesh '" + uri + "': no package path to find package '" + name +
                                  "' in (give --package-path DIR, package_paths: in the robot description, or set ROS_PACKAGE_PATH)");
    }
    std::vector<fs::path> searched;
    for (const fs::path& root : packages.directories) {
      for (const fs::path& package : package_candidates(root, name)) {
        if (is_file(package / path)) return package / path;
        searched.push_back(package);
      }
    }
    throw InputError(where, "mesh '" + uri + "' not found: no '" + path + "' in package '" + name + "'; searched" + list(searched));
  }
  fs::path file;
  if (uri.rfind(file_scheme, 0) == 0) {
    file = uri.substr(file_scheme.size());
  } else if (uri.find("://") != std::string::npos) {
    throw InputError(where, "mesh URI '" + uri + "' has a scheme cluttertamp does not read (package://, file:// or a path)");
  } else {
    file = fs::path(uri).is_absolute() ? fs::path(uri) : relative_to / uri;
  }
  if (!is_file(file)) throw InputError(where, "mesh '" + uri + "' not found: no file " + file.string());
  return file;
}

namespace {

// Appends the triangles of every node, each placed by the product of the transforms
// from the root. Iterative: a file may nest nodes deeper than the stack goes.
void collect(const aiScene& scene, TriangleMesh& out) {
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> open{{scene.mRootNode, scene.mRootNode->mTransformation}};
  while (!open.empty()) {
    const auto [node, root_T_node] = open.back();
    open.pop_back();
    for (unsigned m = 0; m < node->mNumMeshes; ++m) {
      const aiMesh& mesh = *scene.mMeshes[node->mMeshes[m]];
      const auto base = static_cast<std::uint32_t>(out.vertices.size());
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const aiVector3D p = root_T_node * mesh.mVertices[v];
        out.vertices.emplace_back(p.x, p.y, p.z);
      }
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
        out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
      }
    }
    for (unsigned c = node->mNumChildren; c-- > 0;) open.emplace_back(node->mChildren[c], root_T_node * node->mChildren[c]->mTransformation);
  }
}

}  // namespace

TriangleMesh load_mesh(const fs::path& file, const Eigen::Vector3d& scale, const SourceLocation& where) {
  Assimp::Importer importer;
  // The up axis a COLLADA file declares is not applied (the mesh is in its link frame,
  // as RViz and MoveIt read it); its <unit> is.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) {
    throw InputError(where, "cannot read mesh " + file.string() + ": " + importer.GetErrorString());
  }
  TriangleMesh mesh;
  collect(*scene, mesh);
  if (mesh.triangles.empty()) throw InputError(where, "mesh " + file.string() + " has no triangles");
  for (Eigen::Vector3d& v : mesh.vertices) {
    v = v.cwiseProduct(scale);
    if (!v.allFinite()) throw InputError(where, "mesh " + file.string() + " has a vertex that is not a finite number");
  }
  // A mirroring scale turns every triangle inside out.
  if (scale.prod() < 0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

namespace {

// The hull, or none with qhull's first message line for a mesh without volume.
std::optional<TriangleMesh> hull_of(const TriangleMesh& mesh, std::string& why_not) {
  std::vector<coordT> points;
  points.reserve(mesh.vertices.size() * 3);
  for (const Eigen::Vector3d& v : mesh.vertices) points.insert(points.end(), {v.x(), v.y(), v.z()});
  // qhull's messages go to a memory stream: ours says what failed.
  char* messages = nullptr;
  std::size_t message_size = 0;
  FILE* memory = open_memstream(&messages, &message_size);
  FILE* errors = memory ? memory : stderr;
  qhT state;
  qhT* qh = &state;
  qh_zero(qh, errors);
  char options[] = "qhull Qt";  // triangulated facets
  const bool ran = mesh.vertices.size() >= 4;  // qhull is not started on fewer
  const int failed = ran ? qh_new_qhull(qh, 3, static_cast<int>(mesh.vertices.size()), points.data(), False, options, nullptr, errors) : 1;
  TriangleMesh hull;
  if (!failed) {
    std::unordered_map<int, std::uint32_t> index;  // qhull point id -> hull vertex
    auto vertex_of = [&](vertexT* v) {
      const int id = qh_pointid(qh, v->point);
      const auto [it, added] = index.emplace(id, static_cast<std::uint32_t>(hull.vertices.size()));
      if (added) hull.vertices.push_back(mesh.vertices[static_cast<std::size_t>(id)]);
      return it->second;
    };
    for (facetT* facet = qh->facet_list; facet && facet->next; facet = facet->next) {
      if (qh_setsize(qh, facet->vertices) != 3) continue;
      std::array<std::uint32_t, 3> t{};
      for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(k)] = vertex_of(static_cast<vertexT*>(facet->vertices->e[k].p));
      // qhull's vertex order says nothing of orientation: the normal must point outwards.
      const Eigen::Vector3d a = hull.vertices[t[0]], b = hull.vertices[t[1]], c = hull.vertices[t[2]];
      const Eigen::Vector3d outward(facet->normal[0], facet->normal[1], facet->normal[2]);
      if ((b - a).cross(c - a).dot(outward) < 0) std::swap(t[1], t[2]);
      hull.triangles.push_back(t);
    }
  }
  if (ran) {
    qh_freeqhull(qh, !qh_ALL);
    int long_left = 0, long_bytes = 0;
    qh_memfreeshort(qh, &long_left, &long_bytes);
  }
  if (memory) std::fclose(memory);
  std::string why(messages ? messages : "", message_size);
  std::free(messages);
  if (failed || hull.triangles.empty()) {
    why_not = why.substr(0, why.find('\n'));
    return std::nullopt;
  }
  return hull;
}

}  // namespace

TriangleMesh convex_hull(const TriangleMesh& mesh, const SourceLocation& where) {
  std::string why;
  std::optional<TriangleMesh> hull = hull_of(mesh, why);
  if (!hull) {
    throw InputError(where, "the mesh has no convex hull (fewer than 4 vertices, or all on one plane)" +
                                (why.empty() ? std::string() : ": qhull: " + why));
  }
  return std::move(*hull);
}

double enclosed_volume(const TriangleMesh& mesh) {
  double six_volume = 0;
  for (const auto& t : mesh.triangles) {
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  return six_volume / 6;
}

namespace {

// The mesh's triangles clipped to the side of the plane x[axis] = at that `keep_below`
// says; each clipped polygon fanned back into triangles.
TriangleMesh clipped(const TriangleMesh& mesh, int axis, double at, bool keep_below) {
  TriangleMesh out;
  // Kept vertices are shared as in the mesh (qhull's time grows with the points).
  std::vector<std::uint32_t> kept(mesh.vertices.size(), std::numeric_limits<std::uint32_t>::max());
  auto inside = [&](const Eigen::Vector3d& v) { return keep_below ? at - v[axis] : v[axis] - at; };  // >= 0: kept
  std::vector<std::uint32_t> polygon;
  for (const auto& t : mesh.triangles) {
    polygon.clear();
    for (std::size_t i = 0; i < 3; ++i) {
      const std::uint32_t a = t[i], b = t[(i + 1) % 3];
      const double inside_a = inside(mesh.vertices[a]), inside_b = inside(mesh.vertices[b]);
      if (inside_a >= 0) {
        if (kept[a] == std::numeric_limits<std::uint32_t>::max()) {
          kept[a] = static_cast<std::uint32_t>(out.vertices.size());
          out.vertices.push_back(mesh.vertices[a]);
        }
        polygon.push_back(kept[a]);
      }
      if ((inside_a >= 0) != (inside_b >= 0)) {
        polygon.push_back(static_cast<std::uint32_t>(out.vertices.size()));
        out.vertices.push_back(mesh.vertices[a] + (mesh.vertices[b] - mesh.vertices[a]) * (inside_a / (inside_a - inside_b)));
      }
    }
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) out.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
  }
  return out;
}

// The mesh with its vertices merged per grid cell of size `cell` (their mean).
TriangleMesh clustered(const TriangleMesh& mesh, const Eigen::Vector3d& origin, double cell) {
  std::map<std::array<long, 3>, std::uint32_t> cell_vertex;
  std::vector<Eigen::Vector3d> sums;
  std::vector<int> counts;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d c = ((mesh.vertices[i] - origin) / cell).array().floor();
    const std::array<long, 3> key{static_cast<long>(c.x()), static_cast<long>(c.y()), static_cast<long>(c.z())};
    const auto [it, added] = cell_vertex.emplace(key, static_cast<std::uint32_t>(sums.size()));
    if (added) {
      sums.push_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[it->second] += mesh.vertices[i];
    ++counts[it->second];
    remap[i] = it->second;
  }
  TriangleMesh out;
  for (std::size_t v = 0; v < sums.size(); ++v) out.vertices.push_back(sums[v] / counts[v]);
  std::set<std::array<std::uint32_t, 3>> seen;
  for (const auto& t : mesh.triangles) {
    const std::array<std::uint32_t, 3> r{remap[t[0]], remap[t[1]], remap[t[2]]};
    if (r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
    std::array<std::uint32_t, 3> key = r;
    std::sort(key.begin(), key.end());
    if (seen.insert(key).second) out.triangles.push_back(r);
  }
  return out;
}

struct Piece {
  TriangleMesh part;  // the mesh's triangles (clipped) this piece covers
  TriangleMesh hull;
  double volume = 0;
};

struct Split {
  double gain = 0;  // the piece's hull volume less its halves'
  std::array<Piece, 2> halves;
};

double box_volume(const TriangleMesh& mesh) {
  Eigen::Vector3d min, max;
  mesh.bounds(min, max);
  return (max - min).cwiseMax(0.0).prod();
}

// The split of a piece across one axis of its bounds whose halves' bounding boxes hold
// least (a stand-in for their hulls, which cost a qhull run each to measure), with
// the volume its halves' hulls gain; none when a half has no volume.
std::optional<Split> best_split(const Piece& piece) {
  Eigen::Vector3d min, max;
  piece.part.bounds(min, max);
  std::optional<std::array<TriangleMesh, 2>> best;
  double best_boxes = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    for (const double fraction : {0.25, 0.5, 0.75}) {
      const double at = min[axis] + fraction * (max[axis] - min[axis]);
      std::array<TriangleMesh, 2> halves{clipped(piece.part, axis, at, true), clipped(piece.part, axis, at, false)};
      if (halves[0].triangles.empty() || halves[1].triangles.empty()) continue;
      const double boxes = box_volume(halves[0]) + box_volume(halves[1]);
      if (boxes < best_boxes) {
        best_boxes = boxes;
        best = std::move(halves);
      }
    }
  }
  if (!best) return std::nullopt;
  Split split;
  std::string unused;
  for (std::size_t k = 0; k < 2; ++k) {
    Piece& half = split.halves[k];
    half.part = std::move((*best)[k]);
    std::optional<TriangleMesh> hull = hull_of(half.part, unused);
    if (!hull) return std::nullopt;
    half.hull = std::move(*hull);
    half.volume = enclosed_volume(half.hull);
  }
  split.gain = piece.volume - split.halves[0].volume - split.halves[1].volume;
  return split;
}

}  // namespace

std::vector<TriangleMesh> convex_pieces(const TriangleMesh& mesh, const SourceLocation& where, std::size_t max_pieces,
                                        double min_gain) {
  std::vector<Piece> pieces(1);
  // Points merged to within a nanometre (STL repeats each vertex per triangle): fewer
  // points for qhull on every split tried.
  Eigen::Vector3d min, max;
  mesh.bounds(min, max);
  pieces[0].part = clustered(mesh, min, 1e-9);
  pieces[0].hull = convex_hull(pieces[0].part, where);
  pieces[0].volume = enclosed_volume(pieces[0].hull);
  std::vector<std::optional<Split>> splits{best_split(pieces[0])};  // per piece; none: not to be split
  while (pieces.size() < max_pieces) {
    std::size_t chosen = pieces.size();
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      if (!splits[i] || splits[i]->gain < min_gain * pieces[i].volume) continue;
      if (chosen == pieces.size() || splits[i]->gain > splits[chosen]->gain) chosen = i;
    }
    if (chosen == pieces.size()) break;
    std::array<Piece, 2> halves = std::move(splits[chosen]->halves);
    pieces[chosen] = std::move(halves[0]);
    splits[chosen] = best_split(pieces[chosen]);
    pieces.push_back(std::move(halves[1]));
    splits.push_back(best_split(pieces.back()));
  }
  std::vector<TriangleMesh> out;
  out.reserve(pieces.size());
  for (Piece& p : pieces) out.push_back(std::move(p.hull));
  return out;
}

TriangleMesh simplified(const TriangleMesh& mesh, std::size_t max_triangles) {
  if (mesh.triangles.size() <= max_triangles) return mesh;
  Eigen::Vector3d min, max;
  mesh.bounds(min, max);
  const double diagonal = std::max((max - min).norm(), 1e-9);
  TriangleMesh out;
  for (int cells = 256; cells >= 2; cells = cells * 3 / 4) {
    out = clustered(mesh, min, diagonal / cells);
    if (out.triangles.size() <= max_triangles) break;
  }
  return out;
}

std::string to_ascii_stl(const TriangleMesh& mesh, const std::string& name) {
  std::ostringstream out;
  out.precision(17);
  out << "solid " << name << "\n";
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    out << " facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n  outer loop\n";
    for (const Eigen::Vector3d* v : {&a, &b, &c}) out << "   vertex " << v->x() << " " << v->y() << " " << v->z() << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid " << name << "\n";
  return out.str();
}

}  // namespace cluttertamp::robot
