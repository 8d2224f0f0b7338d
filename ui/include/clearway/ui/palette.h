#pragma once

// The console's colours for map cells. The default palette is colour-blind safe (checked under a
// simulated deuteranopia by a test) and keeps the paper's meaning: green drives, orange is careful,
// red is impassable; careful and obstacle cells are also hatched, so the meaning never rests on
// colour alone. The classic palette (core's labelColour, as in the PNG and PLY exports) is a
// setting.

#include <QColor>
#include <QImage>

#include "clearway/traversability/traversability_map.h"

namespace clearway::ui {

enum class PaletteKind { kColourBlindSafe, kClassic };

QColor cellColour(CellLabel label, PaletteKind palette);
// A cell's colour where the robot fits but cannot get: faded towards "not seen".
QColor dimmedColour(QColor colour, PaletteKind palette);

// Whether a cell of this label is hatched (careful: diagonal lines; obstacle: cross-hatch) at a
// given cell position. Hatching is drawn in cells, one line every kHatchPeriod cells.
bool cellHatched(CellLabel label, int column, int row);
inline constexpr int kHatchPeriod = 4;

// The map as an image, one pixel per cell (row 0 = top = largest map y), in the given palette with
// hatching. Cells with `dimmed` set (same indexing as the map's labels; may be empty) are drawn
// faded: free but out of the robot's reach.
QImage mapImage(const TraversabilityMap& map, PaletteKind palette,
                const std::vector<std::uint8_t>& reachable = {});

// Colour vision, for tests and the "simulate deuteranopia" screenshot: Machado, Oliveira and
// Fernandes (2009) severity-1.0 deuteranopia matrix applied in linear RGB.
QColor simulateDeuteranopia(QColor colour);
QImage simulateDeuteranopia(const QImage& image);
// CIE76 colour difference in CIELAB (D65).
double deltaE(QColor a, QColor b);

}  // namespace clearway::ui
