#pragma once
// Triangle meshes of robot links: read from STL, COLLADA (DAE) or OBJ files, found
// through the URIs URDF files use (package://, file://, relative paths).

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::robot {

/// Triangles over shared vertices, in the frame of the shape that holds them, metres.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< counter-clockwise seen from outside

  /// Axis-aligned bounds of the vertices, in the mesh frame (empty box for no vertices).
  CLUTTERTAMP_API void bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const;
};

/// How a link's mesh collides.
enum class MeshCollision {
  convex_hull,  ///< its convex hull: conservative (covers hollows), the fewest shapes
  triangles,    ///< its triangles (a bounding volume hierarchy): exact surface, slower
  /// A few convex hulls that together cover it (convex_pieces): conservative as the
  /// hull, as fast to query, and close to the shape of a link whose hull is much
  /// bulkier than the link (a tube with housings at its ends). The default.
  convex_pieces,
};

/// "convex_hull", "triangles" or "convex_pieces".
CLUTTERTAMP_API const char* mesh_collision_name(MeshCollision m);

/// Where package:// URIs are looked for. A directory D serves package NAME when D is
/// named NAME, or holds NAME (D/NAME), or holds a folder that holds it (D/*/NAME, as a
/// ROS workspace's source folder does).
struct PackagePaths {
  std::vector<std::filesystem::path> directories;

  /// `directories` then each entry of ROS_PACKAGE_PATH (':'-separated), when set.
  CLUTTERTAMP_API static PackagePaths with_environment(std::vector<std::filesystem::path> directories);
};

/// The file a mesh URI names: package://NAME/REST (through `packages`), file:///ABS, or
/// a path (relative to `relative_to`, the URDF's folder). Throws InputError at `where`
/// naming the URI and every directory searched when there is no such file.
CLUTTERTAMP_API std::filesystem::path resolve_mesh_uri(const std::string& uri, const std::filesystem::path& relative_to,
                                                       const PackagePaths& packages, const SourceLocation& where);

/// Reads every triangle of a mesh file (STL, DAE, OBJ and the other formats assimp
/// reads), with its node transforms applied, COLLADA's <unit> applied and its up axis
/// ignored (as ROS tools do: the mesh is in the link frame), then `scale` per axis.
/// Throws InputError at `where` for an unreadable file or one without triangles.
CLUTTERTAMP_API TriangleMesh load_mesh(const std::filesystem::path& file, const Eigen::Vector3d& scale,
                                       const SourceLocation& where);

/// The convex hull of the mesh's vertices, triangulated (qhull). Throws InputError at
/// `where` for a mesh with no volume (all vertices on a plane).
CLUTTERTAMP_API TriangleMesh convex_hull(const TriangleMesh& mesh, const SourceLocation& where);

/// Convex hulls whose union holds every triangle of the mesh and, for a closed mesh,
/// what it encloses. Starting from the mesh's hull, a piece is split in two by a plane
/// across one axis of its bounds, at a quarter, half or three quarters: the plane whose
/// halves have the smallest bounding boxes; each half is the piece's triangles clipped
/// by the plane (so the halves meet on it) and collides as its own hull. The split
/// whose two hulls hold least against the piece's is taken first, while that gain is
/// at least `min_gain` (a fraction) of the piece's hull volume, up to `max_pieces`.
/// Deterministic. Throws InputError at `where` for a mesh with no volume (as convex_hull).
CLUTTERTAMP_API std::vector<TriangleMesh> convex_pieces(const TriangleMesh& mesh, const SourceLocation& where,
                                                        std::size_t max_pieces = 6, double min_gain = 0.2);

/// The volume a closed mesh encloses, m^3 (its triangles outward; a convex hull's are).
CLUTTERTAMP_API double enclosed_volume(const TriangleMesh& mesh);

/// The mesh with at most `max_triangles` triangles, for drawing: vertices merged on ever
/// coarser grids (vertex clustering) until it fits; triangles that collapse are dropped.
/// Deterministic. The mesh itself when it already fits.
CLUTTERTAMP_API TriangleMesh simplified(const TriangleMesh& mesh, std::size_t max_triangles);

/// Writes the mesh as ASCII STL (what `self-collisions` and the tests make meshes with).
CLUTTERTAMP_API std::string to_ascii_stl(const TriangleMesh& mesh, const std::string& name);

}  // namespace cluttertamp::robot
