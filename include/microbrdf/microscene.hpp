#pragma once
// Micro-scenes for the Westin-Arvo-Torrance 1992 simulation (docs/westin.md, "Micro-scenes"):
// ray-traceable microgeometry on Embree 3 (height fields, cylinders, spheres, velvet fibres,
// woven threads) with the micro-scattering modes of W92 sections 4.2-4.4.
//
// Geometry and the tile. A micro-scene is one period ("tile") of a surface that repeats in x and
// y: the tile spans [0, width) x [0, height) in the scene frame, heights in [zmin, zmax]. Rays
// that leave the tile sideways re-enter on the opposite side (periodic tiling). This is the
// infinite periodic surface, so every point of the tile is equally exposed at every angle: no
// edge effects and no need for W92's margin around a smaller target area (section 4.5). Objects
// that cross the tile boundary are replicated on the other side. A height field is periodic when
// its first and last rows/columns join smoothly (FFT-generated surfaces do); a measured scan is
// not, and can be mirror-tiled instead (period twice the scan, continuous heights).
//
// Frames. The scene frame may be turned about z against the BRDF frame (`rotation`): a BRDF
// direction w maps to Rz(-rotation) w in the scene, so `rotation` = 90 deg makes cylinders built
// along the scene's x axis run along the BRDF's y axis.
//
// Units: metres; directions are unit vectors; normals point out of solids (up for height fields
// and planes).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf {

/// What happens where a ray meets a micro-surface (W92 sections 4.2-4.4).
struct MicroMaterial {
  enum class Kind {
    Mirror,      ///< ideal specular reflection, energy times F(cos) (W92 eq. 22)
    Dielectric,  ///< smooth interface: reflect with probability F, else refract; Beer inside
    Lambert,     ///< ideal diffuse, albedo; cosine-sampled
    Brdf,        ///< any Brdf (analytic or a previously simulated ShBrdf) in the local frame
    Absorber     ///< absorbs everything (velvet base)
  };
  Kind kind = Kind::Absorber;
  std::string name;
  std::shared_ptr<const Fresnel> fresnel;  ///< mirror: reflectance; null = 1
  double eta = 1.5;                        ///< dielectric: index inside / index outside
  double absorption = 0;                   ///< dielectric: Beer coefficient inside, 1/m
  double albedo = 1;                       ///< lambert
  std::shared_ptr<const Brdf> brdf;        ///< brdf: local frame z = normal, x = tangent
  /// brdf: W92 eqs. 23-24 (uniform directions over the hemisphere, weight f cos 2 pi) instead of
  /// the BRDF's own importance sampling (same expectation, usually far less variance).
  bool uniform_sampling = false;
  /// Whether the material spawns the N_b branches (diffuse-like).
  bool diffuse() const { return kind == Kind::Lambert || kind == Kind::Brdf; }
};

/// A capsule: the points within `radius` of the segment a-b (a sphere when a == b). Open-ended
/// cylinders are capsules whose ends lie outside the tile.
struct Capsule {
  Eigen::Vector3d a, b;
  double radius = 0;
  int material = 0;
};

/// The scene before it is built: tile, materials and primitives.
struct MicroSceneDesc {
  std::string name;
  double width = 0, height = 0;  ///< tile size, m
  double rotation = 0;           ///< scene frame = BRDF frame turned by -rotation about z, rad
  double wavelength_m = 550e-9;  ///< wavelength used for Fresnel and analytic BRDFs
  std::vector<MicroMaterial> materials;

  struct HeightField {
    Surface surface;  ///< nx dx x ny dy must equal the tile; periodic across its edges
    int material = 0;
    bool grid = false;  ///< Embree RTC_GEOMETRY_TYPE_GRID instead of a triangle mesh
  };
  std::vector<HeightField> heightfields;
  struct Plane {
    double z = 0;
    int material = 0;
  };
  std::vector<Plane> planes;
  std::vector<Capsule> capsules;  ///< not yet replicated across the tile boundary
  nlohmann::json source;          ///< the JSON it came from (metadata)

  int material_index(const std::string& name) const;  ///< throws InputError when unknown
};

// --- Builders (they append to desc.capsules; all lengths in metres, angles in radians) -------

/// Most capsules one scene may hold: counts come from files, and each capsule costs about
/// 256 bytes once the ray-tracing structures are built (the memory budget applies too).
inline constexpr std::int64_t kMaxSceneObjects = std::int64_t{1} << 25;

