#include "cluttertamp/robot/mesh.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
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

const char* mesh_collision_name(MeshCollision m) { return m == MeshCollision::convex_hull ? "convex_hull" : "triangles"; }

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

TriangleMesh convex_hull(const TriangleMesh& mesh, const SourceLocation& where) {
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
    const auto line_end = why.find('\n');
    throw InputError(where, "the mesh has no convex hull (fewer than 4 vertices, or all on one plane)" +
                                (why.empty() ? std::string() : ": qhull: " + why.substr(0, line_end)));
  }
  return hull;
}

namespace {

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

}  // namespace

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
