#include "clearway/hardware/remote_server.h"

#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QMetaObject>
#include <QPointer>
#include <QSslConfiguration>
#include <QSslPreSharedKeyAuthenticator>
#include <QSslSocket>
#include <QTimer>
#include <deque>
#include <filesystem>
#include <map>

#include "clearway/hardware/journal_recovery.h"
#include "clearway/hardware/remote_protocol.h"
#include "clearway/io/scan_io.h"

namespace clearway::hardware::remote {
namespace {

// Lines per Lines frame: the simulated and serial RoSi hand over 8 or 16 lines at a time.
constexpr int kLinesPerFrame = 8;
// A console that lets this much pile up unread is not reading; it is dropped, not buffered.
constexpr qint64 kMaxUnsentBytes = 16 * 1024 * 1024;
// How long a refused peer has to receive the reason before its connection is dropped.
constexpr int kRefusalDrainMs = 1000;

struct Session {
  int id = 0;
  QSslSocket* socket = nullptr;
  QTimer* timer = nullptr;  // handshake deadline, then the idle deadline
  FrameParser parser;
  QString peer;  // address:port, then identity@address:port
  bool greeted = false;
  bool closing = false;
  Role role = Role::kWatch;
  QByteArray token;
};

struct ServerScan {
  std::uint64_t id = 0;
  std::uint32_t expected = 0;
  std::vector<LineRecord> lines;
  std::optional<SensorPose> pose;
  bool finished = false;
  ScanFinished result;
};

}  // namespace

struct RemoteScanServer::Private {
  RemoteScanServer* q = nullptr;
  ScannerDevice* device = nullptr;
  RobotCredentials credentials;
  ServerOptions options;
  ServerStatistics statistics;
  std::map<int, std::unique_ptr<Session>> sessions;
  int next_session = 1;
  int controller = 0;  // session id, 0 = nobody
  std::shared_ptr<ServerScan> current;
  std::deque<std::shared_ptr<ServerScan>> finished;
  std::uint64_t next_scan_id = std::uint64_t(QDateTime::currentMSecsSinceEpoch());
  QString last_failure;

  void log(const QString& line) { emit q->logMessage(line); }
  // Where scan `id`'s lines are journaled while it runs.
  QString journalPath(std::uint64_t id) const {
    return QDir(options.storage_dir).filePath(QString("scan-%1.journal").arg(id));
  }

  Session* session(int id) {
    const auto found = sessions.find(id);
    return found == sessions.end() || found->second->closing ? nullptr : found->second.get();
  }

  void send(Session& session, const Frame& frame) {
    if (session.closing) return;
    session.socket->write(encodeFrame(frame));
    if (session.socket->bytesToWrite() > kMaxUnsentBytes)
      close(session.id, "it does not read what is sent (more than 16 MB waiting)", true);
  }

  void broadcast(const Frame& frame) {
    const QByteArray bytes = encodeFrame(frame);
    std::vector<int> ids;
    for (const auto& [id, session] : sessions)
      if (session->greeted && !session->closing) ids.push_back(id);
    for (const int id : ids)
      if (Session* s = session(id)) send(*s, frame);
  }

  // Closes a connection with a logged reason; a refusal also tells the peer why, when it can.
  void close(int id, const QString& reason, bool refused) {
    Session* s = session(id);
    if (!s) return;
    s->closing = true;
    if (refused) ++statistics.connections_refused;
    log(QString("%1: connection closed: %2").arg(s->peer, reason));
    if (controller == id) controller = 0;
    s->timer->stop();
    if (refused && s->socket->isEncrypted()) {
      // Tell the peer why, let the reason drain, then forget the connection (at most 1 s later).
      s->socket->write(encodeFrame(encodeText(MessageType::kRefused, reason)));
      // Queued: a caller may still hold this session (forget() must never run inside close()).
      QObject::connect(
          s->socket, &QAbstractSocket::disconnected, q, [this, id] { forget(id); },
          Qt::QueuedConnection);
      QTimer::singleShot(kRefusalDrainMs, q, [this, id] { forget(id); });
      s->socket->disconnectFromHost();
      return;
    }
    s->socket->abort();
    QMetaObject::invokeMethod(
        q, [this, id] { forget(id); }, Qt::QueuedConnection);
  }

  void forget(int id) {
    const auto found = sessions.find(id);
    if (found == sessions.end()) return;
    found->second->socket->disconnect(q);
    found->second->socket->abort();
    found->second->socket->deleteLater();
    sessions.erase(found);
  }

