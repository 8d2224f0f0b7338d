#include "remote_scanner_fields.h"

#include <QDir>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSpinBox>
#include <QStandardPaths>

#include "clearway/hardware/remote_rosi.h"

namespace clearway::ui {

namespace {
constexpr int kDefaultPort = 47100;  // the port the operator guide (docs/PROTOCOL.md) uses
}

RemoteScannerFields::RemoteScannerFields(QWidget* parent) : QWidget(parent) {
  setObjectName("remoteScannerFields");
  auto* form = new QFormLayout(this);
  form->setContentsMargins(0, 0, 0, 0);
  host_ = new QLineEdit("127.0.0.1", this);
  host_->setObjectName("remoteHost");
  host_->setToolTip(tr("The robot's address, where clearway-cli serve listens"));
  form->addRow(tr("Robot host"), host_);
  port_ = new QSpinBox(this);
  port_->setObjectName("remotePort");
  port_->setRange(1, 65535);
  port_->setValue(kDefaultPort);
  form->addRow(tr("Robot port"), port_);
  auto* credentials_row = new QHBoxLayout;
  credentials_ =
      new QLineEdit(QDir(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation))
                        .filePath("credentials"),
                    this);
  credentials_->setObjectName("remoteCredentials");
  credentials_->setToolTip(
      tr("The folder holding console.json, written by clearway-cli serve --init-credentials"));
  auto* browse = new QPushButton(tr("…"), this);
  browse->setToolTip(tr("Choose the credentials folder"));
  connect(browse, &QPushButton::clicked, this, [this] {
    const QString dir =
        QFileDialog::getExistingDirectory(this, tr("Credentials folder"), credentials_->text());
    if (!dir.isEmpty()) credentials_->setText(dir);
  });
  credentials_row->addWidget(credentials_);
  credentials_row->addWidget(browse);
  form->addRow(tr("Credentials"), credentials_row);
  link_ = new QLabel(tr("Link: not connected."), this);
  link_->setObjectName("remoteLink");
  link_->setWordWrap(true);
  form->addRow(link_);
}

std::unique_ptr<hardware::ScannerDevice> RemoteScannerFields::createDevice(QString* problem) {
  hardware::remote::RemoteOptions options;
  options.host = host_->text().trimmed();
  options.port = quint16(port_->value());
  options.client_name = tr("Clearway console");
  try {
    options.credentials = hardware::remote::loadConsoleCredentials(credentials_->text());
  } catch (const hardware::remote::CredentialsError& error) {
    if (problem) *problem = tr("Cannot use the credentials: %1").arg(error.what());
    return nullptr;
  }
  auto device = std::make_unique<hardware::remote::RemoteRosi>(options);
  connect(device.get(), &hardware::remote::RemoteRosi::linkStatusChanged, link_,
          [this](const QString& words) { link_->setText(tr("Link: %1.").arg(words)); });
  connect(device.get(), &hardware::remote::RemoteRosi::notice, link_,
          [this](const QString& text) { link_->setToolTip(text); });
  return device;
}

}  // namespace clearway::ui
