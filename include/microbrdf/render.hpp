#pragma once
// The preview renderer: a spectral path tracer on Embree 3 that draws any Brdf / Svbrdf of the
// project on preview objects under environment maps and lights (Dong 2015 Figs. 10 and 13,
// Sun 2002 Figs. 8-11).
//
// Units: scene lengths are dimensionless (objects are about 1 unit across); radiance of an
// environment map is taken as stored (linear, per sRGB channel, upsampled to spectra); output
// pixels are linear sRGB radiance (EXR) and tone-mapped sRGB (PNG). Deterministic for a seed
// whatever the thread count.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "microbrdf/svbrdf.hpp"

namespace microbrdf {

struct MicroSceneDesc;  // microscene.hpp

enum class PreviewScene {
  Cylinders,  ///< two cylinder sections, the BRDF rotated 90 degrees between them (Dong Fig. 10)
  Plate,      ///< a flat plate seen from above under a small area light (Dong Fig. 13)
  Sphere,
  Vase,          ///< a surface of revolution
  Obj,           ///< an OBJ mesh (RenderScene::obj_path)
  FurnaceSphere  ///< a sphere alone in a uniform white environment (tests)
};
PreviewScene parse_preview_scene(const std::string& name);  ///< throws InputError listing names
std::string preview_scene_name(PreviewScene s);

enum class Brushing {
  Linear,     ///< tangent (the BRDF's x axis) along a fixed direction, `brush_angle_rad` about n
  Rotational  ///< tangent along circles about the object's axis (Westin's wheel)
};

struct RenderScene {
  PreviewScene kind = PreviewScene::Cylinders;
  std::string obj_path;
  Brushing brushing = Brushing::Linear;
  double brush_angle_rad = 0;
  double uv_scale = 1;  ///< texture repeats per unit length (SVBRDF textures)
  /// The plate only: its surface is this micro-scene's geometry itself (the scene JSON that
  /// `microbrdf simulate` traces, include/microbrdf/microscene.hpp), repeated periodically over
  /// the plate, instead of a flat plate with a BRDF. The micro-scene's z axis is the plate's
  /// normal, its BRDF-frame x axis the plate's brushing direction (the camera's right turned by
  /// brush_angle_rad, so the same flags orient a simulated BRDF and the geometry it came from),
  /// and z = 0 lies in the plate's plane. Each of its materials is one object (material slot):
  /// pass micro_scene_materials() as the materials. Linear brushing only. Null = the flat plate.
  std::shared_ptr<const MicroSceneDesc> micro_scene;
  /// How many tiles of the micro-scene span the plate's side (2 scene units): the scale at which
  /// the micro-geometry is seen (a tile is 2 / micro_tiles units wide). > 0.
  double micro_tiles = 8;
};

/// The materials of a micro-scene as the renderer draws them, one per material of the scene in
/// its order (the material slots of RenderScene::micro_scene): mirror -> an ideal mirror with
/// the material's Fresnel term, lambert -> Lambertian of its albedo, microfacet and shbrdf ->
/// that BRDF, absorber -> black. Dielectrics (transmission) are not drawn: InputError naming the
/// material.
std::vector<std::shared_ptr<const Svbrdf>> micro_scene_materials(const MicroSceneDesc& scene);

struct RenderLights {
  std::string envmap_path;         ///< EXR or Radiance HDR, equirectangular; empty = none
  double envmap_scale = 1;         ///< multiplies the map
  double envmap_rotation_rad = 0;  ///< about the world up axis
  bool uniform_white_env = false;  ///< radiance 1 everywhere (furnace tests)
  struct Point {
    Eigen::Vector3d position, rgb_intensity;
  };  ///< intensity in W/sr per channel
  struct Sphere {
    Eigen::Vector3d centre;
    double radius;
    Eigen::Vector3d rgb_radiance;
  };
  struct Disk {
    Eigen::Vector3d centre, normal;
    double radius;
    Eigen::Vector3d rgb_radiance;
  };
  std::vector<Point> points;
  std::vector<Sphere> spheres;
  std::vector<Disk> disks;
};

/// What `render` and `mb.render` light a scene with when given no light at all: the plate gets
/// dong_plate_light(), every other scene a uniform white sky of radiance 1.
void add_default_light_if_none(RenderLights& lights, PreviewScene scene);

/// The light of Dong 2015 Fig. 13 for the plate scene: a disk spanning 9 degrees, 23 degrees to
/// the left of the camera (which looks straight down), as far from the plate as the camera; its
/// radiance 1/sin^2(4.5 deg) gives an irradiance of pi on a surface facing it (a white
/// Lambertian surface facing the light would have radiance 1).
RenderLights::Disk dong_plate_light();

enum class MisMode { Mis, BrdfOnly, LightOnly };

/// How direct light from area lights and the environment is estimated at a shading point (with
/// MisMode::Mis; docs/render.md, "Estimators"):
///  - Mis: one light sample and the BRDF-sampled continuation, weighted by the power heuristic;
///  - Ris: resampled importance sampling: RenderOptions::ris_brdf_candidates BRDF-sampled and
///    ris_light_candidates light-sampled directions (no rays), one of them chosen in proportion
///    to an unshadowed, Fresnel-free estimate of its contribution over the balance-heuristic
///    mixture density, one shadow ray for it; the continuation then carries indirect light only.
///    Unbiased; lower noise at equal time for glossy materials under detailed maps. Delta lights
///    (points) keep their own light samples, delta lobes their continuation's emission; under a
///    uniform environment alone (where the target is the BRDF's density) Mis is used.
enum class DirectLight { Mis, Ris };
/// "mis" or "ris"; throws InputError naming `flag` otherwise.
DirectLight parse_direct_light(const std::string& name, const std::string& flag);
std::string direct_light_name(DirectLight d);

/// How the random numbers of each path are drawn: Sobol = padded Owen-scrambled Sobol' points
/// (stratified per pixel; the default, lower noise at equal time), Independent = plain Monte
/// Carlo (docs/render.md, "Sampling").
enum class RenderSampler { Sobol, Independent };
/// "sobol" or "independent"; throws InputError naming `flag` otherwise.
RenderSampler parse_render_sampler(const std::string& name, const std::string& flag);
std::string render_sampler_name(RenderSampler s);

struct RenderOptions {
  int width = 512, height = 512;
  int spp = 64;       ///< samples per pixel
  int max_depth = 6;  ///< path length cap (reported)
  /// Hero-wavelength samples per path (360-830 nm); 8 has less noise at equal time than 4 in
  /// every case of docs/benchmarks.md, "Render noise".
  int wavelengths = 8;
  std::uint64_t seed = 1;
  int threads = 0;  ///< 0 = all cores
  MisMode mis = MisMode::Mis;
  RenderSampler sampler = RenderSampler::Sobol;
  DirectLight direct = DirectLight::Ris;  ///< direct-light estimator (with mis = MisMode::Mis)
  int ris_brdf_candidates = 6;            ///< DirectLight::Ris: BRDF-sampled candidates (1..16)
  int ris_light_candidates = 3;           ///< DirectLight::Ris: light-sampled candidates (1..4)
  double exposure = 0;                    ///< stops, for the PNG only
  std::function<void(double fraction)> progress;  ///< called from one thread, fraction in [0, 1]
  /// Also return the images of the first and the second half of each pixel's samples
  /// (RenderImage::half_rgb; needs spp >= 2).
  bool half_images = false;
  /// render_variants only: the share of each variant's BRDF sampler in the mixture that draws
  /// the path's next direction (one weight per variant, >= 0, not all 0; empty = equal shares).
  /// A variant of weight 0 is still rendered, through the others' samples: give 0 only to a
  /// variant whose lobe the weighted ones cover (e.g. a tabulated NDF beside analytic fits,
  /// which reach every direction), or its image is biased.
  std::vector<double> variant_weights;
};

/// "mis", "brdf" or "light" (MisMode); throws InputError naming `flag` otherwise.
MisMode parse_mis_mode(const std::string& name, const std::string& flag);
/// "M,N": options.ris_brdf_candidates = M (1..16) and ris_light_candidates = N (1..4); throws
/// InputError naming `flag` otherwise.
void parse_ris_candidates(const std::string& text, const std::string& flag, RenderOptions& options);

/// Most variants render_variants takes.
inline constexpr int kMaxRenderVariants = 8;
/// Most light sets render_light_sets takes.
inline constexpr int kMaxRenderLightSets = 4;

struct RenderImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< linear sRGB, row-major from the top, 3 floats per pixel
  double seconds = 0;      ///< wall time
  double samples_per_second = 0;
  std::uint64_t rays = 0;
  std::string settings;  ///< one line: scene, materials, lights, spp, seed (EXR header, JSON)
  /// With RenderOptions::half_images: the images of sample indices [0, spp/2) and
  /// [spp/2, spp), each the mean of its own samples (rgb is their mean weighted by the counts).
  /// Two estimates of the same image from disjoint samples: their difference measures the noise
  /// (see docs/render.md, "Half images"). Empty otherwise.
  std::array<std::vector<float>, 2> half_rgb;
};

