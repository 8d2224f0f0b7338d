#include "clearway/ui/palette.h"

#include <array>
#include <cmath>

#include "clearway/scene/scene_geometry.h"

namespace clearway::ui {
namespace {

// Chosen so that every pair of the five main classes stays at least ΔE 29 apart under simulated
// deuteranopia (the classic green and red are 12 apart): Okabe-Ito's bluish green for
// traversable, a warm yellow-orange for careful, a brown-orange for obstacle, a dark red for
// impassable, dark grey for unobserved.
QColor safeColour(CellLabel label) {
  switch (label) {
    case CellLabel::kTraversable:
      return {0, 158, 115};
    case CellLabel::kCareful:
      return {255, 176, 0};
    case CellLabel::kObstacle:
      return {190, 120, 20};
    case CellLabel::kImpassable:
      return {140, 20, 20};
    case CellLabel::kStairs:
      return {204, 121, 167};
    case CellLabel::kUnknown:
      break;
  }
  return {60, 60, 60};
}

// Hatch lines darken the cell colour by this factor (QColor::darker percentage).
constexpr int kHatchDarkerPercent = 160;
// Cells out of reach are blended this far towards the unobserved grey.
constexpr double kDimmedWeight = 0.55;

double toLinear(double channel) {
  const double c = channel / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

int fromLinear(double c) {
  c = std::clamp(c, 0.0, 1.0);
  const double encoded = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return int(std::lround(255.0 * encoded));
}

std::array<double, 3> toLab(QColor colour) {
  const double r = toLinear(colour.red()), g = toLinear(colour.green()),
               b = toLinear(colour.blue());
  const double x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
  const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
  auto f = [](double t) { return t > 0.008856 ? std::cbrt(t) : 7.787 * t + 16.0 / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

}  // namespace

QColor cellColour(CellLabel label, PaletteKind palette) {
  if (palette == PaletteKind::kClassic) {
    const auto rgb = labelColour(label);
    return {rgb[0], rgb[1], rgb[2]};
  }
  return safeColour(label);
}

QColor dimmedColour(QColor colour, PaletteKind palette) {
  const QColor unknown = cellColour(CellLabel::kUnknown, palette);
  return QColor::fromRgbF(colour.redF() * (1 - kDimmedWeight) + unknown.redF() * kDimmedWeight,
                          colour.greenF() * (1 - kDimmedWeight) + unknown.greenF() * kDimmedWeight,
                          colour.blueF() * (1 - kDimmedWeight) + unknown.blueF() * kDimmedWeight);
}

bool cellHatched(CellLabel label, int column, int row) {
  const auto on = [](int value) {
    return ((value % kHatchPeriod) + kHatchPeriod) % kHatchPeriod == 0;
  };
  if (label == CellLabel::kCareful) return on(column + row);
  if (label == CellLabel::kObstacle) return on(column + row) || on(column - row);
  return false;
}

QImage mapImage(const TraversabilityMap& map, PaletteKind palette,
                const std::vector<std::uint8_t>& reachable) {
  QImage image(std::max(map.grid.width, 1), std::max(map.grid.height, 1), QImage::Format_RGB32);
  const QColor unknown = cellColour(CellLabel::kUnknown, palette);
  image.fill(unknown);
  const bool has_reach = reachable.size() == map.labels.size();
  for (int row = 0; row < map.grid.height; ++row)
    for (int column = 0; column < map.grid.width; ++column) {
      const CellLabel label = map.label(column, row);
      QColor colour = cellColour(label, palette);
      if (cellHatched(label, column, row)) colour = colour.darker(kHatchDarkerPercent);
      // Every cell the box fits on is dimmed where the robot cannot get: orange ones too (a
      // low obstacle, sparse ground), or the operator reads bright orange as a way to go.
      if (has_reach && robotFits(label) && !reachable[map.grid.index(column, row)])
        colour = dimmedColour(colour, palette);
      image.setPixel(column, map.grid.height - 1 - row, colour.rgb());
    }
  return image;
}

QColor simulateDeuteranopia(QColor colour) {
  // Machado et al. 2009, deuteranopia, severity 1.0.
  static constexpr double kMatrix[3][3] = {{0.367322, 0.860646, -0.227968},
                                           {0.280085, 0.672501, 0.047413},
                                           {-0.011820, 0.042940, 0.968881}};
  const double in[3] = {toLinear(colour.red()), toLinear(colour.green()), toLinear(colour.blue())};
  int out[3];
  for (int i = 0; i < 3; ++i)
    out[i] = fromLinear(kMatrix[i][0] * in[0] + kMatrix[i][1] * in[1] + kMatrix[i][2] * in[2]);
  return {out[0], out[1], out[2]};
}

QImage simulateDeuteranopia(const QImage& image) {
  QImage out = image.convertToFormat(QImage::Format_RGB32);
  for (int y = 0; y < out.height(); ++y) {
    auto* line = reinterpret_cast<QRgb*>(out.scanLine(y));
    for (int x = 0; x < out.width(); ++x)
      line[x] = simulateDeuteranopia(QColor(line[x])).rgb();
  }
  return out;
}

double deltaE(QColor a, QColor b) {
  const auto la = toLab(a), lb = toLab(b);
  return std::sqrt((la[0] - lb[0]) * (la[0] - lb[0]) + (la[1] - lb[1]) * (la[1] - lb[1]) +
                   (la[2] - lb[2]) * (la[2] - lb[2]));
}

}  // namespace clearway::ui
