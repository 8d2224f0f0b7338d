#pragma once

// The RoSi on the robot, reached over the remote protocol: a ScannerDevice like the simulated and
// serial ones. It pings every second and names the link's state in words (round trip, throughput,
// "link lost 4 s ago, reconnecting"). When the link drops it reconnects by itself and asks for the
// rest of the running scan (scan id + first missing line), or the whole scan the robot finished
// meanwhile; lines are taken in order exactly once, and a scan is reported complete only when the
// robot says so and every line it counted has arrived. A watcher that connects while a scan runs
// asks for it the same way, from its first line, and receives it whole.

#include <QString>
#include <memory>

#include "clearway/hardware/remote_credentials.h"
#include "clearway/hardware/remote_protocol.h"
#include "clearway/hardware/scanner_device.h"

namespace clearway::hardware::remote {

struct RemoteOptions {
  QString host = "127.0.0.1";
  quint16 port = 0;
  ConsoleCredentials credentials;
  Role role = Role::kControl;  // a second controlling console is given Watch by the robot
  QString client_name;         // shown in the robot's log
  int ping_interval_ms = 1000;
  int link_timeout_ms = 5000;      // nothing heard for this long: the link is lost
  int connect_timeout_ms = 10000;  // the first connection
  int reconnect_delay_ms = 500;    // first retry; doubles up to kMaxReconnectDelayMs
  int give_up_after_ms = 120000;   // reconnecting this long: the scan is reported incomplete
};

struct LinkStatistics {
  double round_trip_ms = -1.0;    // last Ping/Pong; -1 before the first
  double bytes_per_second = 0.0;  // received, over the last ping interval
  qint64 bytes_received = 0;
  int reconnections = 0;
  int duplicate_lines_dropped = 0;  // lines that arrived twice after a resume (never kept twice)
};

class RemoteRosi : public ScannerDevice {
  Q_OBJECT

 public:
  explicit RemoteRosi(RemoteOptions options, QObject* parent = nullptr);
  ~RemoteRosi() override;

  QString description() const override;
  Role role() const;
  LinkStatistics linkStatistics() const;
  QString linkStatus() const;

 signals:
  void linkStatusChanged(const QString& words);
  // The robot said something that is not an error of this device (e.g. "you are watching").
  void notice(const QString& text);

 protected:
  void doConnect() override;
  void doDisconnect() override;
  void doStartScan(const ScanRequest& request) override;
  void doCancel() override;

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::hardware::remote