/// Parallel cylinders along the scene's x axis (y when `along_y`), `count` of them across the
/// tile (the pitch is the tile size / count so the array is periodic), axes at height z_axis,
/// each shifted across by a uniform random amount in [-jitter, jitter] * pitch. Other
/// orientations: turn the whole scene (MicroSceneDesc::rotation).
void add_cylinders(MicroSceneDesc& d, double radius, std::int64_t count, double z_axis,
                   double jitter, std::uint64_t seed, int material, bool along_y = false);
/// Spheres on a square grid of `pitch` (tile / pitch must be a whole number), centres at z,
/// jittered by [-jitter, jitter] * pitch in x and y.
void add_spheres(MicroSceneDesc& d, double radius, double pitch, double z, double jitter,
                 std::uint64_t seed, int material);
/// Velvet (W92 section 5.3): `count` straight fibres rooted at z = 0 at uniform random points,
/// length `length`, tilted from the normal by tilt +- tilt_spread (uniform) towards azimuth
/// tilt_azimuth +- azimuth_spread.
struct FiberParams {
  std::int64_t count = 400;
  double radius = 5e-6, length = 300e-6;
  double tilt = 0.17, tilt_spread = 0.1, tilt_azimuth = 0, azimuth_spread = M_PI;
  std::uint64_t seed = 1;
  int material = 0;
};
void add_fibers(MicroSceneDesc& d, const FiberParams& p);
/// Plain weave (W92 section 5.4): warp threads along x and weft threads along y, `pitch` apart,
/// each passing alternately over and under the crossing threads (centre line z = +-crimp at the
/// crossings, a cosine between), as chains of `segments_per_pitch` capsules per pitch. The tile
/// must be a whole even number of pitches.
struct WeaveParams {
  double pitch = 200e-6, radius = 50e-6, crimp = 50e-6;
  std::int64_t segments_per_pitch = 12;
  int warp_material = 0, weft_material = 0;
};
void add_weave(MicroSceneDesc& d, const WeaveParams& p);

/// How far the geometry may reach from the tile, in multiples of the tile's shorter side: every
/// coordinate, radius and height within that many sides of the tile (see check_scene_geometry).
inline constexpr double kMaxSceneReach = 100;

/// Refuses geometry the tracer cannot follow: a tile side under 1 nm, or any capsule end, radius,
/// plane or height that is not finite or lies more than kMaxSceneReach tile sides (the shorter
/// side) from the tile. The bound keeps Embree's single-precision rays valid and every ray's
/// walk across the periodic tiles short (a ray crossing the scene's height range at elevation
/// e wraps across at most about kMaxSceneReach / tan(e) tiles). Throws InputError naming the
/// object and the numbers. MicroScene's constructor and the JSON reader call it.
void check_scene_geometry(const MicroSceneDesc& d);

/// A mirror-tiled copy (2 nx x 2 ny, reflected) that is periodic and continuous.
Surface mirror_tile(const Surface& s);

/// Reads the JSON scene format (docs/westin.md, "Micro-scenes"; examples/scenes/). Relative file
/// names inside are relative to the scene file. Throws FileError / InputError naming the file.
MicroSceneDesc load_micro_scene(const std::string& path);
/// The same from a parsed document; `base_dir` resolves relative paths, `origin` names it in
/// error messages.
MicroSceneDesc parse_micro_scene(const nlohmann::json& j, const std::string& base_dir,
                                 const std::string& origin);

/// Where a ray meets the scene.
struct MicroHit {
  Eigen::Vector3d p;        ///< point, inside the tile (scene frame), m
  Eigen::Vector3d n;        ///< unit normal, out of the solid (up for height fields and planes)
  Eigen::Vector3d tangent;  ///< unit, orthogonal to n: the local BRDF's x axis
  int material = 0;
  double path_length = 0;  ///< distance travelled from the ray's origin, m (over all tiles)
};

enum class TraceEnd {
  Hit,
  EscapedUp,    ///< left the top of the scene (an exit ray)
  EscapedDown,  ///< fell below the scene (transmitted; lost for a BRDF)
  Lost          ///< ran along the tile without end (a ray exactly parallel to the plane)
};

