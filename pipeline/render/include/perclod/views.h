// perclod/views.h - view sets: where the eye stands for a viewing distance.
//
// A view is named:
//  * a facade, "+x" "-x" "+y" "-y" with Z up (+x -x +z -z with Y up): the eye
//    sits on the facade's outward axis through the bounding-box centre,
//    `distance` metres in front of the bounding-box face, looking at the centre
//    (docs/method.md section 1);
//  * "top": the same from above, `distance` metres over the box's top face;
//  * "az<A>el<E>" (degrees, e.g. az30el15): azimuth around the up axis from +x
//    (counter-clockwise seen from above), elevation above the horizon, the eye
//    `distance` metres outside the bounding sphere.
// Near and far planes are fitted to the bounding box.
//
// View sets (parse_views) name presets or views, comma separated:
//   facades        the four facades (the paper's set; "all" is the old name)
//   obliques       az45el0 az135el0 az225el0 az315el0 (between the facades)
//   top            the view from above
//   held_out       az22.5el15 az67.5el45 az112.5el15 ... az337.5el45 az0el75:
//                  the views `perclod run` judges LODs from (between the
//                  default labelling azimuths, 15 and 45 degrees up, and steep)
//   ring<N>        N azimuths (from 0, every 360/N degrees) at elevations 0, 30, 60
//   ring<N>el<E>[/<E>...]  the same at the elevations given, e.g. ring8el15/45
//   az<A>el<E>, +x, ...    single views
//
// A view that does not fit the model into its frame at a distance is tiled
// (frame_view): several eyes at the same distance, panned across the side, so
// every point of the bounding box is inside some tile's frustum.
#pragma once

#include <string>
#include <vector>

#include "perclod/camera.h"
#include "perclod/display.h"
#include "perclod/scene.h"

namespace perclod {

enum class UpAxis { Y, Z };
UpAxis parse_up_axis(const std::string& s);  // "y" or "z"

// A view set (see above) -> the view names, presets expanded, duplicates
// dropped, in order. Throws std::invalid_argument naming the bad item.
std::vector<std::string> parse_views(const std::string& spec, UpAxis up);
std::vector<std::string> parse_views(const std::vector<std::string>& items, UpAxis up);
// The old name: the same as parse_views.
inline std::vector<std::string> parse_facades(const std::string& spec, UpAxis up) { return parse_views(spec, up); }

// The view set `perclod run` labels from unless told otherwise
// (docs/usage.md#view-sets says how it was chosen).
constexpr const char* kDefaultViews = "facades,ring8el30,ring8el60,top";

// The farthest viewing distance, metres (100,000 km). Beyond it a building
// is far below a pixel on any display, and at much larger distances its size
// is lost in the precision of the eye's coordinates: the views fail with
// errors about the eye and the clip planes instead of about the distance.
constexpr double kMaxDistance = 1e8;
// "" when `distance` is a positive number of metres up to kMaxDistance, else
// what is wrong with it ("1e+300 m is farther than ...").
std::string distance_problem(double distance);

// A view name (see above) -> its camera at `distance`.
Camera view_camera(const Bounds& bounds, UpAxis up, const std::string& view, double distance,
                   const DisplayProfile& display);
// The old name: the same as view_camera.
Camera facade_camera(const Bounds& bounds, UpAxis up, const std::string& facade, double distance,
                     const DisplayProfile& display);
// Free view: azimuth around the up axis from +x (degrees, counter-clockwise seen
// from above), elevation above the horizon; distance from the bounding sphere.
Camera free_camera(const Bounds& bounds, UpAxis up, double azimuth_deg, double elevation_deg,
                   double distance, const DisplayProfile& display);

// Where the eye stands for a view: the model's up axis, the display it is
// seen on and the viewing distance (frame_view's arguments besides the view).
struct Framing {
  UpAxis up = UpAxis::Y;
  DisplayProfile display;
  double distance = 56;
};

// One tile of a framed view.
struct ViewTile {
  std::string name;  // the view's name, with "_t<i>" appended when it was tiled
  Camera camera;
};

// The view's camera when the whole box fits its frame; otherwise tiles: the
// same view direction, eyes panned along the camera's right and up axes so
// that every point of the box lies inside some tile's frustum (each tile's
// frame covers its share of the box at the box's nearest depth). Throws
// std::invalid_argument when more than `max_tiles` would be needed.
std::vector<ViewTile> frame_view(const Bounds& bounds, UpAxis up, const std::string& view, double distance,
                                 const DisplayProfile& display, int max_tiles = 4096);

// p(d) on this display: the footprint in metres of one pixel at eye depth
// `distance` (Camera::pixel_footprint of any view rendered for it).
double display_pixel_footprint(const DisplayProfile& display, double distance);

// Near/far fitted to the box as seen by `cam` (near stays positive).
void fit_clip_planes(Camera& cam, const Bounds& bounds);
// The near plane fit_clip_planes puts before `bounds`, as an eye depth of
// `cam` before the clamps that keep it in front of the eye: the same plane
// for every eye looking along cam.forward.
double box_near_depth(const Camera& cam, const Bounds& bounds);

// Frames each of `views` at every distance (frame_view) around `bounds`, so
// a view that cannot be framed (too many tiles) fails before any rendering
// starts.
void check_framing(const Bounds& bounds, UpAxis up, const DisplayProfile& display, const std::vector<std::string>& views,
                   const std::vector<double>& distances);

}  // namespace perclod
