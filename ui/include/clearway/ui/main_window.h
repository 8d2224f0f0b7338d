#pragma once

#include <QMainWindow>
#include <memory>

namespace clearway::ui {

// The operator console's main window. It only wires panels and workers together.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  // Loads a scan in the background; the window stays responsive.
  void openScan(const QString& path);

 private:
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
