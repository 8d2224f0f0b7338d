#pragma once

// What File > Export writes. Each returns an empty string on success, else a reason to show.

#include <QString>

#include "clearway/segmentation/params.h"
#include "clearway/ui/segmentation_session.h"

namespace clearway::ui {

class SceneView;

enum class ExportKind { kMapPng, kRosMap, kScenePly, kReportJson, kScreenshot3d };

QString exportResult(ExportKind kind, const SessionResult& result, const SegmentationParams& params,
                     const QString& path, SceneView* scene_view);

}  // namespace clearway::ui
