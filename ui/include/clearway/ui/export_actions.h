#pragma once

// What File > Export writes. Each returns an empty string on success, else a reason to show.

#include <QString>

#include "clearway/segmentation/params.h"
#include "clearway/ui/map_drawing.h"
#include "clearway/ui/palette.h"
#include "clearway/ui/segmentation_session.h"

namespace clearway::ui {

class SceneView;

// kMapPng is the map's data, one pixel per cell in the classic colours (for tools); kMapPicture
// is the map for people: a chosen scale, legend, scale bar, robot and north arrow.
enum class ExportKind { kMapPng, kRosMap, kScenePly, kReportJson, kScreenshot3d, kMapPicture };

// The file extension (with the dot) each export writes, and `path` with it added when missing.
QString exportExtension(ExportKind kind);
QString withExportExtension(const QString& path, ExportKind kind);

// What the map picture shows besides the cells.
struct MapPictureOptions {
  double pixels_per_metre = 40.0;
  PaletteKind palette = PaletteKind::kColourBlindSafe;
  PathPose robot;
  std::vector<PathPose> path;
};

QString exportResult(ExportKind kind, const SessionResult& result, const SegmentationParams& params,
                     const QString& path, SceneView* scene_view,
                     const MapPictureOptions& picture = {});

}  // namespace clearway::ui
