#include "clearway/ui/export_actions.h"

#include <QFileInfo>
#include <QImage>

#include "clearway/io/file_util.h"
#include "clearway/io/result_writer.h"
#include "clearway/ui/scene_view.h"

namespace clearway::ui {

QString exportResult(ExportKind kind, const SessionResult& result, const SegmentationParams& params,
                     const QString& path, SceneView* scene_view) {
  if (!result.result) return QObject::tr("There is no result to export yet.");
  const std::filesystem::path file = path.toStdString();
  try {
    switch (kind) {
      case ExportKind::kMapPng:
        writeTraversabilityPng(result.result->map, file);
        break;
      case ExportKind::kRosMap:
        writeRosMap(result.result->map, file);
        break;
      case ExportKind::kScenePly:
        writeScenePly(result.result->scene, file);
        break;
      case ExportKind::kReportJson:
        writeTextFileAtomically(file,
                                reportJson(*result.result, params,
                                           QFileInfo(result.scan_path).fileName().toStdString()));
        break;
      case ExportKind::kScreenshot3d: {
        const QImage image = scene_view ? scene_view->renderedImage() : QImage();
        if (image.isNull()) return QObject::tr("The 3D view is not available on this display.");
        if (!image.save(path)) return QObject::tr("Cannot write %1.").arg(path);
        break;
      }
    }
  } catch (const std::exception& error) {
    return QString::fromUtf8(error.what());
  }
  return {};
}

}  // namespace clearway::ui