/// `materials` holds one entry (applied to every object) or one per object of the scene (the
/// cylinder pair takes two: the second is what the first is with the tangent turned 90 degrees,
/// so passing one material there is the Dong Fig. 10 set-up; with two, the left cylinder takes
/// the first and the right one the second, and the right one's tangent is still turned by 90
/// degrees). Throws InputError (bad options, no light, wrong material count) or FileError
/// (unreadable environment map or OBJ). Method and conventions: docs/render.md.
RenderImage render(const RenderScene& scene,
                   const std::vector<std::shared_ptr<const Svbrdf>>& materials,
                   const RenderLights& lights, const RenderOptions& options);

/// Several materials ("variants") of one scene rendered along the same paths: every camera
/// ray, light sample and shadow ray is shared, each variant carries its own throughput, and the
/// next direction is drawn from the mixture of the variants' BRDF samplers
/// (RenderOptions::variant_weights) and weighted by f_v cos / p_mix for every variant v; the
/// light samples' MIS weights use the same mixture density. Each image is an unbiased estimate
/// of what render() gives for that variant alone, and their noise is correlated, so the
/// differences between variants are far less noisy than between independent renders
/// (docs/render.md, "Variants"). `variants` holds 1..kMaxRenderVariants entries, each as
/// `materials` of render(); with one variant this is render() bit for bit. Delta lobes (mirror)
/// are allowed: a delta sample carries only the variant that drew it. With several variants the
/// direct light is always estimated by MIS (RenderOptions::direct applies to one variant): the
/// shared light sample serves every variant.
std::vector<RenderImage> render_variants(
    const RenderScene& scene,
    const std::vector<std::vector<std::shared_ptr<const Svbrdf>>>& variants,
    const RenderLights& lights, const RenderOptions& options);