  void accept(qintptr descriptor);
  void onFrame(int id, const Frame& frame);
  void onHello(int id, const Hello& hello);
  void onStartScan(Session& s, const StartScan& request);
  void onResume(Session& s, const Resume& resume);
  void sendLines(Session* only, const ServerScan& scan, std::size_t from);
  void takeLines(const Scan& so_far);
  void finishScan(std::shared_ptr<const Scan> scan, bool complete);
  std::shared_ptr<ServerScan> findScan(std::uint64_t id) const;
};

namespace {

// The measured-values line records a journal (docs/JOURNAL.md) holds whole (a torn last one, cut
// by a full disk, is not recovered and not counted).
std::size_t journaledLines(const QString& path) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) return 0;
  std::size_t lines = 0;
  while (!file.atEnd()) {
    const QByteArray record = file.readLine();
    if (record.startsWith("L ") && record.endsWith('\n')) ++lines;
  }
  return lines;
}

}  // namespace

RemoteScanServer::RemoteScanServer(ScannerDevice* device, RobotCredentials credentials,
                                   ServerOptions options, QObject* parent)
    : QTcpServer(parent), d_(std::make_unique<Private>()) {
  d_->q = this;
  d_->device = device;
  d_->credentials = std::move(credentials);
  d_->options = std::move(options);
  connect(device, &ScannerDevice::linesArrived, this,
          [this](std::shared_ptr<const Scan> so_far) { d_->takeLines(*so_far); });
  connect(device, &ScannerDevice::scanFinished, this,
          [this](std::shared_ptr<const Scan> scan, bool complete) {
            d_->finishScan(std::move(scan), complete);
          });
  // Said to every console at once, and logged: the operator may still make space on the robot.
  connect(device, &ScannerDevice::warning, this, [this](const QString& text) {
    d_->log("scanner: " + text);
    d_->broadcast(encodeText(MessageType::kNotice, text));
  });
  connect(device, &ScannerDevice::failed, this, [this](const QString& reason) {
    d_->last_failure = reason;
    d_->log("scanner: " + reason);
    // A scan that failed before any line arrived ends without scanFinished (a laser that refused
    // to start, a pose that could not be read): end it here, once whatever follows the failure
    // in the same breath (scanFinished with the lines so far) has had its turn. The console used
    // to wait for it forever, and the server refused every later scan.
    if (!d_->current || d_->current->finished) return;
    const std::uint64_t id = d_->current->id;
    QMetaObject::invokeMethod(
        this,
        [this, id] {
          if (!d_->current || d_->current->id != id || d_->current->finished) return;
          if (d_->device->state() == ScannerDevice::State::kScanning) return;
          d_->finishScan(std::make_shared<const Scan>(), false);
        },
        Qt::QueuedConnection);
  });
}

RemoteScanServer::~RemoteScanServer() {
  for (auto& [id, session] : d_->sessions) {
    session->socket->disconnect(this);
    session->socket->abort();
    delete session->socket;
  }
}

ServerStatistics RemoteScanServer::statistics() const {
  return d_->statistics;
}

int RemoteScanServer::recoverInterruptedScans() {
  int recovered = 0;
  for (const std::filesystem::path& journal :
       unfinishedJournals(d_->options.storage_dir.toStdString())) {
    const std::filesystem::path scan = recoveredScanPathFor(journal);
    try {
      const Acquisition acquisition = recoverJournalInto(journal, scan);
      ++recovered;
      d_->log(QString("recovered %1, left by a scan the robot did not finish, into %2: %3")
                  .arg(QString::fromStdString(journal.filename().string()),
                       QString::fromStdString(scan.string()),
                       QString::fromStdString(describeLines(acquisition))));
    } catch (const std::exception& error) {
      d_->log(QString("could not recover %1: %2")
                  .arg(QString::fromStdString(journal.string()), error.what()));
    }
  }
  return recovered;
}

int RemoteScanServer::connectionCount() const {
  return int(d_->sessions.size());
}

void RemoteScanServer::incomingConnection(qintptr descriptor) {
  d_->accept(descriptor);
}

