// perclod perceive IMAGE: the vision simulation of one rendered image
// (CDF 9/7 DWT + CSF, docs/method.md section 3): simulated image, visual
// difference, mask of imperceptible pixels and a JSON summary.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "commands.h"
#include "common.h"
#include "perclod/image_io.h"
#include "perclod/outputs.h"
#include "perclod/perception.h"

namespace perclod::cli {
namespace {

PerceptionSettings::CsfMode parse_csf(const std::string& s) {
  if (s == "fir") return PerceptionSettings::CsfMode::Fir;
  if (s == "weights") return PerceptionSettings::CsfMode::Weights;
  if (s == "kakadu") return PerceptionSettings::CsfMode::Kakadu;
  throw OptionError("--csf must be fir, weights or kakadu, got '" + s + "'");
}

PerceptionSettings::Luminance parse_luminance(const std::string& s) {
  if (s == "luma") return PerceptionSettings::Luminance::Luma;
  if (s == "linear") return PerceptionSettings::Luminance::LinearY;
  throw OptionError("--luminance must be luma or linear, got '" + s + "'");
}

// "R,G,B" with 0..255 components.
std::vector<int> parse_rgb(const std::string& s) {
  std::vector<int> c;
  std::stringstream ss(s);
  std::string part;
  while (std::getline(ss, part, ',')) {
    size_t used = 0;
    int v = -1;
    try {
      v = std::stoi(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != part.size() || v < 0 || v > 255)
      throw OptionError("--background must be R,G,B with 0..255 components, got '" + s + "'");
    c.push_back(v);
  }
  if (c.size() != 3) throw OptionError("--background must be R,G,B, got '" + s + "'");
  return c;
}

std::vector<uint8_t> background_of(const Rgb8Image& img, const std::vector<int>& rgb) {
  std::vector<uint8_t> bg(size_t(img.width) * img.height);
  for (size_t i = 0; i < bg.size(); ++i)
    bg[i] = img.pixels[3 * i] == rgb[0] && img.pixels[3 * i + 1] == rgb[1] && img.pixels[3 * i + 2] == rgb[2];
  return bg;
}

const char* name_of(BandOrientation o) {
  return o == BandOrientation::HL ? "HL" : o == BandOrientation::LH ? "LH" : "HH";
}

const char* name_of(PerceptionSettings::CsfMode m) {
  return m == PerceptionSettings::CsfMode::Fir ? "fir" : m == PerceptionSettings::CsfMode::Weights ? "weights" : "kakadu";
}

nlohmann::json summary(const PerceptionResult& r, const PerceptionSettings& s, const std::string& image) {
  nlohmann::json bands = nlohmann::json::array();
  for (const BandResponse& b : r.bands) {
    nlohmann::json j = {{"level", b.level},
                        {"orientation", name_of(b.orientation)},
                        {"f_low_cpd", b.f_low},
                        {"f_high_cpd", b.f_high},
                        {"csf_low", b.target_low},
                        {"csf_high", b.target_high},
                        {"response_low", b.response_low},
                        {"response_high", b.response_high},
                        {"response_centre", b.weight}};
    if (!b.taps.empty()) j["taps"] = b.taps;
    bands.push_back(j);
  }
  return {{"image", image},
          {"width", r.width},
          {"height", r.height},
          {"ppd", r.ppd},
          {"f_max_cpd", r.f_max},
          {"levels", r.levels},
          {"csf", name_of(s.csf)},
          {"k", s.k},
          {"luminance", s.luminance == PerceptionSettings::Luminance::Luma ? "luma" : "linear"},
          {"threshold", s.threshold},
          {"bands", bands},
          {"counted_pixels", r.counted_pixels},
          {"imperceptible_fraction", r.imperceptible_fraction},
          {"seconds", r.seconds}};
}

}  // namespace

void register_perceive(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "perceive",
      "Vision simulation of a rendered image: CDF 9/7 wavelet, contrast sensitivity per band, and the\n"
      "visual difference (original minus simulated). Pixels whose |difference| exceeds the threshold\n"
      "carry detail the viewer cannot see at this display: 'imperceptible'.");
  struct Args {
    PerceptionSettings settings;  // the library's defaults, overridden by the options below
    std::string image, out = "out", csf = name_of(settings.csf), background;
    std::string luminance = settings.luminance == PerceptionSettings::Luminance::Luma ? "luma" : "linear";
    DisplayArgs display;
    double ppd = 0;
    bool raw = false, json = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("IMAGE", a->image, "Rendered image (PNG or anything OpenImageIO reads)")
      ->required()
      ->check(kNotEmpty);
  a->display.add(cmd);
  auto* ppd_opt = cmd->add_option("--ppd", a->ppd, "Pixels per degree instead of a display profile (paper: 29.64)")
      ->excludes(cmd->get_option("--display"));
  cmd->add_option("--csf", a->csf, "CSF mode: fir (default; FIR per band), weights (one per band), kakadu (Nadenau's table)");
  cmd->add_option("--csf-k", a->settings.k, "CSF constant k in A(f) = 2.6 (0.0192 + k f) exp(-(k f)^1.1); Mannos-Sakrison: 0.114")
      ->capture_default_str();
  cmd->add_option("--levels", a->settings.levels, "DWT levels; 0 = fewest that put the LL band under the CSF peak")
      ->capture_default_str();
  cmd->add_option("--threshold", a->settings.threshold, "Grey levels: |difference| above it is imperceptible")
      ->capture_default_str();
  cmd->add_option("--luminance", a->luminance, "luma (encoded Rec.601 luma, default) or linear (CIE Y of linear sRGB)");
  cmd->add_option("--background", a->background, "R,G,B of the background: such pixels are left out of the fraction");
  cmd->add_option("--out,-o", a->out, "Output directory (created)")->check(kNotEmpty);
  cmd->add_flag("--raw", a->raw, "Also write the float difference as <stem>_difference.tif");
  cmd->add_flag("--json", a->json, "Print the JSON summary on stdout");
  cmd->footer(
      "Files: OUT/<stem>_simulated.png (grey), <stem>_difference.png (black = perceptible, grey = imperceptible\n"
      "detail, 64 + 4|d|), <stem>_mask.png (255 = imperceptible), <stem>_perception.json, and with --raw\n"
      "<stem>_difference.tif (32-bit float, signed grey levels).");
  cmd->callback([a, ppd_opt] {
    set_error_files({a->image});
    require_file(a->image);
    if (ppd_opt->count() && !(a->ppd > 0 && std::isfinite(a->ppd)))
      throw OptionError("--ppd must be a positive number of pixels per degree");
    PerceptionSettings s = a->settings;
    s.ppd = ppd_opt->count() ? a->ppd : a->display.profile().pixels_per_degree();
    s.csf = parse_csf(a->csf);
    s.luminance = parse_luminance(a->luminance);
    Rgb8Image img = read_rgb8(a->image);
    std::vector<uint8_t> bg;
    if (!a->background.empty()) bg = background_of(img, parse_rgb(a->background));
    PerceptionResult r = perceive(img.pixels.data(), img.width, img.height, s, bg.empty() ? nullptr : bg.data());

    ensure_directory(a->out);
    const OutputNames out = output_names_for(a->out, a->image);
    write_png(out.file("_simulated.png"), r.width, r.height, 1, simulated_view(r).data());
    write_png(out.file("_difference.png"), r.width, r.height, 1, difference_view(r).data());
    write_png(out.file("_mask.png"), r.width, r.height, 1, mask_view(r).data());
    if (a->raw) write_tiff_float(out.file("_difference.tif"), r.width, r.height, 1, r.difference.data());
    nlohmann::json j = summary(r, s, a->image);
    write_text_atomic(out.file("_perception.json"), j.dump(2) + "\n");
    std::fprintf(stderr, "%s: %dx%d, %.2f ppd, %d levels, %.1f%% imperceptible, %.1f ms -> %s_*.png\n",
                 a->image.c_str(), r.width, r.height, r.ppd, r.levels, 100.0 * r.imperceptible_fraction,
                 r.seconds * 1e3, out.file("").c_str());
    if (a->json) print_json(j);
  });
}

}  // namespace perclod::cli
