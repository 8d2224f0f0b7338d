#include "clearway/hardware/remote_credentials.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QRandomGenerator>
#include <QSaveFile>
#include <QSslCipher>
#include <QSslConfiguration>
#include <QSslSocket>
#include <algorithm>

namespace clearway::hardware::remote {
namespace {

constexpr int kFormatVersion = 1;
constexpr qint64 kMaxCredentialsBytes = 64 * 1024;  // a credentials file is a few hundred bytes

[[noreturn]] void failOn(const QString& file, const QString& problem) {
  throw CredentialsError((file + ": " + problem).toStdString());
}

QByteArray randomKey() {
  QByteArray key(kPreSharedKeyBytes, '\0');
  // QRandomGenerator::system() reads the operating system's cryptographic source.
  QRandomGenerator::system()->generate(reinterpret_cast<quint32*>(key.data()),
                                       reinterpret_cast<quint32*>(key.data() + key.size()));
  return key;
}

void writePrivateJson(const QString& path, const QJsonObject& object) {
  if (QFileInfo::exists(path))
    failOn(path, "exists already; remove it first if you really mean to replace the credentials");
  QSaveFile file(path);  // written beside the target and renamed: atomic
  if (!file.open(QIODevice::WriteOnly)) failOn(path, "cannot be written: " + file.errorString());
  file.setPermissions(QFileDevice::ReadOwner | QFileDevice::WriteOwner);
  file.write(QJsonDocument(object).toJson());
  if (!file.commit()) failOn(path, "cannot be written: " + file.errorString());
}

QString resolve(const QString& dir_or_file, const char* name) {
  const QFileInfo info(dir_or_file);
  // A folder (existing or not) holds the file; only a path ending in .json names it directly.
  return info.isDir() || !dir_or_file.endsWith(".json") ? QDir(dir_or_file).filePath(name)
                                                        : dir_or_file;
}

QJsonObject readJson(const QString& path, const QString& role) {
  QFile file(path);
  if (!file.exists())
    failOn(path, "does not exist (create credentials with serve --init-credentials)");
  // A pipe waited for ever: only a plain file is read.
  if (!QFileInfo(path).isFile()) failOn(path, "is not a plain file");
  if (!file.open(QIODevice::ReadOnly)) failOn(path, "cannot be read: " + file.errorString());
  if (file.size() > kMaxCredentialsBytes) failOn(path, "is too large to be a credentials file");
  QJsonParseError error;
  const QJsonDocument document = QJsonDocument::fromJson(file.readAll(), &error);
  if (!document.isObject()) failOn(path, "is not a credentials file (" + error.errorString() + ")");
  const QJsonObject object = document.object();
  if (object.value("clearway_credentials").toInt() != kFormatVersion)
    failOn(path, "is not a Clearway credentials file of version 1");
  if (!object.value("role").isString()) failOn(path, "says no \"role\" (robot or console)");
  if (object.value("role").toString() != role)
    failOn(path, "holds the " + object.value("role").toString() + "'s credentials, not the " +
                     role + "'s");
  return object;
}

ConsoleKey keyFrom(const QString& path, const QJsonObject& object) {
  ConsoleKey key;
  key.identity = object.value("identity").toString().toUtf8();
  const QString hex = object.value("key").toString();
  if (key.identity.isEmpty()) failOn(path, "has no identity");
  // fromHex skips what is not a hex digit and takes an odd last digit: a key with stray
  // characters connected, one of 63 digits failed only at the handshake.
  const bool hex_digits = std::all_of(hex.begin(), hex.end(), [](QChar c) {
    return c.isDigit() || (c.toLower() >= QChar('a') && c.toLower() <= QChar('f'));
  });
  if (!hex_digits || hex.size() != 2 * kPreSharedKeyBytes)
    failOn(path, QString("has a key of %1 characters%2; it must be %3 hex digits")
                     .arg(hex.size())
                     .arg(hex_digits ? "" : ", not all hex digits")
                     .arg(2 * kPreSharedKeyBytes));
  key.key = QByteArray::fromHex(hex.toLatin1());
  if (key.key.size() != kPreSharedKeyBytes)
    failOn(path, QString("has a key of %1 bytes; it must be %2 bytes as 64 hex digits")
                     .arg(key.key.size())
                     .arg(kPreSharedKeyBytes));
  return key;
}

}  // namespace

QByteArray RobotCredentials::keyFor(const QByteArray& identity) const {
  for (const ConsoleKey& console : consoles)
    if (console.identity == identity) return console.key;
  return {};
}

QStringList initCredentials(const QString& dir, const QByteArray& console_identity) {
  if (!QDir().mkpath(dir)) failOn(dir, "cannot be created");
  const QString robot_path = QDir(dir).filePath(kRobotCredentialsFile);
  const QString console_path = QDir(dir).filePath(kConsoleCredentialsFile);
  for (const QString& path : {robot_path, console_path})
    if (QFileInfo::exists(path))
      failOn(path, "exists already; remove it first if you really mean to replace the credentials");
  const QString key = QString::fromLatin1(randomKey().toHex());
  const QJsonObject console{{"identity", QString::fromUtf8(console_identity)}, {"key", key}};
  writePrivateJson(robot_path, QJsonObject{{"clearway_credentials", kFormatVersion},
                                           {"role", "robot"},
                                           {"identity_hint", "clearway-robot"},
                                           {"consoles", QJsonArray{console}}});
  QJsonObject console_file = console;
  console_file.insert("clearway_credentials", kFormatVersion);
  console_file.insert("role", "console");
  writePrivateJson(console_path, console_file);
  return {robot_path, console_path};
}

RobotCredentials loadRobotCredentials(const QString& dir_or_file) {
  const QString path = resolve(dir_or_file, kRobotCredentialsFile);
  const QJsonObject object = readJson(path, "robot");
  RobotCredentials credentials;
  credentials.identity_hint = object.value("identity_hint").toString("clearway-robot").toUtf8();
  for (const QJsonValue& console : object.value("consoles").toArray()) {
    ConsoleKey key = keyFrom(path, console.toObject());
    // One identity, two keys: the first was used without a word.
    for (const ConsoleKey& earlier : credentials.consoles)
      if (earlier.identity == key.identity)
        failOn(path, "names the console '" + QString::fromUtf8(key.identity) + "' twice");
    credentials.consoles.push_back(std::move(key));
  }
  if (credentials.consoles.empty()) failOn(path, "names no console that may connect");
  return credentials;
}

ConsoleCredentials loadConsoleCredentials(const QString& dir_or_file) {
  const QString path = resolve(dir_or_file, kConsoleCredentialsFile);
  return {keyFrom(path, readJson(path, "console"))};
}

void configurePskTls(QSslSocket& socket) {
  QSslConfiguration configuration = socket.sslConfiguration();
  // PSK authenticates both sides; there are no certificates to verify.
  configuration.setPeerVerifyMode(QSslSocket::VerifyNone);
  configuration.setProtocol(QSsl::TlsV1_2);
  QList<QSslCipher> psk_ciphers;
  for (const QSslCipher& cipher : QSslConfiguration::supportedCiphers())
    if (cipher.name().contains("ECDHE-PSK") || cipher.name().contains("DHE-PSK"))
      psk_ciphers.append(cipher);
  if (!psk_ciphers.isEmpty()) configuration.setCiphers(psk_ciphers);
  socket.setSslConfiguration(configuration);
}

}  // namespace clearway::hardware::remote