/// render_variants plus the first variant under further light sets ("light sets": e.g. a
/// measured BRDF and its fits under the courtyard map, and the measured BRDF also under the
/// studio map): the camera rays, the BRDF-sampled directions and every variant's throughput
/// are shared. The first set lights every variant as render_variants does; each further set
/// lights the first variant only, with its own light sample and shadow ray per bounce and its
/// own emission, weighted by the power heuristic against w_0 p_0 (the first variant's share of
/// the mixture that draws the directions; the two techniques' weights still sum to 1 wherever
/// either can draw, so the image is unbiased). Returns variants.size() images for the first
/// set, then one per further set (image variants.size() + l - 1 for set l). An extra set costs
/// a light sample, the first variant's BRDF value and a shadow ray per bounce, not a path.
/// 1..kMaxRenderLightSets sets; with several, environment maps and point lights only
/// (InputError for sphere or disk lights, on which a path would end in one set only) and MIS
/// for direct light. With one set this is render_variants bit for bit.
std::vector<RenderImage> render_light_sets(
    const RenderScene& scene,
    const std::vector<std::vector<std::shared_ptr<const Svbrdf>>>& variants,
    const std::vector<RenderLights>& light_sets, const RenderOptions& options);

/// Linear EXR (half floats, RGB) with the render settings in the header; atomic.
void write_render_exr(const RenderImage& img, const std::string& path);
/// Linear sRGB radiance (as the EXR, in full precision) as a NumPy float64 array of shape
/// (height, width, 3), row 0 at the top: for measurements on a render; atomic.
void write_render_npy(const RenderImage& img, const std::string& path);
/// The exposure (stops) that takes the `percentile` of the pixels' largest channel to 1 (Sun
/// 2002 scales each image to its maximum; 0.999 ignores a few fireflies); 0 for a black image.
double normalizing_exposure(const RenderImage& img, double percentile = 0.999);
/// Tone-mapped (exposure, then sRGB transfer, clipped) 8-bit PNG; atomic.
void write_render_png(const RenderImage& img, const std::string& path, double exposure_stops = 0);

}  // namespace microbrdf