void RemoteScanServer::Private::accept(qintptr descriptor) {
  auto owned = std::make_unique<Session>();
  Session& s = *owned;
  s.id = next_session++;
  s.socket = new QSslSocket(q);
  if (!s.socket->setSocketDescriptor(descriptor)) {
    delete s.socket;
    return;
  }
  s.peer = QString("%1:%2").arg(s.socket->peerAddress().toString()).arg(s.socket->peerPort());
  s.timer = new QTimer(s.socket);
  s.timer->setSingleShot(true);
  const int id = s.id;
  sessions.emplace(id, std::move(owned));
  if (int(sessions.size()) > options.max_connections) {
    close(id, QString("more than %1 connections").arg(options.max_connections), true);
    return;
  }
  ++statistics.connections_accepted;
  QSslSocket* socket = s.socket;
  configurePskTls(*socket);
  QSslConfiguration configuration = socket->sslConfiguration();
  configuration.setPreSharedKeyIdentityHint(credentials.identity_hint);
  socket->setSslConfiguration(configuration);

  QObject::connect(s.timer, &QTimer::timeout, q, [this, id] {
    Session* live = session(id);
    if (!live) return;
    close(id,
          live->greeted
              ? QString("silent for %1 ms (link lost?)").arg(options.idle_timeout_ms)
              : QString("no authenticated Hello within %1 ms").arg(options.handshake_timeout_ms),
          true);
  });
  QObject::connect(socket, &QSslSocket::preSharedKeyAuthenticationRequired, q,
                   [this, id](QSslPreSharedKeyAuthenticator* authenticator) {
                     Session* live = session(id);
                     if (!live) return;
                     const QByteArray key = credentials.keyFor(authenticator->identity());
                     live->peer =
                         QString::fromUtf8(authenticator->identity().left(64)) + "@" + live->peer;
                     if (key.isEmpty()) {
                       log(QString("%1: unknown console identity; refusing").arg(live->peer));
                       return;  // no key: the handshake fails
                     }
                     authenticator->setPreSharedKey(key);
                   });
  QObject::connect(socket, &QSslSocket::encrypted, q, [this, id] {
    if (Session* live = session(id)) log(QString("%1: authenticated").arg(live->peer));
  });
  QObject::connect(socket, &QAbstractSocket::errorOccurred, q, [this, id](auto) {
    Session* live = session(id);
    if (!live) return;
    const bool handshake = !live->socket->isEncrypted();
    close(id,
          handshake ? "TLS handshake failed (no or wrong credentials, or not TLS): " +
                          live->socket->errorString()
                    : live->socket->errorString(),
          handshake);
  });
  QObject::connect(socket, &QSslSocket::readyRead, q, [this, id] {
    Session* live = session(id);
    if (!live) return;
    live->parser.feed(live->socket->readAll());
    try {
      while (Session* current_session = session(id)) {
        std::optional<Frame> frame = current_session->parser.next();
        if (!frame) break;
        onFrame(id, *frame);
      }
    } catch (const ProtocolError& error) {
      close(id, QString("malformed frame: %1").arg(error.what()), true);
    }
  });
  s.timer->start(options.handshake_timeout_ms);
  socket->startServerEncryption();
}

void RemoteScanServer::Private::onFrame(int id, const Frame& frame) {
  Session* s = session(id);
  if (!s) return;
  if (frame.version != kProtocolVersion) {
    close(id,
          QString("protocol version %1 is not supported; this robot speaks version %2")
              .arg(frame.version)
              .arg(kProtocolVersion),
          true);
    return;
  }
  if (!s->greeted) {
    if (frame.type != MessageType::kHello)
      throw ProtocolError("the first message must be Hello, not " +
                          messageTypeName(frame.type).toStdString());
    onHello(id, decodeHello(frame));
    return;
  }
  s->timer->start(options.idle_timeout_ms);
  switch (frame.type) {
    case MessageType::kPing:
      send(*s, encodeStamp(MessageType::kPong, decodeStamp(frame)));
      return;
    case MessageType::kStartScan:
      onStartScan(*s, decodeStartScan(frame));
      return;
    case MessageType::kCancel:
      decodeEmpty(frame);
      if (s->role != Role::kControl) {
        send(*s, encodeText(MessageType::kNotice,
                            "You are watching; only the controlling console "
                            "can cancel."));
        return;
      }
      log(QString("%1: cancel").arg(s->peer));
      device->cancelScan();
      return;
    case MessageType::kResume:
      onResume(*s, decodeResume(frame));
      return;
    default:
      throw ProtocolError(messageTypeName(frame.type).toStdString() +
                          " is not a message a console sends");
  }
}

