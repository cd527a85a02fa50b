// perclod/views.h - facade views: where the eye stands for a viewing distance.
//
// The eye sits on a facade's outward axis through the bounding-box centre,
// `distance` metres in front of the bounding-box face, looking at the centre
// (docs/method.md section 1). Facades are named by the source file's axes: with Z
// up they are +x -x +y -y, with Y up +x -x +z -z. Near and far planes are
// fitted to the bounding box.
#pragma once

#include <string>
#include <vector>

#include "perclod/camera.h"
#include "perclod/display.h"
#include "perclod/scene.h"

namespace perclod {

enum class UpAxis { Y, Z };
UpAxis parse_up_axis(const std::string& s);  // "y" or "z"

// "all" -> the four facades; otherwise a comma list of facade names or free
// views "az<A>el<E>" (degrees, e.g. az30el15). Throws on a bad name.
std::vector<std::string> parse_facades(const std::string& spec, UpAxis up);

// A facade name ("+x") or a free view name ("az30el15", see free_camera).
Camera facade_camera(const Bounds& bounds, UpAxis up, const std::string& facade, double distance,
                     const DisplayProfile& display);
// Free view: azimuth around the up axis from +x (degrees, counter-clockwise seen
// from above), elevation above the horizon; distance from the bounding sphere.
Camera free_camera(const Bounds& bounds, UpAxis up, double azimuth_deg, double elevation_deg,
                   double distance, const DisplayProfile& display);

// p(d) on this display: the footprint in metres of one pixel at eye depth
// `distance` (Camera::pixel_footprint of any view rendered for it).
double display_pixel_footprint(const DisplayProfile& display, double distance);

// Near/far fitted to the box as seen by `cam` (near stays positive).
void fit_clip_planes(Camera& cam, const Bounds& bounds);

}  // namespace perclod
