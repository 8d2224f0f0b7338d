#include "clearway/hardware/remote_rosi.h"

#include <QElapsedTimer>
#include <QRandomGenerator>
#include <QSslPreSharedKeyAuthenticator>
#include <QSslSocket>
#include <QTimer>
#include <algorithm>

namespace clearway::hardware::remote {
namespace {

constexpr int kMaxReconnectDelayMs = 2000;  // retries at most this far apart
// A robot that calls a scan complete yet keeps lines back is asked again this often, then the scan
// is kept as partial: the request loop is bounded.
constexpr int kMaxShortFinishRetries = 3;

QString megabytes(double bytes) {
  return bytes >= 1e6 ? QString("%1 MB").arg(bytes / 1e6, 0, 'f', 2)
                      : QString("%1 kB").arg(bytes / 1e3, 0, 'f', 1);
}

}  // namespace

struct RemoteRosi::Private {
  RemoteRosi* q = nullptr;
  RemoteOptions options;
  QByteArray token;  // this console, across reconnections
  QSslSocket* socket = nullptr;
  FrameParser parser;
  QTimer tick;  // ping, link watchdog, reconnection
  QElapsedTimer clock;
  qint64 last_heard_ms = 0;
  qint64 lost_at_ms = -1;  // -1: the link is up (or never was)
  qint64 next_attempt_ms = 0;
  int reconnect_delay_ms = 0;
  int attempts = 0;
  bool welcomed_once = false;  // after the first Welcome, losses are reconnected
  bool welcomed = false;
  bool user_disconnected = true;
  bool psk_asked = false;  // this connection's peer asked for the pre-shared key
  Role role = Role::kWatch;
  QString robot;
  LinkStatistics stats;
  qint64 bytes_at_last_tick = 0;
  QString status;

  // The scan being received.
  bool start_pending = false;
  bool cancel_pending = false;
  std::uint64_t scan_id = 0;  // 0: none
  std::uint32_t expected = 0;
  std::shared_ptr<Scan> scan;
  int short_finish_retries = 0;
  // A Resume is on its way: Lines the robot sent before reading it may start beyond the lines
  // held; its answer brings those, so they are dropped rather than taken for a protocol error.
  bool resume_pending = false;

  QString where() const { return QString("%1:%2").arg(options.host).arg(options.port); }

  void setStatus(const QString& words) {
    if (words == status) return;
    status = words;
    emit q->linkStatusChanged(words);
  }

  void send(const Frame& frame) {
    if (socket && welcomed) socket->write(encodeFrame(frame));
  }
  void resume(std::uint32_t from_line) {
    resume_pending = true;
    send(encode(Resume{scan_id, from_line}));
  }

