#include "clearway/ui/hardware_panel.h"

#include <QComboBox>
#include <QDateTime>
#include <QDir>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QStandardPaths>

#include "clearway/hardware/serial_rosi.h"
#include "clearway/hardware/simulated_rosi.h"
#include "clearway/io/scan_io.h"
#include "clearway/sim/builtin_scenes.h"
#include "remote_scanner_fields.h"

namespace clearway::ui {

using hardware::ScannerDevice;

namespace {
constexpr int kRemoteDevice = 2;  // the third device choice
}

struct HardwarePanel::Private {
  QComboBox* device = nullptr;
  QComboBox* scene = nullptr;
  QSpinBox* lines = nullptr;
  QPushButton* connect = nullptr;
  QPushButton* scan = nullptr;
  QPushButton* cancel = nullptr;
  QLabel* status = nullptr;
  QProgressBar* progress = nullptr;
  QLineEdit* lms_port = nullptr;
  QLineEdit* turntable_port = nullptr;
  QComboBox* link_speed = nullptr;
  RemoteScannerFields* remote = nullptr;
  std::unique_ptr<ScannerDevice> scanner;
  QString folder;
  double speedup = 8.0;
};

HardwarePanel::HardwarePanel(QWidget* parent) : QWidget(parent), d_(std::make_unique<Private>()) {
  setObjectName("hardwarePanel");
  d_->folder =
      QDir(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)).filePath("scans");
  auto* form = new QFormLayout(this);
  d_->device = new QComboBox(this);
  d_->device->setObjectName("scannerDevice");
  d_->device->addItem(tr("Simulated RoSi"));
  d_->device->addItem(tr("Serial RoSi (LMS200 + turntable)"));
  d_->device->addItem(tr("Remote RoSi (clearway-cli serve on the robot)"));
  form->addRow(tr("Device"), d_->device);
  d_->remote = new RemoteScannerFields(this);
  d_->remote->setVisible(false);
  form->addRow(d_->remote);
  connect(d_->device, qOverload<int>(&QComboBox::currentIndexChanged), d_->remote,
          [this](int index) { d_->remote->setVisible(index == kRemoteDevice); });
  d_->lms_port = new QLineEdit("/dev/ttyUSB0", this);
  d_->lms_port->setObjectName("lmsPort");
  d_->turntable_port = new QLineEdit("/dev/ttyUSB1", this);
  d_->turntable_port->setObjectName("turntablePort");
  form->addRow(tr("Laser port"), d_->lms_port);
  form->addRow(tr("Turntable port"), d_->turntable_port);
  d_->link_speed = new QComboBox(this);
  d_->link_speed->setObjectName("linkSpeed");
  for (const int baud : {9600, 19200, 38400, 500000})
    d_->link_speed->addItem(tr("%1 baud").arg(baud), baud);
  d_->link_speed->setCurrentIndex(d_->link_speed->findData(38400));
  d_->link_speed->setToolTip(
      tr("The laser starts at 9600 baud and is switched to this speed; 500 kbaud needs an RS-422 "
         "adapter that supports it"));
  form->addRow(tr("Laser link"), d_->link_speed);
  d_->scene = new QComboBox(this);
  d_->scene->setObjectName("simulatedScene");
  for (const std::string& name : sim::builtinSceneNames())
    d_->scene->addItem(QString::fromStdString(name));
  d_->scene->setCurrentText("garage");
  form->addRow(tr("Scene"), d_->scene);
  d_->lines = new QSpinBox(this);
  d_->lines->setObjectName("scanLines");
  d_->lines->setRange(20, 4000);
  d_->lines->setValue(300);
  d_->lines->setToolTip(tr("Lines per revolution (the LMS200 gives 37.5 lines per second)"));
  form->addRow(tr("Lines"), d_->lines);
  auto* buttons = new QHBoxLayout;
  d_->connect = new QPushButton(tr("Connect"), this);
  d_->connect->setObjectName("connectButton");
  d_->scan = new QPushButton(tr("Scan"), this);
  d_->scan->setObjectName("scanButton");
  d_->cancel = new QPushButton(tr("Cancel"), this);
  d_->cancel->setObjectName("cancelScanButton");
  buttons->addWidget(d_->connect);
  buttons->addWidget(d_->scan);
  buttons->addWidget(d_->cancel);
  form->addRow(buttons);
  d_->progress = new QProgressBar(this);
  d_->progress->setObjectName("scanProgress");
  form->addRow(d_->progress);
  d_->status = new QLabel(tr("Not connected."), this);
  d_->status->setObjectName("scannerStatus");
  d_->status->setWordWrap(true);
  form->addRow(d_->status);
  d_->scan->setEnabled(false);
  d_->cancel->setEnabled(false);

