// voxcraft-viz history export (plastivox/render/history_file.hpp). The dialect, as
// voxcraft-viz's player reads it (src/VX1/VXS_SimGLView.cpp there):
//   - a line holding "{{{setting}}}" is followed by one XML element: <rescale>, <voxel_size>
//     or <matcolor><id/><r/><g/><b/><a/></matcolor> (colour channels in [0, 1]);
//   - a frame line is "<<<Step<k> Time:<t>>>>" (k the simulation step count, as voxcraft-sim
//     writes it; the player shows it as text), then per voxel 15 comma-separated numbers,
//     each voxel ending ",;": centre x, y, z; rotation angle (degrees) and axis x, y, z;
//     the local corners nnn x, y, z and ppp x, y, z (relative to the centre, before the
//     rotation); the material id (0..9, picks a <matcolor>); a scalar the viewer's
//     "electrical" mode colours with a jet map over [0, 100]; the line ends "<<<>>>".
// Lengths are multiplied by <rescale> on reading: written in millimetres with rescale
// 0.001, so four decimals keep 0.1 µm. Lines of any other form are skipped by the player.
// Frame: voxcraft-sim puts voxel centres of the bottom layer at z = 0 and its floor at
// z = -L/2, and the player draws the floor at -<voxel_size>/2; plastivox's floor is z = 0 with
// resting centres at L/2. So z is written as z - L/2: the robot stands on the drawn floor.
#include "plastivox/render/history_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/color_scale.hpp"

namespace plastivox::render {
namespace {

constexpr double kMillimetres = 1000;  // lengths written per metre

void append(std::string& out, const char* format, double a, double b, double c) {
  char buf[96];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  out += buf;
}

}  // namespace

std::string history_text(const Model& model, const Recording& recording) {
  std::vector<const Frame*> frames;
  for (const Frame& f : recording.frames) frames.push_back(&f);
  const ColorScale congenital = make_color_scale(ColorMode::kCongenital, model, frames);
  const ColorScale change = make_color_scale(ColorMode::kChange, model, frames);

  std::string out;
  char buf[256];
  std::snprintf(buf, sizeof buf, "{{{setting}}}<rescale>%g</rescale>\n", 1 / kMillimetres);
  out += buf;
  std::snprintf(buf, sizeof buf, "{{{setting}}}<voxel_size>%.17g</voxel_size>\n", model.size);
  out += buf;
  // Class k of kHistoryClasses covers t in [(k-1)/K, k/K) of the congenital map; its colour
  // is the map's at the class centre.
  for (int k = 1; k <= kHistoryClasses; ++k) {
    const Rgb8 c = congenital.map().at((k - 0.5) / kHistoryClasses);
    std::snprintf(buf, sizeof buf,
                  "{{{setting}}}<matcolor><id>%d</id><r>%.3f</r><g>%.3f</g><b>%.3f</b><a>1</a>"
                  "</matcolor>\n",
                  k, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
    out += buf;
  }
  std::vector<int> klass(model.n);
  for (int i = 0; i < model.n; ++i) {
    const double t = congenital.position(std::log10(model.e0[i]));
    klass[i] = std::clamp(1 + static_cast<int>(t * kHistoryClasses), 1, kHistoryClasses);
  }
  for (const Frame& f : recording.frames) {
    std::snprintf(buf, sizeof buf, "<<<Step%lld Time:%.6f>>>", static_cast<long long>(f.step),
                  f.time);
    out += buf;
    for (int i = 0; i < model.n; ++i) {
      const Eigen::Vector3d p = (f.pos[i] - Eigen::Vector3d(0, 0, 0.5 * model.size)) * kMillimetres;
      append(out, "%.4f,%.4f,%.4f,", p.x(), p.y(), p.z());
      // Angle and axis of the body-to-world rotation (no rotation: angle 0 about x).
      const Eigen::AngleAxisd aa(f.orient[i].normalized());
      const bool turned = aa.angle() != 0 && aa.axis().allFinite();
      const Eigen::Vector3d axis = turned ? aa.axis() : Eigen::Vector3d::UnitX();
      std::snprintf(buf, sizeof buf, "%.4f,", turned ? aa.angle() * 180 / M_PI : 0.0);
      out += buf;
      append(out, "%.6f,%.6f,%.6f,", axis.x(), axis.y(), axis.z());
      const double h = 0.5 * f.size[i] * kMillimetres;
      append(out, "%.4f,%.4f,%.4f,", -h, -h, -h);
      append(out, "%.4f,%.4f,%.4f,", h, h, h);
      // Stiffness change E/E0 on the change scale of the whole life, as 0..100.
      const double signal = 100 * change.position(change.value(model, f, i));
      std::snprintf(buf, sizeof buf, "%d,%.2f,;", klass[i], signal);
      out += buf;
    }
    out += "<<<>>>\n";
  }
  return out;
}

void write_history_file(const std::string& path, const Model& model, const Recording& recording) {
  write_file_atomic(path, history_text(model, recording));
}

}  // namespace plastivox::render