void RemoteScanServer::Private::onHello(int id, const Hello& hello) {
  Session* s = session(id);
  s->greeted = true;
  s->token = hello.session_token;
  if (!hello.client_name.isEmpty()) s->peer += " (" + hello.client_name.left(64) + ")";
  Welcome welcome;
  welcome.robot = device->description();
  welcome.active_scan = current ? current->id : 0;
  if (hello.role == Role::kControl) {
    Session* holder = controller ? session(controller) : nullptr;
    if (holder && holder->token == hello.session_token) {
      // The same console came back over a new link before the old one timed out.
      close(holder->id, "replaced by a reconnection of the same console", false);
      holder = nullptr;
    }
    if (!holder) {
      controller = id;
      s->role = Role::kControl;
    } else {
      welcome.note =
          QString("%1 controls the scanner; you may watch.").arg(holder->peer.section('@', 0, 0));
      log(QString("%1: control refused (%2 has it); watching").arg(s->peer, holder->peer));
    }
  }
  welcome.granted = s->role;
  log(QString("%1: %2").arg(s->peer, s->role == Role::kControl ? "controls" : "watches"));
  s->timer->start(options.idle_timeout_ms);
  send(*s, encode(welcome));
}

void RemoteScanServer::Private::onStartScan(Session& s, const StartScan& request) {
  if (s.role != Role::kControl) {
    send(s, encodeText(MessageType::kNotice,
                       "You are watching; only the controlling console can start a scan."));
    return;
  }
  if (device->state() != ScannerDevice::State::kIdle || current) {
    send(s, encodeText(MessageType::kNotice, QString("The scanner is not ready (%1).")
                                                 .arg(ScannerDevice::stateName(device->state()))));
    return;
  }
  current = std::make_shared<ServerScan>();
  current->id = next_scan_id++;
  current->expected = request.lines;
  last_failure.clear();
  log(QString("%1: scan %2 started (%3 lines)").arg(s.peer).arg(current->id).arg(request.lines));
  broadcast(encode(ScanStarted{current->id, current->expected, std::nullopt}));
  ScanRequest scan_request;
  scan_request.lines = int(request.lines);
  scan_request.turntable_speed_deg_s = request.turntable_speed_deg_s;
  // A real device journals every line as it arrives: a robot killed or powered off mid-scan
  // keeps them, and recovers them when serve starts again.
  QDir().mkpath(options.storage_dir);
  scan_request.journal = journalPath(current->id).toStdString();
  device->startScan(scan_request);
}

std::shared_ptr<ServerScan> RemoteScanServer::Private::findScan(std::uint64_t id) const {
  if (current && current->id == id) return current;
  for (const auto& scan : finished)
    if (scan->id == id) return scan;
  return nullptr;
}

void RemoteScanServer::Private::onResume(Session& s, const Resume& resume) {
  const std::shared_ptr<ServerScan> scan = findScan(resume.scan_id);
  if (!scan) {
    ScanFinished unknown;
    unknown.scan_id = resume.scan_id;
    // Not in memory: the robot restarted, or the scan is older than those it keeps. Its file may
    // still be on the robot's disk (a stopped robot saves the scan under way first).
    QString saved;
    for (const QString& suffix : {QString(), QString("-partial"), QString("-recovered")}) {
      const QString path = QDir(options.storage_dir)
                               .filePath(QString("scan-%1%2.pcd").arg(resume.scan_id).arg(suffix));
      if (saved.isEmpty() && QFileInfo::exists(path)) saved = path;
    }
    unknown.reason =
        saved.isEmpty()
            ? QString(
                  "The robot does not hold scan %1: it restarted since, or keeps only the "
                  "last %2 scans, and has no file of it.")
                  .arg(resume.scan_id)
                  .arg(options.finished_scans_kept)
            : QString(
                  "The robot no longer serves scan %1 (it restarted since, or keeps only the "
                  "last %2 scans), but saved it as %3 on the robot.")
                  .arg(resume.scan_id)
                  .arg(options.finished_scans_kept)
                  .arg(saved);
    unknown.saved_as = saved;
    send(s, encode(unknown));
    return;
  }
  log(QString("%1: resumes scan %2 from line %3").arg(s.peer).arg(scan->id).arg(resume.from_line));
  if (!scan->finished) send(s, encode(ScanStarted{scan->id, scan->expected, scan->pose}));
  sendLines(&s, *scan, resume.from_line);
  if (scan->finished) send(s, encode(scan->result));
}

