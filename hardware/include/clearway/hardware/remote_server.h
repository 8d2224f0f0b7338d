#pragma once

// The robot's side of the remote protocol (`clearway-cli serve`): owns a ScannerDevice, accepts TLS
// (PSK) connections, gives control to one console and lets others watch, acquires on request and
// streams every line to every console as it arrives. Each finished scan is saved atomically in the
// storage folder before its ScanFinished is sent, and kept in memory for resumption: a console that
// lost the link asks for (scan id, from line) and gets the rest. A malformed frame, a failed
// handshake or a silent peer closes that connection with a logged reason, never the server.

#include <QHostAddress>
#include <QTcpServer>
#include <functional>
#include <memory>

#include "clearway/hardware/remote_credentials.h"
#include "clearway/hardware/scanner_device.h"

namespace clearway::hardware::remote {

struct ServerOptions {
  QString storage_dir;              // where every scan is saved
  int handshake_timeout_ms = 5000;  // a peer that has not authenticated and said Hello by then
  int idle_timeout_ms = 10000;      // a console silent this long (it pings every second) is gone
  int max_connections = 32;         // more are refused at once
  int finished_scans_kept = 4;      // in memory, for resumption
};

struct ServerStatistics {
  int connections_accepted = 0;
  int connections_refused = 0;  // handshake failures, protocol errors, limits
  int scans_finished = 0;
};

class RemoteScanServer : public QTcpServer {
  Q_OBJECT

 public:
  // `device` stays owned by the caller and must outlive the server.
  RemoteScanServer(ScannerDevice* device, RobotCredentials credentials, ServerOptions options,
                   QObject* parent = nullptr);
  ~RemoteScanServer() override;

  ServerStatistics statistics() const;
  int connectionCount() const;

  // Scans a killed or powered-off robot left as journals in the storage folder (every line of a
  // scan under way is journaled there as it arrives, docs/JOURNAL.md): each is saved as
  // scan-ID-recovered.pcd and its journal removed, one log line each. Call before listening, so
  // a console resuming such a scan is told where it is. Returns how many were recovered.
  int recoverInterruptedScans();

 signals:
  // One line per event, for the log: connections, refusals with their reason, scans.
  void logMessage(const QString& line);
  // A scan was saved on the robot (before its ScanFinished went out).
  void scanSaved(const QString& path, bool complete);

 protected:
  void incomingConnection(qintptr descriptor) override;

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::hardware::remote
