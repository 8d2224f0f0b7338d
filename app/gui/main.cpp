// clearway: the operator console.

#include <QApplication>
#include <QCommandLineParser>

#include "clearway/ui/main_window.h"

int main(int argc, char** argv) {
  QApplication application(argc, argv);
  QApplication::setApplicationName("Clearway");
  QApplication::setOrganizationName("Clearway");

  QCommandLineParser parser;
  parser.setApplicationDescription("Clearway operator console");
  parser.addHelpOption();
  parser.addPositionalArgument("scan", "Scan file to open");
  parser.process(application);

  clearway::ui::MainWindow window;
  window.show();
  if (!parser.positionalArguments().isEmpty())
    window.openScan(parser.positionalArguments().first());
  return QApplication::exec();
}