void RemoteScanServer::Private::sendLines(Session* only, const ServerScan& scan, std::size_t from) {
  for (std::size_t first = from; first < scan.lines.size(); first += kLinesPerFrame) {
    Lines message;
    message.scan_id = scan.id;
    message.first_line = std::uint32_t(first);
    const std::size_t end = std::min(scan.lines.size(), first + kLinesPerFrame);
    message.lines.assign(scan.lines.begin() + std::ptrdiff_t(first),
                         scan.lines.begin() + std::ptrdiff_t(end));
    const Frame frame = encode(message);
    if (only)
      send(*only, frame);
    else
      broadcast(frame);
  }
}

void RemoteScanServer::Private::takeLines(const Scan& so_far) {
  if (!current || current->finished) return;
  const std::size_t had = current->lines.size();
  if (so_far.lines.size() <= had) return;
  std::vector<LineRecord> added = encodeScanLines(so_far, had, so_far.lines.size() - had);
  for (LineRecord& line : added)
    current->lines.push_back(std::move(line));
  // The pose comes with the first lines (a serial RoSi reads it from the arm as it starts): told
  // before them, so a console that loses the link keeps its partial scan with its pose.
  const bool pose_learnt = !current->pose && so_far.sensor_pose;
  current->pose = so_far.sensor_pose;
  if (pose_learnt) broadcast(encode(ScanStarted{current->id, current->expected, current->pose}));
  sendLines(nullptr, *current, had);
}

void RemoteScanServer::Private::finishScan(std::shared_ptr<const Scan> scan, bool complete) {
  if (!current) return;
  takeLines(*scan);
  if (scan->sensor_pose) current->pose = scan->sensor_pose;
  ScanFinished& result = current->result;
  result.scan_id = current->id;
  result.total_lines = std::uint32_t(current->lines.size());
  result.complete = complete;
  result.pose = current->pose;
  if (!complete)
    result.reason = last_failure.isEmpty() ? QString("The scan was cancelled.") : last_failure;
  // Saved on the robot before anything calls it finished: a dropped link loses nothing.
  const QString name = QString("scan-%1%2.pcd").arg(current->id).arg(complete ? "" : "-partial");
  const QString path = QDir(options.storage_dir).filePath(name);
  bool save_failed = false;
  if (!current->lines.empty()) {
    try {
      QDir().mkpath(options.storage_dir);
      saveRosiPcd(scanFromLineRecords(current->lines, current->pose), path.toStdString());
      result.saved_as = path;
      emit q->scanSaved(path, complete);
    } catch (const std::exception& error) {
      save_failed = true;
      result.complete = false;
      result.reason = QString("The robot could not save the scan: %1").arg(error.what());
    }
  }
  // Saved: the journal is no longer needed. Kept when the save failed, and when it holds lines
  // the scan could not place (no turntable angle came with them), as `acquire` keeps them.
  const QString journal = journalPath(current->id);
  const std::size_t journaled = result.saved_as.isEmpty() ? journaledLines(journal) : 0;
  const std::size_t lines = current->lines.size();
  if (journaled == 0) {
    QFile::remove(journal);
  } else if (!save_failed) {
    log(QString("scan %1: kept %2, which holds lines the scan could not place")
            .arg(current->id)
            .arg(journal));
  } else {
    // The journal may have stopped on the same full disk: how many lines it keeps, not "its
    // lines" (it held 109 of 302), and not "lines the scan could not place".
    result.reason +=
        journaled >= lines
            ? QString(" (its lines are kept in %1)").arg(journal)
            : QString(" (%1 keeps %2 of its %3 lines)").arg(journal).arg(journaled).arg(lines);
    log(QString("scan %1: kept %2, which holds %3 of its %4 lines: the scan could not be saved")
            .arg(current->id)
            .arg(journal)
            .arg(journaled)
            .arg(lines));
  }
  current->finished = true;
  ++statistics.scans_finished;
  // An incomplete scan's log line says why (a full disk was said only to the console).
  log(QString("scan %1 %2: %3 lines%4%5")
          .arg(current->id)
          .arg(result.complete ? "complete" : "incomplete")
          .arg(result.total_lines)
          .arg(result.saved_as.isEmpty() ? QString() : ", saved as " + result.saved_as)
          .arg(result.complete ? QString() : ": " + result.reason));
  broadcast(encode(result));
  finished.push_back(std::move(current));
  current.reset();
  while (int(finished.size()) > options.finished_scans_kept)
    finished.pop_front();
}

}  // namespace clearway::hardware::remote