  void open();
  void dropSocket();
  void onFrame(const Frame& frame);
  void onWelcome(const Welcome& welcome);
  void onLines(const Lines& lines);
  void onFinished(const ScanFinished& finished);
  void linkLost(const QString& reason);
  void onTick();
  void endScan(bool complete, const QString& reason);
  void refuse(const QString& reason);
  // Why the first connection failed, in words: nothing listening, no such host, not a Clearway
  // robot, or credentials the robot refused.
  QString firstConnectionFailure(QAbstractSocket::SocketError error, const QString& reason) const;
};

RemoteRosi::RemoteRosi(RemoteOptions options, QObject* parent)
    : ScannerDevice(parent), d_(std::make_unique<Private>()) {
  d_->q = this;
  d_->options = std::move(options);
  d_->token.resize(kSessionTokenBytes);
  for (char& byte : d_->token)
    byte = char(QRandomGenerator::system()->bounded(256));
  d_->clock.start();
  connect(&d_->tick, &QTimer::timeout, this, [this] { d_->onTick(); });
}

RemoteRosi::~RemoteRosi() {
  d_->user_disconnected = true;
  d_->dropSocket();
}

QString RemoteRosi::description() const {
  return tr("Remote RoSi at %1%2")
      .arg(d_->where(), d_->robot.isEmpty() ? QString() : " (" + d_->robot + ")");
}

Role RemoteRosi::role() const {
  return d_->role;
}
LinkStatistics RemoteRosi::linkStatistics() const {
  return d_->stats;
}
QString RemoteRosi::linkStatus() const {
  return d_->status;
}

void RemoteRosi::doConnect() {
  d_->user_disconnected = false;
  d_->welcomed_once = false;
  d_->lost_at_ms = -1;
  d_->setStatus(tr("connecting to %1").arg(d_->where()));
  d_->open();
  d_->tick.start(d_->options.ping_interval_ms);
}

void RemoteRosi::doDisconnect() {
  d_->user_disconnected = true;
  d_->tick.stop();
  if (d_->socket && d_->welcomed) d_->socket->flush();  // a Cancel just sent goes out first
  d_->dropSocket();
  // The lines that arrived are handed over, marked incomplete; the robot saves its own copy.
  if (d_->scan && !d_->scan->empty())
    d_->endScan(false, tr("Disconnected during the scan; the robot keeps its copy."));
  d_->scan.reset();
  d_->scan_id = 0;
  d_->start_pending = false;
  d_->setStatus(tr("disconnected"));
}

void RemoteRosi::doStartScan(const ScanRequest& request) {
  if (!d_->welcomed) {
    // Never queued for later: the operator decides again when the link is back.
    setState(State::kIdle);
    emit failed(tr("The link to the robot is down (%1); start the scan again when it is back.")
                    .arg(d_->status));
    return;
  }
  d_->start_pending = true;
  d_->scan.reset();
  d_->scan_id = 0;
  StartScan message;
  message.lines = std::uint32_t(std::max(0, request.lines));
  message.turntable_speed_deg_s = request.turntable_speed_deg_s;
  d_->send(encode(message));
}

void RemoteRosi::doCancel() {
  // The robot stops the scan and answers with what it has; over a lost link, cancel on return.
  if (d_->welcomed)
    d_->send(encodeEmpty(MessageType::kCancel));
  else
    d_->cancel_pending = true;
}

void RemoteRosi::Private::open() {
  dropSocket();
  parser = FrameParser();
  welcomed = false;
  resume_pending = false;
  socket = new QSslSocket(q);
  configurePskTls(*socket);
  ++attempts;
  psk_asked = false;
  QObject::connect(socket, &QSslSocket::preSharedKeyAuthenticationRequired, q,
                   [this](QSslPreSharedKeyAuthenticator* authenticator) {
                     psk_asked = true;  // a TLS-PSK peer: a Clearway robot
                     authenticator->setIdentity(options.credentials.key.identity);
                     authenticator->setPreSharedKey(options.credentials.key.key);
                   });
  QObject::connect(socket, &QSslSocket::encrypted, q, [this] {
    last_heard_ms = clock.elapsed();
    Hello hello;
    hello.role = options.role;
    hello.session_token = token;
    hello.client_name = options.client_name;
    socket->write(encodeFrame(encode(hello)));
  });
  QObject::connect(socket, &QSslSocket::readyRead, q, [this] {
    const QByteArray bytes = socket->readAll();
    stats.bytes_received += bytes.size();
    last_heard_ms = clock.elapsed();
    parser.feed(bytes);
    try {
      while (socket) {
        std::optional<Frame> frame = parser.next();
        if (!frame) break;
        onFrame(*frame);
      }
    } catch (const ProtocolError& error) {
      linkLost(tr("the robot sent a malformed frame: %1").arg(error.what()));
    }
  });
  QObject::connect(socket, &QAbstractSocket::errorOccurred, q,
                   [this](QAbstractSocket::SocketError error) {
                     const bool handshake = socket && !socket->isEncrypted();
                     const QString reason = socket ? socket->errorString() : QString();
                     if (!welcomed_once && handshake) {
                       refuse(firstConnectionFailure(error, reason));
                       return;
                     }
                     linkLost(reason);
                   });
  last_heard_ms = clock.elapsed();
  socket->connectToHostEncrypted(options.host, options.port);
}

QString RemoteRosi::Private::firstConnectionFailure(QAbstractSocket::SocketError error,
                                                    const QString& reason) const {
  if (error == QAbstractSocket::ConnectionRefusedError)
    return tr("Could not connect to the robot: nothing listens at %1 (is clearway-cli serve "
              "running there, on that port?).")
        .arg(where());
  if (error == QAbstractSocket::HostNotFoundError)
    return tr("Could not connect to the robot at %1: host not found.").arg(where());
  // The robot offers TLS with a pre-shared key: only a peer that asked for our key is one.
  if (psk_asked)
    return tr("The robot at %1 refused this console's credentials (%2): the credentials may be "
              "wrong (console.json must hold an identity and key that the robot's robot.json "
              "lists).")
        .arg(where(), reason);
  if (error == QAbstractSocket::SslHandshakeFailedError ||
      error == QAbstractSocket::RemoteHostClosedError ||
      error == QAbstractSocket::SslInternalError || error == QAbstractSocket::UnknownSocketError)
    return tr("Could not connect to the robot: %1 does not speak Clearway's protocol (not a "
              "Clearway robot?); the TLS handshake ended with: %2")
        .arg(where(), reason);
  return tr("Could not connect to the robot at %1: %2.").arg(where(), reason);
}

void RemoteRosi::Private::dropSocket() {
  welcomed = false;
  if (!socket) return;
  QSslSocket* old = socket;
  socket = nullptr;
  old->disconnect(q);
  old->abort();
  old->deleteLater();
}

void RemoteRosi::Private::refuse(const QString& reason) {
  dropSocket();
  tick.stop();
  user_disconnected = true;
  if (scan_id != 0 || start_pending) endScan(false, reason);
  setStatus(tr("refused: %1").arg(reason));
  q->fail(reason);
}

void RemoteRosi::Private::onFrame(const Frame& frame) {
  if (frame.version != kProtocolVersion)
    throw ProtocolError("protocol version " + std::to_string(frame.version) + " instead of " +
                        std::to_string(kProtocolVersion));
  switch (frame.type) {
    case MessageType::kWelcome:
      onWelcome(decodeWelcome(frame));
      return;
    case MessageType::kRefused:
      refuse(tr("The robot refused the connection: %1").arg(decodeText(frame)));
      return;
    case MessageType::kNotice: {
      const QString text = decodeText(frame);
      emit q->notice(text);
      if (start_pending && scan_id == 0) {
        // The robot did not start the scan (busy, or we only watch).
        start_pending = false;
        q->setState(State::kIdle);
        emit q->failed(text);
      }
      return;
    }
    case MessageType::kPong:
      stats.round_trip_ms = double(clock.elapsed() - qint64(decodeStamp(frame)));
      return;
    case MessageType::kScanStarted: {
      const ScanStarted started = decodeScanStarted(frame);
      if (scan_id != 0 && scan_id != started.scan_id) return;  // another scan while ours runs
      if (scan_id == 0) {
        scan_id = started.scan_id;
        short_finish_retries = 0;
        start_pending = false;
        scan = std::make_shared<Scan>();
      }
      expected = started.expected_lines;
      // A watcher that joined a scan under way scans from the robot's answer to its Resume.
      if (q->state() != State::kScanning) q->setState(State::kScanning);
      // Repeated with the pose once the robot knows it, and on a resumption: the lines held, even
      // a partial scan kept after the link is lost for good, carry it.
      if (started.pose && scan) scan->sensor_pose = started.pose;
      return;
    }
    case MessageType::kLines:
      onLines(decodeLines(frame));
      return;
    case MessageType::kScanFinished:
      onFinished(decodeScanFinished(frame));
      return;
    default:
      throw ProtocolError(messageTypeName(frame.type).toStdString() +
                          " is not a message a robot sends");
  }
}

void RemoteRosi::Private::onWelcome(const Welcome& welcome) {
  const bool reconnection = welcomed_once;
  welcomed = true;
  welcomed_once = true;
  role = welcome.granted;
  robot = welcome.robot;
  lost_at_ms = -1;
  attempts = 0;
  reconnect_delay_ms = options.reconnect_delay_ms;
  if (!welcome.note.isEmpty()) emit q->notice(welcome.note);
  if (reconnection) ++stats.reconnections;
  if (scan_id != 0) {
    // Ask for what is missing: the rest of the running scan, or all of the finished one.
    resume(std::uint32_t(scan ? scan->lines.size() : 0));
  } else if (start_pending && welcome.active_scan != 0) {
    // The scan started while the link was down: take it from its first line.
    scan_id = welcome.active_scan;
    scan = std::make_shared<Scan>();
    start_pending = false;
    resume(0);
  } else if (role == Role::kWatch && welcome.active_scan != 0) {
    // A watcher arriving while a scan runs: the robot holds its lines, so it is received from its
    // first line, then live (it used to wait, silent, for a ScanStarted that had gone by).
    scan_id = welcome.active_scan;
    scan = std::make_shared<Scan>();
    expected = 0;
    short_finish_retries = 0;
    emit q->notice(tr("A scan is under way on the robot: receiving it from its first line."));
    resume(0);
  }
  if (cancel_pending) {
    cancel_pending = false;
    send(encodeEmpty(MessageType::kCancel));
  }
  if (q->state() == State::kConnecting) q->setState(State::kIdle);
  onTick();
}

void RemoteRosi::Private::onLines(const Lines& lines) {
  if (lines.scan_id != scan_id || !scan) return;
  const std::size_t have = scan->lines.size();
  if (lines.first_line > have && resume_pending) return;  // the Resume's answer brings them
  if (lines.first_line > have)
    throw ProtocolError("lines from " + std::to_string(lines.first_line) + " arrived but only " +
                        std::to_string(have) + " are here");
  const std::size_t skip = have - lines.first_line;
  if (skip >= lines.lines.size()) {
    stats.duplicate_lines_dropped += int(lines.lines.size());
    return;
  }
  stats.duplicate_lines_dropped += int(skip);
  resume_pending = false;  // from here on the lines follow on from those held
  appendLineRecords(*scan, std::vector<LineRecord>(lines.lines.begin() + std::ptrdiff_t(skip),
                                                   lines.lines.end()));
  const int received = int(scan->lines.size());
  emit q->progress(received, std::max<int>(int(expected), received));
  emit q->linesArrived(std::make_shared<const Scan>(*scan));
}

void RemoteRosi::Private::onFinished(const ScanFinished& finished) {
  if (finished.scan_id != scan_id || !scan) return;
  if (finished.complete && scan->lines.size() < finished.total_lines &&
      short_finish_retries < kMaxShortFinishRetries) {
    // Cannot happen on one ordered link; ask again rather than call a partial scan complete.
    ++short_finish_retries;
    resume(std::uint32_t(scan->lines.size()));
    return;
  }
  scan->sensor_pose = finished.pose;
  endScan(finished.complete && scan->lines.size() == finished.total_lines, finished.reason);
}

void RemoteRosi::Private::endScan(bool complete, const QString& reason) {
  std::shared_ptr<Scan> result = scan ? scan : std::make_shared<Scan>();
  result->metadata.format = "clearway remote protocol v" + std::to_string(kProtocolVersion);
  scan.reset();
  scan_id = 0;
  start_pending = false;
  if (q->state() == State::kScanning) q->setState(State::kIdle);
  if (!complete && !reason.isEmpty()) emit q->failed(reason);
  emit q->scanFinished(result, complete);
}

void RemoteRosi::Private::linkLost(const QString& reason) {
  if (user_disconnected) return;
  dropSocket();
  if (lost_at_ms < 0) {
    lost_at_ms = clock.elapsed();
    reconnect_delay_ms = options.reconnect_delay_ms;
    next_attempt_ms = lost_at_ms + reconnect_delay_ms;
    emit q->notice(tr("Link to %1 lost: %2").arg(where(), reason));
  }
  // Retry when due, not only on the next ping tick.
  QTimer::singleShot(int(std::max<qint64>(0, next_attempt_ms - clock.elapsed())), q,
                     [this] { onTick(); });
  onTick();
}

void RemoteRosi::Private::onTick() {
  const qint64 now = clock.elapsed();
  if (user_disconnected) return;
  if (lost_at_ms < 0 && welcomed) {
    if (now - last_heard_ms > options.link_timeout_ms) {
      linkLost(tr("nothing heard for %1 s").arg(options.link_timeout_ms / 1000.0, 0, 'f', 1));
      return;
    }
    send(encodeStamp(MessageType::kPing, std::uint64_t(now)));
    const double seconds = options.ping_interval_ms / 1000.0;
    stats.bytes_per_second = double(stats.bytes_received - bytes_at_last_tick) / seconds;
    bytes_at_last_tick = stats.bytes_received;
    QString words = tr("connected to %1 (%2)")
                        .arg(where(), role == Role::kControl ? tr("in control") : tr("watching"));
    if (stats.round_trip_ms >= 0) words += tr(", round trip %1 ms").arg(stats.round_trip_ms);
    words += tr(", %1/s").arg(megabytes(stats.bytes_per_second));
    setStatus(words);
    return;
  }
  if (lost_at_ms < 0) {
    // Still connecting for the first time.
    if (!welcomed_once && now - last_heard_ms > options.connect_timeout_ms) {
      const bool accepted = socket && socket->state() == QAbstractSocket::ConnectedState;
      refuse(accepted && !psk_asked
                 ? tr("Could not connect to the robot: %1 accepted the connection but did not "
                      "answer within %2 s: it does not speak Clearway's protocol (not a "
                      "Clearway robot?).")
                       .arg(where())
                       .arg(options.connect_timeout_ms / 1000)
                 : tr("The robot at %1 did not answer within %2 s.")
                       .arg(where())
                       .arg(options.connect_timeout_ms / 1000));
    }
    return;
  }
  const qint64 lost_for = now - lost_at_ms;
  if (lost_for > options.give_up_after_ms) {
    const QString reason =
        tr("The link to %1 was lost for %2 s; gave up.").arg(where()).arg(lost_for / 1000);
    refuse(reason);
    return;
  }
  setStatus(tr("link lost %1 s ago, reconnecting (attempt %2)").arg(lost_for / 1000).arg(attempts));
  if (now >= next_attempt_ms && (!socket || socket->state() == QAbstractSocket::UnconnectedState)) {
    reconnect_delay_ms = std::min(kMaxReconnectDelayMs, reconnect_delay_ms * 2);
    next_attempt_ms = now + reconnect_delay_ms;
    open();
  } else if (socket && now >= next_attempt_ms) {
    // An attempt that hangs (a black-holed link) is abandoned and retried.
    dropSocket();
  }
}

}  // namespace clearway::hardware::remote