  connect(d_->connect, &QPushButton::clicked, this, &HardwarePanel::connectScanner);
  connect(d_->scan, &QPushButton::clicked, this, &HardwarePanel::startScan);
  connect(d_->cancel, &QPushButton::clicked, this, &HardwarePanel::cancelScan);
  connect(this, &HardwarePanel::statusChanged, d_->status, &QLabel::setText);
}

HardwarePanel::~HardwarePanel() = default;

void HardwarePanel::setScanFolder(const QString& folder) {
  d_->folder = folder;
}
QString HardwarePanel::scanFolder() const {
  return d_->folder;
}
void HardwarePanel::setSpeedup(double speedup) {
  d_->speedup = speedup;
  if (auto* simulated = dynamic_cast<hardware::SimulatedRosi*>(d_->scanner.get()))
    simulated->setSpeedup(speedup);
}

void HardwarePanel::connectScanner() {
  if (d_->device->currentIndex() == kRemoteDevice) {
    QString problem;
    std::unique_ptr<ScannerDevice> remote = d_->remote->createDevice(&problem);
    if (!remote) {
      emit statusChanged(problem);
      return;
    }
    d_->scanner = std::move(remote);
  } else if (d_->device->currentIndex() == 1) {
    d_->scanner = std::make_unique<hardware::SerialRosi>(
        d_->lms_port->text(), d_->turntable_port->text(), d_->link_speed->currentData().toInt());
  } else {
    auto simulated = std::make_unique<hardware::SimulatedRosi>(
        *sim::builtinScene(d_->scene->currentText().toStdString()));
    simulated->setSpeedup(d_->speedup);
    d_->scanner = std::move(simulated);
  }
  ScannerDevice* device = d_->scanner.get();
  connect(device, &ScannerDevice::stateChanged, this, [this, device](ScannerDevice::State state) {
    d_->scan->setEnabled(state == ScannerDevice::State::kIdle);
    d_->cancel->setEnabled(state == ScannerDevice::State::kScanning);
    emit statusChanged(tr("%1: %2.").arg(device->description(), ScannerDevice::stateName(state)));
  });
  connect(device, &ScannerDevice::linesArrived, this, &HardwarePanel::linesArrived);
  connect(device, &ScannerDevice::progress, this, [this](int received, int expected) {
    d_->progress->setMaximum(expected);
    d_->progress->setValue(received);
  });
  connect(device, &ScannerDevice::failed, this,
          [this](const QString& reason) { emit statusChanged(reason); });
  connect(
      device, &ScannerDevice::scanFinished, this,
      [this](std::shared_ptr<const Scan> scan, bool complete) {
        // Save first: nothing the operator acquired is lost, whatever happens next.
        QDir().mkpath(d_->folder);
        const QString name = "rosi-" +
                             QDateTime::currentDateTime().toString("yyyyMMdd-hhmmss-zzz") +
                             (complete ? "" : "-partial") + ".pcd";
        const QString path = QDir(d_->folder).filePath(name);
        if (scan->empty()) {
          emit statusChanged(
              tr("The scan was cancelled before any line arrived; nothing to keep."));
          return;
        }
        try {
          saveRosiPcd(*scan, path.toStdString());
        } catch (const std::exception& error) {
          emit statusChanged(
              tr("The scan could not be saved: %1").arg(QString::fromUtf8(error.what())));
          return;
        }
        emit statusChanged(
            complete
                ? tr("Scan saved to %1.").arg(path)
                : tr("Scan incomplete (%1 lines) saved to %2.").arg(scan->lines.size()).arg(path));
        emit scanSaved(path, complete);
      });
  device->connectDevice();
}

void HardwarePanel::startScan() {
  if (!d_->scanner) return;
  hardware::ScanRequest request;
  request.lines = d_->lines->value();
  d_->progress->setValue(0);
  d_->scanner->startScan(request);
}

void HardwarePanel::cancelScan() {
  if (d_->scanner) d_->scanner->cancelScan();
}

}  // namespace clearway::ui
