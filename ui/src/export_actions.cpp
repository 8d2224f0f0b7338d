#include "clearway/ui/export_actions.h"

#include <QSaveFile>

#include "clearway/ui/map_picture.h"

#include <QFileInfo>
#include <QImage>

#include "clearway/io/file_util.h"
#include "clearway/io/result_writer.h"
#include "clearway/ui/scene_view.h"

namespace clearway::ui {

QString exportExtension(ExportKind kind) {
  switch (kind) {
    case ExportKind::kRosMap:
      return ".pgm";
    case ExportKind::kScenePly:
      return ".ply";
    case ExportKind::kReportJson:
      return ".json";
    case ExportKind::kMapPng:
    case ExportKind::kScreenshot3d:
    case ExportKind::kMapPicture:
      break;
  }
  return ".png";
}

QString withExportExtension(const QString& path, ExportKind kind) {
  const QString extension = exportExtension(kind);
  return path.endsWith(extension, Qt::CaseInsensitive) ? path : path + extension;
}

QString exportResult(ExportKind kind, const SessionResult& result, const SegmentationParams& params,
                     const QString& path, SceneView* scene_view, const MapPictureOptions& picture) {
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
      case ExportKind::kMapPicture: {
        const QImage image = renderMapPicture(*result.result, picture.pixels_per_metre,
                                              picture.palette, picture.robot, picture.path);
        if (image.isNull())
          return QObject::tr(
                     "%1: a picture at %2 pixels per metre would be larger than %3 pixels "
                     "on a side; choose a smaller scale.")
              .arg(path)
              .arg(picture.pixels_per_metre)
              .arg(kMaxMapPictureSide);
        // Written to a temporary file and renamed: never a half-written picture.
        QSaveFile out(path);
        if (!out.open(QIODevice::WriteOnly) || !image.save(&out, "PNG") || !out.commit())
          return QObject::tr("Cannot write %1: %2").arg(path, out.errorString());
        break;
      }
    }
  } catch (const std::exception& error) {
    return QString::fromUtf8(error.what());
  }
  return {};
}

}  // namespace clearway::ui
