#include "clearway/ui/hardware_panel.h"

#include <QComboBox>
#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QStackedWidget>
#include <QStandardPaths>
#include <optional>

#include "clearway/hardware/acquisition_files.h"
#include "clearway/hardware/pose_source.h"
#include "clearway/hardware/serial_rosi.h"
#include "clearway/hardware/simulated_rosi.h"
#include "clearway/io/file_util.h"
#include "clearway/io/scan_io.h"
#include "clearway/segmentation/params.h"
#include "clearway/sim/builtin_scenes.h"
#include "clearway/traversability/ground_density.h"
#include "remote_scanner_fields.h"

namespace clearway::ui {

using hardware::ScannerDevice;

namespace {
constexpr int kSimulatedPage = 0;
constexpr int kSerialPage = 1;
constexpr int kRemotePage = 2;  // clearway-cli serve on the robot (docs/PROTOCOL.md)

// The density readout: the LMS200's beams are 0.5 deg apart along a line, and a RoSi on a real
// robot's arm is about this high above the floor (the simulated scenes give their own) [m].
constexpr double kLms200StepDeg = 0.5;
constexpr double kTypicalScannerHeight = 1.0;
// Ranges at which the spacing of the ground samples is shown [m].
constexpr double kNearRange = 2.0;
constexpr double kFarRange = 5.0;
// The device box shows at least this many characters of the device's name.
constexpr int kDeviceNameChars = 16;
}  // namespace

struct HardwarePanel::Private {
  QComboBox* device = nullptr;
  QComboBox* scene = nullptr;
  QSpinBox* lines = nullptr;
  QLabel* density = nullptr;  // the ground-sample density the chosen line count gives
  double robot_step = RobotParams{}.max_step;
  QPushButton* connect = nullptr;
  QPushButton* disconnect = nullptr;
  QStackedWidget* fields = nullptr;  // the chosen device's own fields only
  QLineEdit* arm_port = nullptr;
  QLabel* mounting_label = nullptr;
  QLineEdit* mounting = nullptr;
  QLabel* arm_pose = nullptr;
  QString journal;  // of the scan in progress on a serial device
  QString warning;  // what the device warned of during this scan (its journal stopped)
  QPushButton* scan = nullptr;
  QPushButton* cancel = nullptr;
  QLabel* status = nullptr;
  QProgressBar* progress = nullptr;
  QLineEdit* lms_port = nullptr;
  RemoteScannerFields* remote = nullptr;
  QLineEdit* turntable_port = nullptr;
  QComboBox* link_speed = nullptr;
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
  // The box is as wide as the dock gives it, not as its longest entry (the open list shows that
  // whole): at 1024 x 600 the panel scrolled sideways.
  d_->device->setSizeAdjustPolicy(QComboBox::AdjustToMinimumContentsLengthWithIcon);
  d_->device->setMinimumContentsLength(kDeviceNameChars);
  form->addRow(tr("Device"), d_->device);
  // Each device shows only its own fields: a scene for the simulated RoSi, ports, link speed,
  // arm and mounting for the serial one.
  d_->fields = new QStackedWidget(this);
  d_->fields->setObjectName("deviceFields");
  auto* simulated_page = new QWidget(d_->fields);
  simulated_page->setObjectName("simulatedFields");
  auto* simulated_form = new QFormLayout(simulated_page);
  simulated_form->setContentsMargins(0, 0, 0, 0);
  d_->scene = new QComboBox(simulated_page);
  d_->scene->setObjectName("simulatedScene");
  for (const std::string& name : sim::builtinSceneNames())
    d_->scene->addItem(QString::fromStdString(name));
  d_->scene->setCurrentText("garage");
  simulated_form->addRow(tr("Scene"), d_->scene);
  auto* serial_page = new QWidget(d_->fields);
  serial_page->setObjectName("serialFields");
  auto* serial_form = new QFormLayout(serial_page);
  serial_form->setContentsMargins(0, 0, 0, 0);
  // "Mounting (robot from scanner)" and its field side by side were wider than a small screen's
  // dock: a row too wide puts its field under its label.
  serial_form->setRowWrapPolicy(QFormLayout::WrapLongRows);
  d_->lms_port = new QLineEdit("/dev/ttyUSB0", serial_page);
  d_->lms_port->setObjectName("lmsPort");
  d_->turntable_port = new QLineEdit("/dev/ttyUSB1", serial_page);
  d_->turntable_port->setObjectName("turntablePort");
  serial_form->addRow(tr("Laser port"), d_->lms_port);
  serial_form->addRow(tr("Turntable port"), d_->turntable_port);
  d_->link_speed = new QComboBox(serial_page);
  d_->link_speed->setObjectName("linkSpeed");
  for (const int baud : {9600, 19200, 38400, 500000})
    d_->link_speed->addItem(tr("%1 baud").arg(baud), baud);
  d_->link_speed->setCurrentIndex(d_->link_speed->findData(38400));
  d_->link_speed->setToolTip(
      tr("The laser starts at 9600 baud and is switched to this speed; 500 kbaud needs an RS-422 "
         "adapter that supports it"));
  serial_form->addRow(tr("Laser link"), d_->link_speed);
  d_->arm_port = new QLineEdit(serial_page);
  d_->arm_port->setObjectName("armPort");
  d_->arm_port->setPlaceholderText(tr("none: the RoSi is fixed on the robot"));
  d_->arm_port->setToolTip(
      tr("The arm controller's serial port (docs/ARM.md): asked for the "
         "arm's pose before every scan"));
  serial_form->addRow(tr("Arm port"), d_->arm_port);
  d_->mounting_label = new QLabel(serial_page);
  d_->mounting = new QLineEdit(serial_page);
  d_->mounting->setObjectName("mounting");
  d_->mounting->setToolTip(
      tr("tx,ty,tz,qw,qx,qy,qz in metres and a unit quaternion. With an arm: where the RoSi sits "
         "on the tool flange (tool from scanner). Without: where it sits on the robot (robot "
         "from scanner). Empty without an arm: the scans carry no pose."));
  serial_form->addRow(d_->mounting_label, d_->mounting);
  d_->arm_pose = new QLabel(tr("No pose received yet."), serial_page);
  d_->arm_pose->setObjectName("armPose");
  d_->arm_pose->setWordWrap(true);
  serial_form->addRow(tr("Pose"), d_->arm_pose);
  d_->fields->addWidget(simulated_page);
  d_->fields->addWidget(serial_page);
  d_->remote = new RemoteScannerFields(d_->fields);
  d_->fields->addWidget(d_->remote);
  form->addRow(d_->fields);
  const auto showMountingMeaning = [this] {
    const bool arm = !d_->arm_port->text().trimmed().isEmpty();
    d_->mounting_label->setText(arm ? tr("Mounting (tool from scanner)")
                                    : tr("Mounting (robot from scanner)"));
    d_->mounting->setPlaceholderText(
        arm ? QString::fromStdString(hardware::formatPose(hardware::defaultToolFromScanner()))
            : tr("none"));
  };
  showMountingMeaning();
  connect(d_->arm_port, &QLineEdit::textChanged, this, showMountingMeaning);
  // The chosen device's page alone sets the fields' size: every page took the serial one's
  // height, pushing Connect and Scan down below a small screen's fold.
  const auto followPage = [this](int index) {
    d_->fields->setCurrentIndex(index);
    for (int page = 0; page < d_->fields->count(); ++page)
      d_->fields->widget(page)->setSizePolicy(
          page == index ? QSizePolicy(QSizePolicy::Preferred, QSizePolicy::Preferred)
                        : QSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored));
    d_->fields->updateGeometry();
  };
  followPage(d_->device->currentIndex());
  connect(d_->device, qOverload<int>(&QComboBox::currentIndexChanged), this, followPage);
  d_->lines = new QSpinBox(this);
  d_->lines->setObjectName("scanLines");
  d_->lines->setRange(20, 4000);
  d_->lines->setValue(300);
  d_->lines->setToolTip(tr("Lines per revolution (the LMS200 gives 37.5 lines per second)"));
  form->addRow(tr("Lines"), d_->lines);
  d_->density = new QLabel(this);
  d_->density->setObjectName("groundDensity");
  d_->density->setWordWrap(true);
  d_->density->setToolTip(
      tr("How far apart the scan's ground samples lie, and how far from the scanner the map can "
         "show ground green: beyond, an obstacle taller than the robot's step could stand "
         "between the samples unseen (docs/ALGORITHM.md, \"Sparse scans never lie\")"));
  form->addRow(tr("Density"), d_->density);
  connect(d_->lines, qOverload<int>(&QSpinBox::valueChanged), this,
          &HardwarePanel::showGroundDensity);
  connect(d_->scene, &QComboBox::currentTextChanged, this, &HardwarePanel::showGroundDensity);
  // The simulated RoSi scans the scene it was connected with: a scene chosen while it stood
  // connected was ignored without a word. It connects again to the new one (the box is off while
  // a scan runs).
  connect(d_->scene, &QComboBox::currentTextChanged, this, [this] {
    if (dynamic_cast<hardware::SimulatedRosi*>(d_->scanner.get()) && !scanning()) connectScanner();
  });
  connect(d_->device, qOverload<int>(&QComboBox::currentIndexChanged), this,
          &HardwarePanel::showGroundDensity);
  showGroundDensity();
  auto* buttons = new QHBoxLayout;
  d_->connect = new QPushButton(tr("Connect"), this);
  d_->connect->setObjectName("connectButton");
  d_->disconnect = new QPushButton(tr("Disconnect"), this);
  d_->disconnect->setObjectName("disconnectButton");
  d_->disconnect->setEnabled(false);
  d_->scan = new QPushButton(tr("Scan"), this);
  d_->scan->setObjectName("scanButton");
  d_->cancel = new QPushButton(tr("Cancel"), this);
  d_->cancel->setObjectName("cancelScanButton");
  buttons->addWidget(d_->connect);
  buttons->addWidget(d_->disconnect);
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
  connect(d_->disconnect, &QPushButton::clicked, this, &HardwarePanel::disconnectScanner);
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
bool HardwarePanel::scanning() const {
  return d_->scanner && d_->scanner->state() == ScannerDevice::State::kScanning;
}
void HardwarePanel::setSpeedup(double speedup) {
  d_->speedup = speedup;
  if (auto* simulated = dynamic_cast<hardware::SimulatedRosi*>(d_->scanner.get()))
    simulated->setSpeedup(speedup);
}

void HardwarePanel::setRobotStep(double max_step) {
  d_->robot_step = max_step;
  showGroundDensity();
}

void HardwarePanel::showGroundDensity() {
  const int lines = d_->lines->value();
  double height = kTypicalScannerHeight;
  if (d_->device->currentIndex() == kSimulatedPage) {
    if (const auto scene = sim::builtinScene(d_->scene->currentText().toStdString()))
      height = scene->scanner_position.z();
  }
  const SensorGeometry sensor = rosiGeometry(lines, kLms200StepDeg);
  const double vouched = vouchedGroundRange(sensor, height, d_->robot_step);
  d_->density->setText(
      tr("Ground samples %1 m apart at %2 m, %3 m at %4 m; green possible up to %5 m from the "
         "scanner (%6 m step, scanner %7 m above the floor)")
          .arg(expectedGroundSpacing(sensor, kNearRange, height), 0, 'f', 2)
          .arg(kNearRange, 0, 'f', 0)
          .arg(expectedGroundSpacing(sensor, kFarRange, height), 0, 'f', 2)
          .arg(kFarRange, 0, 'f', 0)
          .arg(vouched, 0, 'f', 1)
          .arg(d_->robot_step, 0, 'f', 2)
          .arg(height, 0, 'f', 1));
}

void HardwarePanel::connectScanner() {
  if (d_->scanner) disconnectScanner();
  if (d_->device->currentIndex() == kRemotePage) {
    QString problem;
    std::unique_ptr<ScannerDevice> remote = d_->remote->createDevice(&problem);
    if (!remote) {
      emit statusChanged(problem);
      return;
    }
    d_->scanner = std::move(remote);
  } else if (d_->device->currentIndex() == kSerialPage) {
    const QString arm = d_->arm_port->text().trimmed();
    const QString mounting_text = d_->mounting->text().trimmed();
    std::optional<hardware::RigidPose> mounting;
    if (!mounting_text.isEmpty()) {
      std::string error;
      mounting = hardware::parsePose(mounting_text.toStdString(), error);
      if (!mounting) {
        emit statusChanged(tr("The mounting is not a pose: %1").arg(QString::fromStdString(error)));
        return;
      }
    }
    auto serial = std::make_unique<hardware::SerialRosi>(
        d_->lms_port->text(), d_->turntable_port->text(), d_->link_speed->currentData().toInt());
    if (!arm.isEmpty())
      serial->setPoseSource(std::make_shared<hardware::ArmPoseSource>(
          arm.toStdString(), mounting.value_or(hardware::defaultToolFromScanner())));
    else if (mounting)
      serial->setPoseSource(std::make_shared<hardware::FixedMounting>(*mounting));
    d_->arm_pose->setText(arm.isEmpty() && !mounting ? tr("None: the scans carry no pose.")
                                                     : tr("No pose received yet."));
    d_->scanner = std::move(serial);
  } else {
    auto simulated = std::make_unique<hardware::SimulatedRosi>(
        *sim::builtinScene(d_->scene->currentText().toStdString()));
    simulated->setSpeedup(d_->speedup);
    d_->scanner = std::move(simulated);
  }
  ScannerDevice* device = d_->scanner.get();
  connect(device, &ScannerDevice::stateChanged, this, [this, device](ScannerDevice::State state) {
    d_->scan->setEnabled(state == ScannerDevice::State::kIdle);
    d_->disconnect->setEnabled(state != ScannerDevice::State::kDisconnected);
    d_->connect->setEnabled(state == ScannerDevice::State::kDisconnected ||
                            state == ScannerDevice::State::kFailed);
    d_->cancel->setEnabled(state == ScannerDevice::State::kScanning);
    d_->scene->setEnabled(state != ScannerDevice::State::kScanning);
    emit statusChanged(tr("%1: %2.").arg(device->description(), ScannerDevice::stateName(state)));
  });
  connect(device, &ScannerDevice::linesArrived, this, &HardwarePanel::linesArrived);
  connect(device, &ScannerDevice::poseReceived, d_->arm_pose, &QLabel::setText);
  connect(device, &ScannerDevice::progress, this, [this](int received, int expected) {
    d_->progress->setMaximum(expected);
    d_->progress->setValue(received);
  });
  connect(device, &ScannerDevice::failed, this,
          [this](const QString& reason) { emit statusChanged(reason); });
  // Said while the scan runs: the operator can still make space, or stop it.
  connect(device, &ScannerDevice::warning, this, [this](const QString& text) {
    d_->warning = text;
    emit statusChanged(text);
  });
  connect(
      device, &ScannerDevice::scanFinished, this,
      [this](std::shared_ptr<const Scan> scan, bool complete) {
        // Save first: nothing the operator acquired is lost, whatever happens next.
        QDir().mkpath(d_->folder);
        const QString name = "rosi-" +
                             QDateTime::currentDateTime().toString("yyyyMMdd-hhmmss-zzz") +
                             (complete ? "" : "-partial") + ".pcd";
        const QString path = QDir(d_->folder).filePath(name);
        const auto forgetJournal = [this] {
          if (!d_->journal.isEmpty()) QFile::remove(d_->journal);
          d_->journal.clear();
        };
        if (scan->empty()) {
          forgetJournal();
          emit statusChanged(
              tr("The scan was cancelled before any line arrived; nothing to keep."));
          emit scanEndedUnsaved();
          return;
        }
        try {
          saveRosiPcd(*scan, path.toStdString());
          // Where the scanner was, beside the scan, for the pose resolution.
          if (const auto* serial = dynamic_cast<hardware::SerialRosi*>(d_->scanner.get());
              serial && serial->lastPose())
            writeTextFileAtomically(hardware::poseSidecarPathFor(path.toStdString()),
                                    hardware::poseSidecarJson(*serial->lastPose()));
        } catch (const std::exception& error) {
          QString kept;
          if (!d_->journal.isEmpty() && d_->warning.isEmpty())
            kept =
                tr(" Its lines are kept in %1 (clearway-cli acquire --recover).").arg(d_->journal);
          else if (!d_->journal.isEmpty())  // its journal stopped, on the same full disk
            kept = tr(" Only the lines its journal held when it stopped are kept, in %1 "
                      "(clearway-cli acquire --recover): %2")
                       .arg(d_->journal, d_->warning);
          emit statusChanged(
              tr("The scan could not be saved: %1").arg(QString::fromUtf8(error.what())) + kept);
          emit scanEndedUnsaved();
          return;
        }
        forgetJournal();
        emit statusChanged(
            complete
                ? tr("Scan saved to %1.").arg(path)
                : tr("Scan incomplete (%1 lines) saved to %2.").arg(scan->lines.size()).arg(path));
        d_->progress->reset();  // the next scan starts from an empty bar, not from 99 %
        emit scanSaved(path, complete);
      });
  device->connectDevice();
}

void HardwarePanel::disconnectScanner() {
  if (!d_->scanner) return;
  d_->scanner->disconnectDevice();
  // Deleted later: queued results of a cancelled scan may still name it.
  d_->scanner.release()->deleteLater();
  d_->scan->setEnabled(false);
  d_->cancel->setEnabled(false);
  d_->disconnect->setEnabled(false);
  d_->connect->setEnabled(true);
  emit statusChanged(tr("Disconnected."));
}

void HardwarePanel::startScan() {
  if (!d_->scanner) return;
  hardware::ScanRequest request;
  request.lines = d_->lines->value();
  if (dynamic_cast<hardware::SerialRosi*>(d_->scanner.get())) {
    // Every line journaled as it arrives: a crash of the console keeps them (recover with
    // clearway-cli acquire --recover, docs/JOURNAL.md).
    QDir().mkpath(d_->folder);
    d_->journal =
        QDir(d_->folder)
            .filePath("rosi-" + QDateTime::currentDateTime().toString("yyyyMMdd-hhmmss-zzz") +
                      ".journal");
    request.journal = d_->journal.toStdString();
  }
  d_->progress->setValue(0);
  d_->warning.clear();
  emit scanStarted();
  d_->scanner->startScan(request);
}

void HardwarePanel::cancelScan() {
  if (d_->scanner) d_->scanner->cancelScan();
}

}  // namespace clearway::ui
