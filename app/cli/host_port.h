#pragma once

// HOST:PORT on the command line of serve and acquire --remote.

#include <QString>
#include <string>
#include <utility>

#include "arguments.h"

namespace clearway::cli {

// Splits "HOST:PORT" ("[::1]:PORT" for IPv6); `allow_any_port` accepts port 0 (the system picks).
inline std::pair<QString, quint16> parseHostPort(const std::string& text, bool allow_any_port) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) throw UsageError("'" + text + "' is not HOST:PORT");
  std::string host = text.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  bool ok = false;
  const uint port = QString::fromStdString(text.substr(colon + 1)).toUInt(&ok);
  if (!ok || port > 65535 || (port == 0 && !allow_any_port))
    throw UsageError("'" + text + "' has no valid port (1..65535)");
  return {QString::fromStdString(host), quint16(port)};
}

}  // namespace clearway::cli
