#pragma once

// The map as a picture for a report: the cells at a chosen scale with the legend, a scale bar, the
// robot with its heading, the path if there is one, and a north arrow (map +y).

#include <QImage>
#include <vector>

#include "clearway/pipeline.h"
#include "clearway/ui/map_drawing.h"
#include "clearway/ui/palette.h"

namespace clearway::ui {

// The largest picture side we write, so a fine scale on a large map cannot exhaust memory [px].
inline constexpr int kMaxMapPictureSide = 8000;

// Null when the picture would be larger than kMaxMapPictureSide on a side.
QImage renderMapPicture(const PipelineResult& result, double pixels_per_metre, PaletteKind palette,
                        const PathPose& robot, const std::vector<PathPose>& path = {});

}  // namespace clearway::ui
