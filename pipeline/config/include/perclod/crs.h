// perclod/crs.h - a model's coordinate reference system, through PROJ: the
// `crs` setting and a CityJSON file's metadata.referenceSystem read as EPSG
// codes, checked, and the local frame that takes source coordinates to
// Earth-centred ones (EPSG:4978) for the 3D Tiles transform
// (docs/usage.md#export-for-viewers).
#pragma once

#include <array>
#include <string>

namespace perclod {

// "EPSG:7415" for the ways a CRS is written: "EPSG:7415" (any case), "7415",
// "urn:ogc:def:crs:EPSG::7415" (or with a version between the colons) and
// "http(s)://www.opengis.net/def/crs/EPSG/0/7415"; "" for anything else.
std::string epsg_code(const std::string& text);

// Throws std::invalid_argument saying what is wrong, naming the code, unless
// `code` is an EPSG code (epsg_code) of a CRS PROJ knows and can take to
// Earth-centred coordinates: a projected, compound (projected + vertical) or
// geocentric CRS. A geographic one is refused: degrees are no mesh
// coordinates. Results are remembered, so a batch checks each code once.
void check_crs(const std::string& code);

// A CRS's local frame at a point: its Earth-centred position and, per source
// axis, the Earth-centred metres one model unit along that axis moves (the
// derivative of PROJ's transformation there, so the projection's grid
// convergence and scale factor are in it); and what PROJ says of the
// transformations it used. The horizontal position takes the transformation
// PROJ ranks first for the CRS's horizontal part; a compound CRS's heights
// the one for the whole CRS (PROJ 9.1 without the geoid grid ranks a
// "ballpark geographic offset" first for the whole of some compound CRSs:
// about 110 m off for EPSG:7415).
struct CrsFrame {
  std::string code, name;                       // "EPSG:7415", "Amersfoort / RD New + NAP height"
  std::array<double, 3> origin{};               // ECEF (EPSG:4978) of the point, metres
  std::array<std::array<double, 3>, 3> axes{};  // axes[i]: ECEF metres per model unit along source axis i
  double lat = 0, lon = 0, height = 0;          // WGS84 (EPSG:4979): degrees, ellipsoidal metres
  std::string operation;                        // the name of PROJ's transformation of the position to WGS84
  double accuracy_m = -1;                       // its accuracy in metres (-1: unknown)
  bool ballpark = false;                        // it has a ballpark step (a datum shift left out)
  std::string height_operation;                 // a compound CRS's: the transformation of its heights
  // The heights are taken as WGS84 ellipsoidal heights as they are: a
  // compound CRS whose geoid model PROJ lacks (a ballpark vertical step), or
  // a CRS without heights of its own (a 2D projected one).
  bool height_ballpark = false;
  // "EGM96" when a compound CRS's geoid grid is missing and its heights
  // were taken as heights above the EGM96 geoid instead (Debian's proj-data
  // has that grid): the Delft tile's NAP heights are 43.5 m over the
  // ellipsoid there, not 0.
  std::string height_fallback;
};

// The frame of CRS `code` at `point`, in model units: source coordinates
// times `scale` (LoadOptions::scale). Throws std::invalid_argument as
// check_crs does, or when PROJ cannot transform the point.
CrsFrame crs_frame(const std::string& code, const std::array<double, 3>& point, double scale = 1.0);

}  // namespace perclod
