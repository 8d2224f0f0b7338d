#pragma once

// Who may talk to the robot: TLS with a pre-shared key (TLS 1.2, ECDHE-PSK cipher suites, so every
// session still gets its own keys). `clearway-cli serve --init-credentials DIR` writes two files:
//   DIR/robot.json    the robot's: its identity hint and the consoles it accepts (identity + key)
//   DIR/console.json  the console's: its identity and key
// The robot keeps robot.json; the operator copies console.json to the control room. Both are
// written owner-read-only. A wrong key fails the TLS handshake, so nothing else is ever read.

#include <QByteArray>
#include <QString>
#include <QStringList>
#include <stdexcept>
#include <vector>

class QSslSocket;

namespace clearway::hardware::remote {

class CredentialsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

constexpr int kPreSharedKeyBytes = 32;  // 256 bits from the system's random source

struct ConsoleKey {
  QByteArray identity;
  QByteArray key;
};

struct RobotCredentials {
  QByteArray identity_hint = "clearway-robot";
  std::vector<ConsoleKey> consoles;
  // The key of `identity`, or empty when it is not a known console.
  QByteArray keyFor(const QByteArray& identity) const;
};

struct ConsoleCredentials {
  ConsoleKey key;
};

inline const char* kRobotCredentialsFile = "robot.json";
inline const char* kConsoleCredentialsFile = "console.json";

// Writes DIR/robot.json and DIR/console.json with a fresh key (refuses to overwrite existing
// files). Returns the paths written. Throws CredentialsError naming the file on failure.
QStringList initCredentials(const QString& dir, const QByteArray& console_identity = "console");

// Read DIR/robot.json or DIR/console.json (DIR may also name the file itself). Throws
// CredentialsError naming the file and the problem.
RobotCredentials loadRobotCredentials(const QString& dir_or_file);
ConsoleCredentials loadConsoleCredentials(const QString& dir_or_file);

// The TLS settings both sides use: TLS 1.2 exactly, PSK cipher suites only, no certificates.
void configurePskTls(QSslSocket& socket);

}  // namespace clearway::hardware::remote
