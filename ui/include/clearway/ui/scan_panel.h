#pragma once

// Scans to review: the open scan in words (the raw facts behind Details), Open, Previous/Next
// through the scans of its folder, and the recent scans (kept in QSettings).

#include <QStringList>
#include <QWidget>
#include <memory>

namespace clearway::ui {

class ScanPanel : public QWidget {
  Q_OBJECT

 public:
  explicit ScanPanel(QWidget* parent = nullptr);
  ~ScanPanel() override;

  // The scan now shown: remembered in the recent list; Previous/Next follow its folder.
  // `summary` is for people (a few lines); `details` (the key/value facts, stage timings) sits
  // behind the Details toggle.
  void setCurrent(const QString& path, const QString& summary, const QString& details = {});
  // No scan is shown (a failed or cancelled open).
  void clearCurrent();
  // `path` could not be opened (`reason`): no scan is shown, Previous/Next step from it (it is
  // where the operator stands in its folder), and it is not remembered as opened: in the recent
  // list it keeps its place, marked "could not be opened", until it opens again.
  void setFailed(const QString& path, const QString& reason);
  // Replaces the shown scan's summary alone (its age moves on), keeping the rest.
  void setSummary(const QString& summary);
  QStringList recentScans() const;
  // The scans Clearway can read in a folder, sorted by name.
  static QStringList scansInFolder(const QString& folder);
  static bool isScanFile(const QString& path);

 signals:
  void openRequested(const QString& path);
  void browseRequested();

 private:
  void step(int direction);
  void showRecent(const QStringList& recent);
  void followFolder();
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