/// One ray of a trace as Embree sees it (float origin, direction, [0, tfar]), for benchmarks that
/// replay the very rays a simulation traces. `kind`: 0 the first query of an incident ray, 1 a
/// query after a scattering event, 2 a continuation across a tile wall, 3 an escape ray that
/// MicroScene::clears_upward() answered without Embree (recorded as the query it replaces).
struct MicroRay {
  float o[3], d[3], tfar;
  int kind;
};

/// A built scene; thread-safe for tracing. Holds an Embree device and scene.
class MicroScene {
 public:
  explicit MicroScene(MicroSceneDesc desc);
  ~MicroScene();
  MicroScene(const MicroScene&) = delete;
  MicroScene& operator=(const MicroScene&) = delete;

  const MicroSceneDesc& desc() const { return desc_; }
  double width() const { return desc_.width; }
  double height() const { return desc_.height; }
  double zmin() const { return zmin_; }
  double zmax() const { return zmax_; }
  /// Offset used to leave a surface without hitting it again, m.
  double epsilon() const { return eps_; }
  std::size_t triangle_count() const { return triangles_; }
  std::size_t capsule_count() const { return capsules_.size(); }  ///< including replicas

  /// Follows the ray from `origin` (inside the tile) along unit `dir` across tiles until it hits
  /// something, leaves the top or the bottom. On return `origin` holds the last tile-wrapped
  /// origin; `segments` (if given) is incremented by the Embree queries made.
  /// `log` (if given) receives every query, the first one tagged `kind` (0 or 1), the tile
  /// continuations 2.
  TraceEnd trace(Eigen::Vector3d origin, const Eigen::Vector3d& dir, MicroHit& hit,
                 std::size_t* segments = nullptr, std::vector<MicroRay>* log = nullptr,
                 int kind = 0) const;

  /// For a scene made of one height field alone: true when the ray from `p + epsilon() n` along
  /// unit `dir` (dir.z > 0), where `p` is a point of the height field found by trace() and `n`
  /// its upward unit normal, provably leaves the top of the scene without meeting the surface
  /// (clearing it by at least epsilon() / 4, far above Embree's round-off), decided from
  /// per-block maximum heights and slopes of the mesh without an Embree query. False when the
  /// bound cannot decide (the caller traces the ray) and always for other scenes.
  bool clears_upward(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                     const Eigen::Vector3d& dir) const;
  /// Whether clears_upward() can answer at all (a scene of one height field alone).
  bool has_escape_bound() const { return !esc_hmax_.empty(); }

  /// Scene frame <-> BRDF frame (rotation about z).
  Eigen::Vector3d to_scene(const Eigen::Vector3d& w) const;
  Eigen::Vector3d to_brdf(const Eigen::Vector3d& w) const;

  /// The raw Embree scene (RTCScene), for benchmarks that trace bare rays.
  void* embree_scene() const { return scene_; }
  /// Geometry id of the first height field (or -1): bare benchmark loops report it.
  int heightfield_geometry() const { return hf_geom_; }

  /// Internal: capsule and plane primitives of the user geometry (with replicas).
  struct Analytic {
    Eigen::Vector3d a, u;  // start, unit axis (u = 0 for spheres; plane: a.z = height)
    double length = 0, radius = 0;
    int material = 0;
    bool plane = false;
  };

 private:
  void build_escape_bound();
  MicroSceneDesc desc_;
  void* device_ = nullptr;  // RTCDevice
  void* scene_ = nullptr;   // RTCScene
  std::vector<Analytic> capsules_;
  std::vector<int> geom_material_;  // per Embree geometry id: material (-1 = user geometry)
  std::vector<std::vector<float>> vertex_store_;  // shared with Embree
  void* user_data_owner_ = nullptr;
  double zmin_ = 0, zmax_ = 0, eps_ = 0;
  double cos_rot_ = 1, sin_rot_ = 0;
  std::size_t triangles_ = 0;
  unsigned user_geom_ = ~0u;
  int hf_geom_ = -1;
  // clears_upward(): blocks of 8 x 8 cells (the last ones in a row or column may be narrower),
  // per block the highest vertex and the ranges of the gradient components (min, max of
  // dh/dx, then of dh/dy) of the triangles over it (both diagonals of every cell); esc_top_ the
  // highest vertex of all.
  int esc_nbx_ = 0, esc_nby_ = 0;
  double esc_bw_ = 0, esc_bh_ = 0, esc_top_ = 0;
  std::vector<double> esc_hmax_, esc_grad_;
};

}  // namespace microbrdf
