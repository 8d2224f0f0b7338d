#include "clearway/ui/scan_panel.h"

#include <QDir>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHash>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QSettings>
#include <QToolButton>
#include <QVBoxLayout>

#include "clearway/io/scan_io.h"

namespace clearway::ui {
namespace {

constexpr int kRecentScans = 10;
const char* const kRecentKey = "scans/recent";
const QStringList kScanPatterns = {"*.pcd", "*.ply", "*.xyz", "*.txt",
                                   "*.dat", "*.asc", "*.bin", "*.3d"};

}  // namespace

struct ScanPanel::Private {
  QLabel* info = nullptr;
  QToolButton* show_details = nullptr;
  QLabel* details = nullptr;
  QListWidget* recent = nullptr;
  QPushButton* previous = nullptr;
  QPushButton* next = nullptr;
  // Where Previous/Next step from: the scan shown, or the file that last failed to open.
  QString current;
  // Files that failed to open since, with why: marked in the recent list until they open.
  QHash<QString, QString> failed;
};

ScanPanel::ScanPanel(QWidget* parent) : QWidget(parent), d_(std::make_unique<Private>()) {
  setObjectName("scanPanel");
  auto* layout = new QVBoxLayout(this);
  auto* buttons = new QHBoxLayout;
  auto* open = new QPushButton(tr("Open..."), this);
  open->setObjectName("openScanButton");
  d_->previous = new QPushButton(tr("< Previous"), this);
  d_->previous->setObjectName("previousScanButton");
  d_->next = new QPushButton(tr("Next >"), this);
  d_->next->setObjectName("nextScanButton");
  buttons->addWidget(open);
  buttons->addWidget(d_->previous);
  buttons->addWidget(d_->next);
  layout->addLayout(buttons);
  d_->info = new QLabel(tr("Open a scan, or drop one on the window."), this);
  d_->info->setObjectName("scanInfo");
  d_->info->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  d_->info->setTextInteractionFlags(Qt::TextSelectableByMouse);
  d_->info->setWordWrap(true);
  layout->addWidget(d_->info);
  d_->show_details = new QToolButton(this);
  d_->show_details->setObjectName("scanDetailsToggle");
  d_->show_details->setText(tr("Details"));
  d_->show_details->setCheckable(true);
  d_->show_details->setEnabled(false);
  layout->addWidget(d_->show_details);
  d_->details = new QLabel(this);
  d_->details->setObjectName("scanDetails");
  d_->details->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  d_->details->setTextInteractionFlags(Qt::TextSelectableByMouse);
  d_->details->setWordWrap(true);
  d_->details->hide();
  layout->addWidget(d_->details, 1);
  connect(d_->show_details, &QToolButton::toggled, d_->details, &QWidget::setVisible);
  layout->addWidget(new QLabel(tr("Recent scans"), this));
  d_->recent = new QListWidget(this);
  d_->recent->setObjectName("recentScans");
  showRecent(QSettings().value(kRecentKey).toStringList());
  layout->addWidget(d_->recent);
  d_->previous->setEnabled(false);
  d_->next->setEnabled(false);

  connect(open, &QPushButton::clicked, this, &ScanPanel::browseRequested);
  connect(d_->previous, &QPushButton::clicked, this, [this] { step(-1); });
  connect(d_->next, &QPushButton::clicked, this, [this] { step(+1); });
  connect(d_->recent, &QListWidget::itemActivated, this, [this](QListWidgetItem* item) {
    emit openRequested(item->data(Qt::UserRole).toString());
  });
}

ScanPanel::~ScanPanel() = default;

bool ScanPanel::isScanFile(const QString& path) {
  return QDir::match(kScanPatterns, QFileInfo(path).fileName().toLower());
}

QStringList ScanPanel::scansInFolder(const QString& folder) {
  QStringList scans;
  for (const QFileInfo& info : QDir(folder).entryInfoList(kScanPatterns, QDir::Files, QDir::Name))
    if (looksLikeScanFile(info.absoluteFilePath().toStdString()))  // not a README.txt
      scans << info.absoluteFilePath();
  return scans;
}

void ScanPanel::setSummary(const QString& summary) {
  d_->info->setText(summary);
}

void ScanPanel::clearCurrent() {
  d_->info->setText(tr("No scan shown. Open a scan, or drop one on the window."));
  d_->details->clear();
  d_->show_details->setChecked(false);
  d_->show_details->setEnabled(false);
}

void ScanPanel::setCurrent(const QString& path, const QString& summary, const QString& details) {
  d_->current = QFileInfo(path).absoluteFilePath();
  d_->failed.remove(d_->current);
  d_->info->setText(summary);
  d_->details->setText(details);
  d_->show_details->setEnabled(!details.isEmpty());
  QStringList recent = QSettings().value(kRecentKey).toStringList();
  recent.removeAll(d_->current);
  recent.prepend(d_->current);
  while (recent.size() > kRecentScans)
    recent.removeLast();
  QSettings().setValue(kRecentKey, recent);
  showRecent(recent);
  followFolder();
}

void ScanPanel::setFailed(const QString& path, const QString& reason) {
  // Previous/Next went on from the scan shown before: Next opened this file again and again.
  d_->current = QFileInfo(path).absoluteFilePath();
  d_->failed.insert(d_->current, reason);
  clearCurrent();
  d_->info->setText(tr("<b>%1</b> could not be opened: %2<br>No scan is shown.")
                        .arg(QFileInfo(path).fileName().toHtmlEscaped(), reason.toHtmlEscaped()));
  showRecent(QSettings().value(kRecentKey).toStringList());
  followFolder();
}

void ScanPanel::showRecent(const QStringList& recent) {
  d_->recent->clear();
  for (const QString& path : recent) {
    auto* item = new QListWidgetItem(path, d_->recent);
    item->setData(Qt::UserRole, path);
    if (const auto failed = d_->failed.constFind(path); failed != d_->failed.constEnd()) {
      item->setText(tr("%1 — could not be opened").arg(path));
      item->setToolTip(*failed);
    }
  }
}

void ScanPanel::followFolder() {
  const QStringList scans = scansInFolder(QFileInfo(d_->current).absolutePath());
  const int index = int(scans.indexOf(d_->current));
  d_->previous->setEnabled(index > 0);
  d_->next->setEnabled(index >= 0 && index + 1 < scans.size());
}

QStringList ScanPanel::recentScans() const {
  return QSettings().value(kRecentKey).toStringList();
}

void ScanPanel::step(int direction) {
  const QStringList scans = scansInFolder(QFileInfo(d_->current).absolutePath());
  const int index = int(scans.indexOf(d_->current)) + direction;
  if (index >= 0 && index < scans.size()) emit openRequested(scans[index]);
}

}  // namespace clearway::ui
