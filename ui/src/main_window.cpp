#include "clearway/ui/main_window.h"

#include <QFileInfo>
#include <QFutureWatcher>
#include <QLabel>
#include <QStatusBar>
#include <QtConcurrent/QtConcurrentRun>

#include "clearway/io/scan_io.h"
#include "clearway/scan_summary.h"

namespace clearway::ui {

namespace {

struct LoadResult {
  QString summary;
  QString error;
};

LoadResult loadSummary(const QString& path) {
  try {
    const Scan scan = loadScan(path.toStdString());
    return {QString::fromStdString(toText(summarise(scan))), {}};
  } catch (const std::exception& error) {
    return {{}, QString::fromUtf8(error.what())};
  }
}

}  // namespace

struct MainWindow::Private {
  QLabel* summary = nullptr;
  QFutureWatcher<LoadResult> load_watcher;
};

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), d_(std::make_unique<Private>()) {
  setWindowTitle(tr("Clearway"));
  d_->summary = new QLabel(tr("Open a scan to begin."), this);
  d_->summary->setObjectName("scanSummary");
  d_->summary->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  d_->summary->setTextInteractionFlags(Qt::TextSelectableByMouse);
  d_->summary->setMargin(12);
  setCentralWidget(d_->summary);
  resize(900, 600);
  connect(&d_->load_watcher, &QFutureWatcher<LoadResult>::finished, this, [this] {
    const LoadResult result = d_->load_watcher.result();
    if (!result.error.isEmpty()) {
      d_->summary->setText(tr("Could not load the scan:\n%1").arg(result.error));
      statusBar()->showMessage(tr("Load failed"));
    } else {
      d_->summary->setText(result.summary);
      statusBar()->showMessage(tr("Scan loaded"));
    }
  });
}

MainWindow::~MainWindow() {
  d_->load_watcher.waitForFinished();
}

void MainWindow::openScan(const QString& path) {
  statusBar()->showMessage(tr("Loading %1 …").arg(QFileInfo(path).fileName()));
  d_->load_watcher.setFuture(QtConcurrent::run(loadSummary, path));
}

}  // namespace clearway::ui
