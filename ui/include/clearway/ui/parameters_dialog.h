#pragma once

// Every numeric parameter of SegmentationParams in one form, generated from its table (ranges,
// defaults, descriptions); the validation reasons are shown live and OK needs valid values.

#include <QDialog>
#include <memory>

#include "clearway/segmentation/params.h"

namespace clearway::ui {

class ParametersDialog : public QDialog {
  Q_OBJECT

 public:
  explicit ParametersDialog(const SegmentationParams& params, QWidget* parent = nullptr);
  ~ParametersDialog() override;

  SegmentationParams params() const;
  // Reasons the current values are unusable; empty when they are fine.
  QStringList problems() const;

 private:
  void refresh();
  struct Private;
  std::unique_ptr<Private> d_;
};

}  // namespace clearway::ui
