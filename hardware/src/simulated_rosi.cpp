#include "clearway/hardware/simulated_rosi.h"

#include <algorithm>
#include <cmath>

#include "clearway/sim/rosi_simulator.h"

namespace clearway::hardware {
namespace {

// Lines handed over per timer tick: the GUI sees steady progress without a tick per line.
constexpr int kLinesPerTick = 8;

// The first `lines` lines of a scan, as a scan.
std::shared_ptr<const Scan> firstLines(const Scan& scan, int lines) {
  auto part = std::make_shared<Scan>();
  const std::size_t count = lines > 0 ? scan.lines[std::size_t(lines - 1)].first +
                                            scan.lines[std::size_t(lines - 1)].count
                                      : 0;
  part->points.assign(scan.points.begin(), scan.points.begin() + std::ptrdiff_t(count));
  part->status.assign(scan.status.begin(), scan.status.begin() + std::ptrdiff_t(count));
  if (!scan.intensity.empty())
    part->intensity.assign(scan.intensity.begin(), scan.intensity.begin() + std::ptrdiff_t(count));
  if (!scan.alpha.empty())
    part->alpha.assign(scan.alpha.begin(), scan.alpha.begin() + std::ptrdiff_t(count));
  part->lines.assign(scan.lines.begin(), scan.lines.begin() + lines);
  part->sensor_pose = scan.sensor_pose;
  part->metadata = scan.metadata;
  return part;
}

}  // namespace

SimulatedRosi::SimulatedRosi(sim::Scene scene, QObject* parent)
    : ScannerDevice(parent), scene_(std::move(scene)) {
  connect(&line_timer_, &QTimer::timeout, this, &SimulatedRosi::deliverLines);
}

SimulatedRosi::~SimulatedRosi() = default;

QString SimulatedRosi::description() const {
  return tr("Simulated RoSi (scene %1)").arg(QString::fromStdString(scene_.name));
}

void SimulatedRosi::doConnect() {
  // A simulated device answers at once.
  QTimer::singleShot(0, this, [this] { setState(State::kIdle); });
}

void SimulatedRosi::doDisconnect() {
  line_timer_.stop();
  full_scan_.reset();
}

void SimulatedRosi::doStartScan(const ScanRequest& request) {
  sim::SensorModel sensor;
  if (request.turntable_speed_deg_s > 0)
    sensor.lines = sim::SensorModel::linesForSpeed(request.turntable_speed_deg_s);
  if (request.lines > 0) sensor.lines = request.lines;
  full_scan_ =
      std::make_shared<Scan>(sim::simulateRosi(scene_, sensor, sim::defaultPlacement(scene_)).scan);
  full_scan_->metadata.source_path.clear();
  delivered_ = 0;
  const double tick_ms =
      1000.0 * kLinesPerTick / (sim::SensorModel::kLineRateHz * std::max(speedup_, 1e-3));
  line_timer_.start(std::max(1, int(std::lround(tick_ms))));
}

void SimulatedRosi::doCancel() {
  line_timer_.stop();
  if (!full_scan_) return;
  // What arrived is kept, marked incomplete.
  auto part = firstLines(*full_scan_, delivered_);
  full_scan_.reset();
  setState(State::kIdle);
  emit scanFinished(part, false);
}

void SimulatedRosi::deliverLines() {
  if (!full_scan_) return;
  const int total = int(full_scan_->lines.size());
  delivered_ = std::min(total, delivered_ + kLinesPerTick);
  emit progress(delivered_, total);
  emit linesArrived(firstLines(*full_scan_, delivered_));
  if (delivered_ < total) return;
  line_timer_.stop();
  std::shared_ptr<const Scan> scan = std::move(full_scan_);
  setState(State::kIdle);
  emit scanFinished(scan, true);
}

}  // namespace clearway::hardware
