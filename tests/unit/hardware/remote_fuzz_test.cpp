// 10,000 malformed or truncated frames from a small fuzzer of our own, over authenticated TLS
// connections, while a good console keeps scanning: the server refuses each with a reason, never
// crashes, never drops the good console, and is left with only that console connected.

#include "remote_test_support.h"

namespace clearway::hardware::remote {
namespace {

// One malformed or truncated frame, of the kinds a broken or hostile peer sends.
QByteArray fuzzFrame(QRandomGenerator& random, const Scan& scan) {
  const Frame good = [&] {
    switch (random.bounded(5)) {
      case 0:
        return encode(Hello{});
      case 1:
        return encode(StartScan{10, 0.0});
      case 2:
        return encode(Resume{1, 0});
      case 3:
        return encodeStamp(MessageType::kPing, 1);
      default:
        return encode(Lines{1, 0, encodeScanLines(scan, 0, 1)});
    }
  }();
  QByteArray bytes = encodeFrame(good);
  switch (random.bounded(7)) {
    case 0:  // an absurd length
      qToBigEndian(quint32(random.bounded(quint32(kMaxFrameBytes + 1), quint32(0x7FFFFFFF))),
                   reinterpret_cast<uchar*>(bytes.data()));
      break;
    case 1:  // a wrong version
      bytes[5] = char(2 + random.bounded(200));
      break;
    case 2:  // an unknown type
      bytes[6] = char(23 + random.bounded(200));
      break;
    case 3:  // truncated, then the peer goes away
      bytes.truncate(random.bounded(1, int(bytes.size())));
      break;
    case 4: {  // random payload bytes under a valid header
      for (int i = 7; i < bytes.size(); ++i)
        if (random.bounded(4) == 0) bytes[i] = char(random.bounded(256));
      bytes[6] = char(MessageType::kLines);
      break;
    }
    case 5:  // a message only the robot sends
      bytes = encodeFrame(encode(Welcome{}));
      break;
    default: {  // a length too short for its message
      const quint32 length = quint32(kFrameHeaderBytes + random.bounded(3));
      qToBigEndian(length, reinterpret_cast<uchar*>(bytes.data()));
      bytes.truncate(kLengthBytes + int(length));
      break;
    }
  }
  return bytes;
}

TEST_F(RemoteLink, TenThousandMalformedFramesWhileAGoodConsoleIsServed) {
  constexpr int kFrames = 10000;
  constexpr int kParallel = 16;  // fuzzing connections open at a time
  const ConsoleCredentials credentials = loadConsoleCredentials(credentials_dir_.path());
  const Scan small = simulatorScan(20);
  QRandomGenerator random(20261122);

  RemoteRosi good(consoleOptions(server_->serverPort()));
  Result result;
  int scans_complete = 0;
  connect(&good, &RemoteRosi::scanFinished, [&](std::shared_ptr<const Scan> scan, bool complete) {
    if (complete && scan->lines.size() == 100) ++scans_complete;
    result.done = true;
    result.complete = complete;
  });
  good.connectDevice();
  ASSERT_TRUE(waitFor([&] { return good.state() == ScannerDevice::State::kIdle; }));
  device_->setSpeedup(5.0);

  int sent = 0, closed_by_server = 0, live = 0;
  std::function<void()> launch = [&] {
    if (sent >= kFrames) return;
    ++sent;
    ++live;
    auto* client = new RawTlsClient(server_->serverPort(), credentials);
    QSslSocket* socket = &client->socket();
    const QByteArray frame = fuzzFrame(random, small);
    // Sometimes the bad frame comes first, sometimes after a proper Hello.
    const bool hello_first = random.bounded(2) == 0;
    QObject::connect(socket, &QSslSocket::encrypted, [socket, frame, hello_first] {
      if (hello_first) socket->write(encodeFrame(encode(Hello{Role::kWatch, {}, "fuzzer"})));
      socket->write(frame);
      if (frame.size() < 7 ||
          qFromBigEndian<quint32>(frame.constData()) + 4 > quint32(frame.size()))
        socket->disconnectFromHost();  // truncated: the peer goes away mid-frame
    });
    QObject::connect(socket, &QAbstractSocket::disconnected, [&, client] {
      ++closed_by_server;
      --live;
      client->socket().disconnect();
      QTimer::singleShot(0, [client] { delete client; });
      launch();
    });
  };
  for (int i = 0; i < kParallel; ++i)
    launch();
  // The good console scans again and again while the fuzzer runs.
  int scans_started = 0;
  ASSERT_TRUE(waitFor(
      [&] {
        if (good.state() == ScannerDevice::State::kIdle && scans_started == scans_complete) {
          ++scans_started;
          result.done = false;
          good.startScan({100, 0.0, {}});
        }
        return sent >= kFrames && live == 0;
      },
      600000));
  ASSERT_TRUE(waitFor([&] { return good.state() == ScannerDevice::State::kIdle; }));
  EXPECT_EQ(sent, kFrames);
  EXPECT_EQ(closed_by_server, kFrames);
  EXPECT_GE(scans_complete, 1);
  EXPECT_EQ(good.state(), ScannerDevice::State::kIdle);
  EXPECT_EQ(good.linkStatistics().reconnections, 0);  // the good console was never dropped
  std::cout << "[ figure ] " << kFrames << " malformed frames, " << scans_complete
            << " complete scans served meanwhile; server refused "
            << server_->statistics().connections_refused << " connections\n";
  // Every fuzzing connection is gone; only the good console remains.
  ASSERT_TRUE(waitFor([&] { return server_->connectionCount() == 1; }, 5000));
}

}  // namespace
}  // namespace clearway::hardware::remote
